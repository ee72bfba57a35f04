// SPDX-License-Identifier: Apache-2.0
// Profiles: table row counts, spot checks against the spec text, identity matching, PDO layouts,
// the EMCY text hook and the device dictionary builder.
#include <codrive/drives/profile.hpp>
#include <codrive/emcy/message.hpp>

#include <gtest/gtest.h>

#include <algorithm>
#include <fstream>
#include <regex>
#include <sstream>

namespace codrive::drives {
namespace {

TEST(Profiles, Akd2gFaultTableHas185RowsWith123FaultsAnd62Warnings) {
    const Profile& p = akd2g_profile();
    ASSERT_EQ(p.faults.size(), 185U);
    const auto warnings = std::count_if(p.faults.begin(), p.faults.end(),
                                        [](const FaultRow& r) { return r.is_warning(); });
    EXPECT_EQ(warnings, 62);
    EXPECT_EQ(p.faults.size() - static_cast<std::size_t>(warnings), 123U);
}

TEST(Profiles, Akd2gSpotChecks) {
    const Profile& p = akd2g_profile();
    EXPECT_EQ(p.fault_text(0x3210), "F2006 Bus over voltage");
    EXPECT_EQ(p.fault_text(0x8611), "F6001 Following error magnitude fault");
    EXPECT_EQ(p.fault_text(0x8130), "F7002 Fieldbus Heartbeat lost");
    EXPECT_EQ(p.fault_text(0xFF0B), "F9000 Safe torque off");
    EXPECT_EQ(p.fault_text(0xFF0C), "W9000 Safe torque off");
    EXPECT_EQ(p.fault_text(0x3110), "F2015 Bus over voltage FPGA");
    EXPECT_EQ(p.fault_text(0xFF5A), "F9007 Safe brake parameters inconsistent");
    EXPECT_EQ(p.fault_text(0x86A4), "W6015 Homing Failed");
    EXPECT_EQ(p.fault_text(0x8785), "F7006 Only on CAN drives: CAN hardware initialization failed");
    EXPECT_EQ(p.fault_text(0x1234), "");
}

TEST(Profiles, Akd2gTableMatchesTheSpecTextRowByRow) {
    // CODRIVE_SHARED_DIR comes from CMake (cache variable of the same name).
    const std::string path = std::string(CODRIVE_SHARED_DIR) + "/specs/akd2g.md";
    std::ifstream in(path);
    ASSERT_TRUE(in) << path
                    << " cannot be read: configure with -DCODRIVE_SHARED_DIR=<dir with specs/>";
    const std::regex row(R"(^\| ([0-9A-F]{4}) \| ([FW]\d{4}) \| (.*) \|$)");
    std::string line;
    bool in_table = false;
    std::size_t rows = 0;
    while (std::getline(in, line)) {
        if (line.starts_with("## 6. EMCY error codes")) {
            in_table = true;
        } else if (line.starts_with("Decoder notes")) {
            break;
        }
        std::smatch m;
        if (in_table && std::regex_match(line, m, row)) {
            const auto code = static_cast<std::uint16_t>(std::stoul(m[1].str(), nullptr, 16));
            const FaultRow* f = akd2g_profile().fault(code);
            ASSERT_NE(f, nullptr) << m[1];
            EXPECT_EQ(f->number, m[2].str());
            EXPECT_EQ(f->text, m[3].str());
            ++rows;
        }
    }
    EXPECT_EQ(rows, 185U);
}

TEST(Profiles, DsBvsErrorTableHas14Rows) {
    const Profile& p = ds_bvs_profile();
    ASSERT_EQ(p.faults.size(), 14U);
    EXPECT_EQ(p.fault_text(0x8611), "Following error");
    EXPECT_EQ(p.fault_text(0xFF02), "Over load error (I2T)");
    EXPECT_EQ(p.fault(0xFF01)->error_register, 0x80);
    EXPECT_EQ(p.fault(0x3220)->error_register, 0x04);
    EXPECT_EQ(p.fault(0x6100)->error_register, 0x20);
}

TEST(Profiles, FioTablesHave18CodesAnd30ErrorNumbers) {
    const Profile& p = fio_profile();
    ASSERT_EQ(p.faults.size(), 18U);
    ASSERT_EQ(p.error_numbers.size(), 30U);
    EXPECT_EQ(p.fault_text(0x5540), "interlock error (60FDh bit 3 = 0)");
    EXPECT_EQ(p.error_number(0x2E)->text, "interlock error: 60FDh bit 3 = 0");
    EXPECT_EQ(p.error_number(0x1D)->typical_code, 0x8400);
    EXPECT_EQ(p.error_number(0x0D)->typical_code, 0x8611);
    EXPECT_EQ(p.error_number(0x1E), nullptr);
}

TEST(Profiles, IdentityMatch) {
    EXPECT_EQ(match_identity(0x00020192, 0x6A, 0x11210100), &akd2g_profile());
    EXPECT_EQ(match_identity(0x000A0192, 0x6A, 0x11110100), &akd2g_profile()); // CoE + FSoE
    EXPECT_EQ(match_identity(0x00060192, 0x0048554B, 0x0002BA67), &fio_profile());
    EXPECT_EQ(match_identity(0x00020192, 0x1234, 0x1, "DS-BVS 10A"), &ds_bvs_profile());
    EXPECT_EQ(match_identity(0x00020192, 0x1234, 0x1), &generic_profile());
    EXPECT_EQ(match_identity(0x00000191, 0x6A, 0x11210100), nullptr); // CiA 401 I/O
    EXPECT_EQ(akd2g_profile().axes_from_product_code(0x11210100), 2U);
    EXPECT_EQ(akd2g_profile().axes_from_product_code(0x11110100), 1U);
    EXPECT_EQ(&profile_by_name("AKD2G"), &akd2g_profile());
    EXPECT_EQ(&profile_by_name("ds-bvs"), &ds_bvs_profile());
    EXPECT_EQ(&profile_by_name("kuhnke-fio"), &fio_profile());
    EXPECT_EQ(&profile_by_name("unknown"), &generic_profile());
}

TEST(Profiles, AxisOffsets) {
    const Profile& p = akd2g_profile();
    EXPECT_EQ(p.axis_index(0x6040, 2), 0x6840);
    EXPECT_EQ(p.axis_index(0x6502, 2), 0x6D02);
    EXPECT_EQ(p.axis_index(0x5004, 2), 0x5104);
    EXPECT_EQ(p.axis_index(0x1018, 2), 0x1018);
    EXPECT_EQ(p.axis_index(0x6040, 1), 0x6040);
    const PdoEntry e{0x607A, 0, 32};
    EXPECT_EQ(mapping_value(p, e, 2), 0x687A0020U);
}

TEST(Profiles, SupportedModes) {
    using cia402::Mode;
    const Profile& akd = akd2g_profile();
    EXPECT_TRUE(akd.supports_mode(8));
    EXPECT_TRUE(akd.supports_mode(9)); // accepted although 6502h = 0xAD
    EXPECT_FALSE(akd.supports_mode(10));
    EXPECT_FALSE(akd.supports_mode(7));
    EXPECT_TRUE(akd.supports_mode(-1));
    const Profile& ds = ds_bvs_profile();
    EXPECT_FALSE(ds.supports_mode(4)); // 6502h bit 3 set, but 6060h has no PT
    EXPECT_TRUE(ds.supports_mode(10));
    EXPECT_TRUE(ds.supports_mode(-128));
    EXPECT_FALSE(ds.supports_mode(-5));
    EXPECT_FALSE(fio_profile().supports_mode(7));
    EXPECT_TRUE(fio_profile().supports_mode(-2));
}

TEST(Profiles, EveryCanLayoutFitsEightBytesAndItsObjectsAreMappable) {
    for (const Profile* p : all_profiles()) {
        ObjectDictionary od;
        build_device_dictionary(od, *p, p->max_axes);
        for (const ModeLayout& l : p->layouts) {
            for (const auto& [entries, dir] :
                 {std::pair{l.rx, PdoDir::Rpdo}, std::pair{l.tx, PdoDir::Tpdo}}) {
                unsigned bits = 0;
                for (const PdoEntry& e : entries) {
                    bits += e.bits;
                    for (unsigned axis = 1; axis <= p->max_axes; ++axis) {
                        const SubObject* s = od.find(p->axis_index(e.index, axis), e.subindex);
                        ASSERT_NE(s, nullptr) << p->name << " " << std::hex << e.index;
                        EXPECT_TRUE(s->pdo_mappable) << p->name << " " << std::hex << e.index;
                        EXPECT_EQ(s->bit_length(), e.bits) << p->name << " " << std::hex << e.index;
                    }
                }
                EXPECT_LE(bits, 64U) << p->name << " mode " << int(l.mode);
                EXPECT_LE(entries.size(), p->quirks.max_pdo_entries);
            }
            EXPECT_TRUE(p->supports_mode(static_cast<std::int8_t>(l.mode)))
                << p->name << " mode " << int(l.mode);
        }
    }
}

TEST(Profiles, DeviceDictionaryCarriesProfileData) {
    ObjectDictionary od;
    build_device_dictionary(od, akd2g_profile(), 2);
    EXPECT_EQ(od.get<std::uint32_t>(0x1000, 0), 0x00020192U);
    EXPECT_EQ(od.get<std::uint32_t>(0x1018, 1), 0x6AU);
    EXPECT_EQ(od.get<std::uint32_t>(0x1018, 2), 0x11210100U);
    EXPECT_EQ(od.get<std::uint32_t>(0x6D02, 0), 0xADU);
    EXPECT_EQ(od.get<std::uint32_t>(0x6892, 1), 65536U);
    EXPECT_NE(od.find(0x6840), nullptr);
    EXPECT_EQ(od.find(0x605B), nullptr); // no shutdown option code on the AKD2G
    EXPECT_EQ(od.find(0x6041, 0)->access, Access::Ro);
    // 605Ah accepts 1..6 only.
    const std::uint8_t bad[2] = {7, 0};
    EXPECT_FALSE(od.check_write(0x605A, 0, bad).has_value());

    ObjectDictionary ds;
    build_device_dictionary(ds, ds_bvs_profile(), 1);
    EXPECT_EQ(ds.get<std::int8_t>(0x6060, 0), 3);
    EXPECT_EQ(ds.get<std::uint32_t>(0x6502, 0), 0x3AFU);
    EXPECT_EQ(ds.get<std::uint8_t>(0x6099, 0), 2);
    EXPECT_EQ(ds.find(0x6092), nullptr);
    EXPECT_FALSE(ds.find(0x6062, 0)->pdo_mappable);

    ObjectDictionary fio;
    build_device_dictionary(fio, fio_profile(), 1);
    EXPECT_EQ(fio.get<std::uint32_t>(0x60A8, 0), 0xFF410000U);
    EXPECT_EQ(fio.get<std::uint32_t>(0x60A9, 0), 0x00B44700U);
    EXPECT_EQ(fio.get<std::int8_t>(0x6098, 0), 35);
}

// A bus file names the error control objects in `writes:` (e.g. 1016h:01 so the drive
// supervises the master's heartbeat): the master-side dictionaries of the CAN drives hold them.
TEST(Profiles, CanDrivesListTheirErrorControlObjects) {
    ObjectDictionary ak;
    build_device_dictionary(ak, akd2g_profile(), 2);
    ASSERT_NE(ak.find(0x1016, 1), nullptr);
    EXPECT_EQ(ak.find(0x1016, 1)->type, DataType::Unsigned32);
    EXPECT_EQ(ak.find(0x1016, 1)->access, Access::Rw);
    EXPECT_EQ(ak.find(0x1016, 2), nullptr) << "one consumer entry (akd2g.md 1016h)";
    EXPECT_EQ(ak.find(0x1017, 0)->type, DataType::Unsigned16);
    EXPECT_EQ(ak.find(0x1029), nullptr) << "AKD2G has no 1029h (akd2g.md AMB-6)";

    ObjectDictionary ds;
    build_device_dictionary(ds, ds_bvs_profile(), 1);
    ASSERT_NE(ds.find(0x1029, 1), nullptr);
    EXPECT_EQ(ds.get<std::uint8_t>(0x1029, 1), 1) << "default: no state change (ds-bvs.md)";
    const std::uint8_t three = 3;
    EXPECT_FALSE(ds.check_write(0x1029, 1, {&three, 1}).has_value()) << "0..2 only";
    const std::uint8_t zero = 0;
    EXPECT_TRUE(ds.check_write(0x1029, 1, {&zero, 1}).has_value());

    ObjectDictionary fio;
    build_device_dictionary(fio, fio_profile(), 1);
    EXPECT_EQ(fio.find(0x1016), nullptr) << "EtherCAT only";
}

TEST(Profiles, QuirksFromTheSpecs) {
    EXPECT_TRUE(ds_bvs_profile().quirks.pdo_cob_ids_read_only);
    EXPECT_TRUE(ds_bvs_profile().quirks.empty_default_pdo_maps);
    EXPECT_TRUE(akd2g_profile().quirks.pdo_maps_volatile);
    EXPECT_FALSE(akd2g_profile().quirks.pdo_mapping_preop_only) << "§5.2.31 dynamic mapping";
    EXPECT_TRUE(ds_bvs_profile().quirks.pdo_maps_volatile) << "maps are Backup NO";
    EXPECT_FALSE(fio_profile().quirks.canopen);
    EXPECT_EQ(akd2g_profile().axis_offset, 0x800);
    EXPECT_EQ(ds_bvs_profile().default_quick_stop_option, 6);
}

TEST(Profiles, EmcyTextHookAddsVendorText) {
    auto akd = emcy_text_provider(akd2g_profile());
    emcy::EmcyMessage m;
    m.node = 3;
    m.error_code = 0x3210;
    m.error_register = 0x01;
    EXPECT_EQ(akd->vendor_text(m), "F2006 Bus over voltage");
    EXPECT_NE(emcy::describe(m, akd.get()).find("F2006 Bus over voltage"), std::string::npos);
    m.error_code = 0;
    EXPECT_EQ(akd->vendor_text(m), std::nullopt);

    auto fio = emcy_text_provider(fio_profile());
    emcy::EmcyMessage f;
    f.node = 1;
    f.error_code = 0x8611;
    f.manufacturer = {0x0D, 0x20, 0, 0, 0};
    EXPECT_EQ(fio->vendor_text(f),
              "error number 0x0D: following error (6065h/6066h) exceeded; position monitoring: "
              "following error too large");

    auto ds = emcy_text_provider(ds_bvs_profile());
    emcy::EmcyMessage d;
    d.error_code = 0xFF01;
    EXPECT_EQ(ds->vendor_text(d), "Hall sensor error");
}

} // namespace
} // namespace codrive::drives
