// SPDX-License-Identifier: Apache-2.0
// Mapping validation: every rejection names node, PDO, object and cause.
#include "pdo_rig.hpp"

#include <codrive/pdo/validate.hpp>

#include <gtest/gtest.h>

using namespace codrive;
using namespace codrive::pdo;
using namespace codrive::pdo::test;

namespace {

struct Model {
    explicit Model(PdoQuirks q = quirks::standard()) {
        fill_drive_od(od, 3, q);
        dm.od = &od;
        dm.quirks = q;
    }
    std::string why(const PdoConfig& p) const {
        auto r = validate(3, p, dm);
        return r ? std::string("ok") : r.error().message;
    }
    ObjectDictionary od;
    DeviceModel dm;
};

} // namespace

TEST(PdoValidate, AcceptsAStandardCsPMapping) {
    Model m;
    EXPECT_EQ(m.why(rpdo(1, {entry(0x6040, 0, 16), entry(0x607A, 0, 32)}, 1)), "ok");
    EXPECT_EQ(m.why(tpdo(1, {entry(0x6041, 0, 16), entry(0x6064, 0, 32)}, 1)), "ok");
}

TEST(PdoValidate, RejectsRpdoOnlyObjectInTpdo) {
    Model m;
    EXPECT_EQ(m.why(tpdo(1, {entry(0x607A, 0, 32)})),
              "node 3: TPDO1 maps 0x607A:00 (INTEGER32) but it is only RPDO-mappable");
}

TEST(PdoValidate, RejectsTpdoOnlyObjectInRpdo) {
    Model m;
    EXPECT_EQ(m.why(rpdo(2, {entry(0x6041, 0, 16)})),
              "node 3: RPDO2 maps 0x6041:00 (UNSIGNED16) but it is only TPDO-mappable");
}

TEST(PdoValidate, RejectsUnmappableAndMissingObjects) {
    Model m;
    EXPECT_EQ(m.why(tpdo(1, {entry(0x6062, 0, 32)})),
              "node 3: TPDO1 maps 0x6062:00 (INTEGER32) but it is not PDO-mappable");
    EXPECT_EQ(m.why(tpdo(1, {entry(0x6099, 0, 32)})),
              "node 3: TPDO1 maps 0x6099:00, which does not exist in the object dictionary");
    EXPECT_EQ(m.why(tpdo(1, {entry(0x6041, 1, 16)})),
              "node 3: TPDO1 maps 0x6041:01, but 0x6041 has no sub-index 01h");
}

TEST(PdoValidate, RejectsWrongLength) {
    Model m;
    EXPECT_EQ(m.why(tpdo(1, {entry(0x6041, 0, 32)})),
              "node 3: TPDO1 maps 0x6041:00 (UNSIGNED16) with 32 bits, but the object has 16");
}

TEST(PdoValidate, RejectsMoreThan64Bits) {
    Model m;
    EXPECT_EQ(m.why(tpdo(1, {entry(0x6041, 0, 16), entry(0x6064, 0, 32), entry(0x606C, 0, 32)})),
              "node 3: TPDO1 maps 80 bits, more than the 64 bits of a CAN frame");
}

TEST(PdoValidate, RejectsMoreEntriesThanTheDeviceAllows) {
    Model m(quirks::akd2g());
    std::vector<MappingEntry> nine(9, entry(0x0000, 0, 0));
    for (auto& e : nine) {
        e = entry(0x2002, 0, 8);
    }
    const std::string why = m.why(rpdo(1, nine));
    EXPECT_EQ(why.rfind("node 3: RPDO1 maps 9 entries, more than the 8 AKD2G allows", 0), 0U)
        << why;
}

TEST(PdoValidate, DummyEntriesOnlyInRpdosWithTheirLength) {
    Model m;
    EXPECT_EQ(m.why(rpdo(1, {entry(0x6040, 0, 16), entry(0x0005, 0, 8), entry(0x607A, 0, 32)})),
              "ok");
    EXPECT_EQ(m.why(tpdo(1, {entry(0x0005, 0, 8)})),
              "node 3: TPDO1 maps 0x0005:00 (UNSIGNED8 dummy), but dummies are only for RPDOs");
    EXPECT_EQ(m.why(rpdo(1, {entry(0x0006, 0, 8)})),
              "node 3: RPDO1 maps 0x0006:00 with 8 bits, but a UNSIGNED16 dummy has 16");
}

TEST(PdoValidate, DummyUsageFromEdsIsHonoured) {
    Model m;
    DummyUsage usage;
    usage.entries[0x0005] = true;
    usage.entries[0x0007] = false;
    m.dm.dummy_usage = &usage;
    EXPECT_EQ(m.why(rpdo(1, {entry(0x0005, 0, 8)})), "ok");
    EXPECT_EQ(m.why(rpdo(1, {entry(0x0007, 0, 32)})),
              "node 3: RPDO1 maps 0x0007:00 (UNSIGNED32 dummy), but the device does not support "
              "that dummy ([DummyUsage])");
}

TEST(PdoValidate, Akd2gIsByteAlignedAndPadsWithIndexZero) {
    Model m(quirks::akd2g());
    EXPECT_EQ(m.why(rpdo(1, {entry(0x6040, 0, 16), entry(0x0000, 0, 8), entry(0x607A, 0, 32)})),
              "ok");
    EXPECT_EQ(m.why(rpdo(1, {entry(0x2002, 0, 1)})),
              "node 3: RPDO1 maps 0x2002:00 with 1 bits at bit 0, but AKD2G PDOs are byte "
              "aligned");
    Model s;
    EXPECT_EQ(s.why(rpdo(1, {entry(0x0000, 0, 8)})),
              "node 3: RPDO1 maps 0x0000:00, but index 0000h is not an object (use a dummy "
              "0002h..0007h for padding)");
}

TEST(PdoValidate, TransmissionTypesAreCheckedAgainstDirectionAndDevice) {
    Model m;
    EXPECT_EQ(m.why(tpdo(1, {entry(0x6041, 0, 16)}, 245)),
              "node 3: TPDO1 transmission type 245 is reserved (CiA 301 Table 72)");
    EXPECT_EQ(m.why(rpdo(1, {entry(0x6040, 0, 16)}, 252)),
              "node 3: RPDO1 transmission type 252 is for TPDOs only");
    EXPECT_EQ(m.why(tpdo(1, {entry(0x6041, 0, 16)}, 253)), "ok");
    Model bvs(quirks::ds_bvs());
    EXPECT_EQ(bvs.why(tpdo(1, {entry(0x6041, 0, 16)}, 253)),
              "node 3: TPDO1 transmission type 253 needs RTR, which DS-BVS does not support");
    Model akd(quirks::akd2g());
    EXPECT_EQ(akd.why(tpdo(1, {entry(0x6041, 0, 16)}, 254)),
              "node 3: TPDO1 transmission type 254 is not supported by AKD2G");
}

TEST(PdoValidate, CobIdsAreChecked) {
    Model m;
    PdoConfig p = tpdo(1, {entry(0x6041, 0, 16)});
    p.comm.can_id = 0x601;
    EXPECT_EQ(m.why(p), "node 3: TPDO1 COB-ID 0x601 is restricted by CiA 301 (Table 41)");
    p.comm.can_id = 0x800;
    EXPECT_EQ(m.why(p), "node 3: TPDO1 COB-ID 0x800 does not fit 11 bits");
    p.comm.can_id = 0x1234567;
    p.comm.extended = true;
    EXPECT_EQ(m.why(p), "ok");
    Model akd(quirks::akd2g());
    EXPECT_EQ(akd.why(p), "node 3: TPDO1 uses a 29-bit COB-ID, which AKD2G does not support");
    EXPECT_EQ(m.why(tpdo(5, {entry(0x6041, 0, 16)})),
              "node 3: TPDO5 does not exist (CiA 301 has 4 TPDOs)");
}

TEST(PdoValidate, AllChecksDuplicateCobIdsAndListsEveryProblem) {
    Model m;
    PdoConfig a = tpdo(1, {entry(0x6041, 0, 16)});
    PdoConfig b = tpdo(2, {entry(0x6064, 0, 32)});
    b.comm.can_id = 0x183;
    std::vector<PdoConfig> both{a, b};
    auto r = validate_all(3, both, m.dm);
    ASSERT_FALSE(r);
    EXPECT_EQ(r.error().message, "node 3: TPDO1 and TPDO2 both use COB-ID 0x183");
    std::vector<PdoConfig> bad{tpdo(1, {entry(0x607A, 0, 32)}), rpdo(1, {entry(0x6041, 0, 16)})};
    EXPECT_EQ(find_problems(3, bad, m.dm).size(), 2U);
}

TEST(PdoTypes, MappingEntryRoundTripsAndDescribes) {
    const auto e = MappingEntry::from_raw(0x607A0020);
    EXPECT_EQ(e.index, 0x607A);
    EXPECT_EQ(e.subindex, 0);
    EXPECT_EQ(e.bits, 32);
    EXPECT_EQ(e.raw(), 0x607A0020U);
    EXPECT_EQ(to_string(e), "0x607A:00/32");
    EXPECT_EQ(describe_transmission(3), "3 (every 3rd SYNC)");
    EXPECT_EQ(describe_transmission(11), "11 (every 11th SYNC)");
    EXPECT_EQ(describe_transmission(22), "22 (every 22nd SYNC)");
    EXPECT_EQ(tpdo(2, {}).cob_id_value(5, true), 0xC0000285U);
    EXPECT_EQ(rpdo(4, {}).cob_id_value(5, false), 0x00000505U);
    EXPECT_TRUE(is_restricted_can_id(0x180));
    EXPECT_FALSE(is_restricted_can_id(0x181));
}

TEST(PdoValidate, ModelFromEdsUsesItsPdoCountsGranularityAndDummies) {
    const std::string eds = R"([DeviceInfo]
Granularity=8
NrOfRXPDO=2
NrOfTXPDO=2

[DummyUsage]
Dummy0005=1
Dummy0006=0

[MandatoryObjects]
SupportedObjects=1
1=0x1000

[1000]
ParameterName=Device type
ObjectType=0x7
DataType=0x0007
AccessType=ro
DefaultValue=0x00020192
PDOMapping=0

[OptionalObjects]
SupportedObjects=0

[ManufacturerObjects]
SupportedObjects=1
1=0x2100

[2100]
ParameterName=Setpoint
ObjectType=0x7
DataType=0x0003
AccessType=rww
DefaultValue=0
PDOMapping=1
)";
    const DeviceDescription desc = parse_eds(eds, "test.eds");
    const DeviceModel m = device_model(desc);
    EXPECT_TRUE(m.quirks.byte_aligned);
    auto why = [&](const PdoConfig& p) {
        auto r = validate(3, p, m);
        return r ? std::string("ok") : r.error().message;
    };
    EXPECT_EQ(why(rpdo(1, {entry(0x2100, 0, 16), entry(0x0005, 0, 8)})), "ok");
    EXPECT_EQ(why(rpdo(1, {entry(0x0006, 0, 16)})),
              "node 3: RPDO1 maps 0x0006:00 (UNSIGNED16 dummy), but the device does not support "
              "that dummy ([DummyUsage])");
    EXPECT_EQ(why(tpdo(1, {entry(0x2100, 0, 16)})),
              "node 3: TPDO1 maps 0x2100:00 (INTEGER16) but it is only RPDO-mappable");
    EXPECT_EQ(why(rpdo(3, {entry(0x2100, 0, 16)})),
              "node 3: RPDO3 does not exist (CiA 301 has 2 RPDOs)");
}
