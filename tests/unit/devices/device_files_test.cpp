// SPDX-License-Identifier: Apache-2.0
// devices/*.eds and devices/*.xml: generated from the profiles, never drifting from them, and
// readable by codrive's EDS parser and linter (EDS) and by pugixml (ESI).
#include <codrive/core/eds.hpp>
#include <codrive/devices/device_files.hpp>

#include <gtest/gtest.h>
#include <pugixml.hpp>

#include <fstream>
#include <map>
#include <sstream>
#include <string>

using namespace codrive;

namespace {

std::string device_path(std::string_view stem, std::string_view ext) {
    return std::string(CODRIVE_SOURCE_DIR) + "/devices/" + std::string(stem) + std::string(ext);
}

std::string read_text(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    std::stringstream s;
    s << in.rdbuf();
    return s.str();
}

const drives::Profile& profile_of(const devices::DeviceFile& f) {
    const drives::Profile* p = drives::find_profile(f.profile);
    EXPECT_NE(p, nullptr) << f.profile;
    return p != nullptr ? *p : drives::generic_profile();
}

// The master's dictionary of the profile plus the objects the stack builds around it: what a
// file must hold. The EDS carries the CANopen stack's objects on a drive with a CAN interface,
// else (and the ESI always) the CoE stack's.
ObjectDictionary file_dictionary(const devices::DeviceFile& f, bool esi) {
    const drives::Profile& p = profile_of(f);
    ObjectDictionary od;
    drives::build_device_dictionary(od, p, f.axes);
    const auto stack = !esi && p.quirks.canopen ? devices::Stack::CanOpen : devices::Stack::Coe;
    const ObjectDictionary extra = devices::stack_objects(p, f.axes, stack);
    for (const auto& [index, obj] : extra.objects()) {
        EXPECT_EQ(od.find(index), nullptr)
            << f.stem << ": the stack and the profile both make " << std::hex << index;
        od.insert(obj);
    }
    return od;
}

// "line N: committed `...`, profile gives `...`" for the first line that differs.
std::string first_difference(const std::string& committed, const std::string& generated) {
    std::istringstream a(committed);
    std::istringstream b(generated);
    std::string la;
    std::string lb;
    for (std::size_t line = 1;; ++line) {
        const bool more_a = static_cast<bool>(std::getline(a, la));
        const bool more_b = static_cast<bool>(std::getline(b, lb));
        if (!more_a && !more_b) {
            return "no difference";
        }
        if (!more_a || !more_b || la != lb) {
            return "line " + std::to_string(line) + ": committed `" + (more_a ? la : "<end>") +
                   "`, the profile gives `" + (more_b ? lb : "<end>") + "`";
        }
    }
}

constexpr const char* kRegenerate =
    "devices/ is out of date with the profiles: run `devices/regenerate.sh` (after building "
    "`codrive`) and commit the result";

} // namespace

TEST(DeviceFiles, EveryVendorProfileHasItsFiles) {
    ASSERT_EQ(devices::device_files().size(), 3U);
    for (const auto& f : devices::device_files()) {
        EXPECT_EQ(devices::device_file(f.profile), &f);
        EXPECT_EQ(f.axes, profile_of(f).max_axes) << f.stem;
    }
    EXPECT_EQ(devices::device_file("generic"), nullptr);
}

TEST(DeviceFiles, CommittedEdsFilesAreWhatTheProfilesExport) {
    for (const auto& f : devices::device_files()) {
        const std::string path = device_path(f.stem, ".eds");
        const std::string committed = read_text(path);
        ASSERT_FALSE(committed.empty()) << path << " is missing; " << kRegenerate;
        const std::string generated = devices::export_eds(profile_of(f), f.axes, f.vendor_name);
        EXPECT_TRUE(committed == generated)
            << path << ": " << first_difference(committed, generated) << "; " << kRegenerate;
    }
}

TEST(DeviceFiles, CommittedEsiFilesAreWhatTheProfilesExport) {
    for (const auto& f : devices::device_files()) {
        const std::string path = device_path(f.stem, ".xml");
        const std::string committed = read_text(path);
        ASSERT_FALSE(committed.empty()) << path << " is missing; " << kRegenerate;
        const std::string generated = devices::export_esi(profile_of(f), f.axes, f.vendor_name);
        EXPECT_TRUE(committed == generated)
            << path << ": " << first_difference(committed, generated) << "; " << kRegenerate;
    }
}

TEST(DeviceFiles, EdsParsesWithoutErrorsAndHoldsTheMasterDictionary) {
    for (const auto& f : devices::device_files()) {
        const std::string path = device_path(f.stem, ".eds");
        auto desc = load_eds(path);
        ASSERT_TRUE(desc) << path;
        for (const auto& finding : desc->findings) {
            EXPECT_NE(finding.severity, EdsSeverity::Error) << format_finding(finding);
        }
        const ObjectDictionary od = file_dictionary(f, false);
        ASSERT_EQ(desc->od.size(), od.size()) << path;
        for (const auto& [index, obj] : od.objects()) {
            const Object* got = desc->od.find(index);
            ASSERT_NE(got, nullptr) << path << " lacks " << std::hex << index;
            ASSERT_EQ(got->subs.size(), obj.subs.size()) << path << " " << std::hex << index;
            for (const auto& [si, sub] : obj.subs) {
                const SubObject* s = desc->od.find(index, si);
                ASSERT_NE(s, nullptr);
                EXPECT_EQ(s->name, sub.name);
                EXPECT_EQ(s->type, sub.type) << std::hex << index << ":" << unsigned(si);
                EXPECT_EQ(s->access, sub.access) << std::hex << index << ":" << unsigned(si);
                EXPECT_EQ(s->pdo_mappable, sub.pdo_mappable);
                EXPECT_EQ(s->value, sub.value) << std::hex << index << ":" << unsigned(si);
                EXPECT_EQ(s->low_limit.has_value(), sub.low_limit.has_value());
            }
        }
        const drives::Profile& p = profile_of(f);
        EXPECT_EQ(desc->device_info.vendor_number, p.identity.vendor_id);
        EXPECT_EQ(desc->device_info.product_name, p.title);
        EXPECT_EQ(desc->od.get<std::uint32_t>(0x1000, 0), p.identity.device_type);
        EXPECT_EQ(p.axes_from_product_code(desc->device_info.product_number), f.axes);
    }
}

TEST(DeviceFiles, EdsOfTheDsBvsListsTheBitRatesOfItsBitRateObject) {
    auto desc = load_eds(device_path("ds-bvs", ".eds"));
    ASSERT_TRUE(desc);
    // §6.2.76 5002h: 20, 50, 125, 250, 500 and 1000 kbit/s; 10 and 800 "not supported".
    EXPECT_EQ(desc->device_info.baud_rates, (std::vector<unsigned>{20, 50, 125, 250, 500, 1000}));
    EXPECT_EQ(desc->device_info.granularity, 8);
    auto fio = load_eds(device_path("fio", ".eds"));
    ASSERT_TRUE(fio);
    EXPECT_EQ(fio->device_info.granularity, 0) << "the FIO has no CAN interface to map PDOs on";
}

TEST(DeviceFiles, EsiLoadsWithPugixmlWithTheProfileIdentityAndEveryObject) {
    for (const auto& f : devices::device_files()) {
        const std::string path = device_path(f.stem, ".xml");
        pugi::xml_document doc;
        const pugi::xml_parse_result r = doc.load_file(path.c_str());
        ASSERT_TRUE(r) << path << ": " << r.description();
        const drives::Profile& p = profile_of(f);
        const ObjectDictionary od = file_dictionary(f, true);
        const pugi::xml_node info = doc.child("EtherCATInfo");
        char want[16];
        std::snprintf(want, sizeof want, "#x%08X", p.identity.vendor_id);
        EXPECT_STREQ(info.child("Vendor").child_value("Id"), want) << path;
        const pugi::xml_node device = info.child("Descriptions").child("Devices").child("Device");
        ASSERT_TRUE(device) << path;
        std::snprintf(want, sizeof want, "#x%08X", *od.get<std::uint32_t>(0x1018, 2));
        EXPECT_STREQ(device.child("Type").attribute("ProductCode").value(), want) << path;
        EXPECT_EQ(device.child_value("Name"), std::string(p.title));
        EXPECT_TRUE(device.child("Mailbox").child("CoE")) << path;
        EXPECT_TRUE(device.child("RxPdo")) << path;
        EXPECT_TRUE(device.child("TxPdo")) << path;
        const pugi::xml_node objects = device.child("Profile").child("Dictionary").child("Objects");
        std::size_t count = 0;
        for (const pugi::xml_node o : objects.children("Object")) {
            const auto index =
                static_cast<std::uint16_t>(std::stoul(o.child_value("Index") + 2, nullptr, 16));
            const Object* obj = od.find(index);
            ASSERT_NE(obj, nullptr) << path << ": object " << o.child_value("Index");
            EXPECT_EQ(obj->name, o.child_value("Name"));
            ++count;
        }
        EXPECT_EQ(count, od.size()) << path;
        // Every object's Type is declared in DataTypes with the object's BitSize (ETG.2000
        // §5.4.3: the dictionary is self-contained).
        std::map<std::string, std::string> type_bits;
        const pugi::xml_node types = device.child("Profile").child("Dictionary").child("DataTypes");
        for (const pugi::xml_node t : types.children("DataType")) {
            type_bits[t.child_value("Name")] = t.child_value("BitSize");
        }
        for (const pugi::xml_node o : objects.children("Object")) {
            const auto it = type_bits.find(o.child_value("Type"));
            ASSERT_NE(it, type_bits.end()) << path << " " << o.child_value("Index") << " type "
                                           << o.child_value("Type") << " is not declared";
            EXPECT_EQ(it->second, o.child_value("BitSize"))
                << path << " " << o.child_value("Index");
        }
        // Every mapped PDO entry is an object of the dictionary that may be mapped.
        for (const char* kind : {"RxPdo", "TxPdo"}) {
            for (const pugi::xml_node pdo : device.children(kind)) {
                for (const pugi::xml_node e : pdo.children("Entry")) {
                    const auto index = static_cast<std::uint16_t>(
                        std::stoul(e.child_value("Index") + 2, nullptr, 16));
                    const auto sub =
                        static_cast<std::uint8_t>(std::stoul(e.child_value("SubIndex")));
                    const SubObject* s = od.find(index, sub);
                    // FIO manual §7.13.18: the default 1A03h maps 6402h:01/02, an object the
                    // manual never describes; the map is kept as the manual gives it.
                    if (f.stem == "fio" && index == 0x6402) {
                        EXPECT_EQ(s, nullptr) << "6402h is described now: drop this exception";
                        EXPECT_FALSE(e.child("DataType"));
                        continue;
                    }
                    // DS-BVS manual §6.2.20: the fixed map 1609h names 4700h:01..08 (Target
                    // Motion Info, §6.2.70); the profile describes only 4700h:02 so far.
                    if (f.stem == "ds-bvs" && index == 0x4700 && sub != 2) {
                        EXPECT_EQ(s, nullptr) << "4700h:" << unsigned(sub)
                                              << " is described now: drop this exception";
                        EXPECT_FALSE(e.child("DataType"));
                        continue;
                    }
                    ASSERT_NE(s, nullptr) << path << " " << kind << " " << e.child_value("Index");
                    EXPECT_TRUE(s->pdo_mappable) << path << " " << e.child_value("Index");
                }
            }
        }
    }
}

TEST(DeviceFiles, FilesHoldTheCommunicationObjectsTheStacksBuild) {
    // DS-BVS EDS: the CAN node's objects at node-ID 1 (§6.2.8 1014h = 81h; §6.2.13 RPDO1 COB-ID
    // 201h, RECORD with sub 0..2 at least; §6.2.14.1 1600h empty by default), 4080h and 60E3h.
    auto eds = load_eds(device_path("ds-bvs", ".eds"));
    ASSERT_TRUE(eds);
    EXPECT_EQ(eds->od.get<std::uint32_t>(0x1014, 0), 0x81U);
    const Object* rpdo1 = eds->od.find(0x1400);
    ASSERT_NE(rpdo1, nullptr) << "ds-bvs.eds has no 1400h";
    EXPECT_EQ(rpdo1->code, ObjectCode::Record);
    EXPECT_EQ(eds->od.get<std::uint32_t>(0x1400, 1), 0x201U);
    EXPECT_EQ(eds->od.get<std::uint8_t>(0x1600, 0), 0U);
    EXPECT_EQ(eds->device_info.nr_of_rx_pdo, 4U);
    EXPECT_EQ(eds->device_info.nr_of_tx_pdo, 4U);
    EXPECT_NE(eds->od.find(0x4080), nullptr);
    // §6.2.140: homing methods 17, 18, 23, 27, 37, -3, -4 in this order.
    EXPECT_EQ(eds->od.get<std::int8_t>(0x60E3, 1), 17);
    EXPECT_EQ(eds->od.get<std::int8_t>(0x60E3, 7), -4);

    // FIO ESI: the CoE slave's sync-manager objects, and RxPdo/TxPdo stating the same default
    // maps and assignment as the Dictionary (§7.13.11-§7.13.22: 1C12h:01 = 1600h).
    pugi::xml_document doc;
    ASSERT_TRUE(doc.load_file(device_path("fio", ".xml").c_str()));
    const pugi::xml_node device =
        doc.child("EtherCATInfo").child("Descriptions").child("Devices").child("Device");
    std::map<std::string, pugi::xml_node> objects;
    for (const pugi::xml_node o :
         device.child("Profile").child("Dictionary").child("Objects").children("Object")) {
        objects[o.child_value("Index")] = o;
    }
    for (const char* index : {"#x1001", "#x1003", "#x1010", "#x1C00", "#x1C12", "#x1C13", "#x1C32",
                              "#x1C33", "#x1600", "#x1A03"}) {
        EXPECT_EQ(objects.count(index), 1U) << "fio.xml lacks " << index;
    }
    const pugi::xml_node rx1 = device.find_child_by_attribute("RxPdo", "Sm", "2");
    ASSERT_TRUE(rx1) << "fio.xml assigns no RxPdo to SM2";
    EXPECT_STREQ(rx1.child_value("Index"), "#x1600");
    const auto subs = objects["#x1600"].child("Info").children("SubItem");
    std::vector<std::string> dictionary;
    for (const pugi::xml_node s : subs) {
        dictionary.emplace_back(s.child("Info").child_value("DefaultData"));
    }
    ASSERT_GE(dictionary.size(), 2U);
    std::size_t entries = 0;
    for (const pugi::xml_node e : rx1.children("Entry")) {
        ++entries;
        const auto index = std::stoul(e.child_value("Index") + 2, nullptr, 16);
        const auto sub = std::stoul(e.child_value("SubIndex"));
        const auto bits = std::stoul(e.child_value("BitLen"));
        char want[64];
        // DefaultData is the little-endian image of index << 16 | sub << 8 | bits.
        std::snprintf(want, sizeof want, "%02lX%02lX%02lX%02lX", bits, sub, index & 0xFF,
                      index >> 8);
        ASSERT_LT(entries, dictionary.size());
        EXPECT_EQ(dictionary[entries], want) << "1600h entry " << entries;
    }
    char count[24]; // room for any size_t, so -O3 sees no truncation
    std::snprintf(count, sizeof count, "%02zX", entries);
    EXPECT_EQ(dictionary[0], count) << "1600h:00 states the RxPdo's entry count";
}
