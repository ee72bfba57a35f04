// SPDX-License-Identifier: Apache-2.0
// The hand-written full.eds and device.dcf fixtures: every section and object feature.
#include "eds_test_support.hpp"

#include <gtest/gtest.h>

namespace codrive {
namespace {

using eds_test::dump;
using eds_test::load;

TEST(EdsFixture, FullEdsHasNoFindings) {
    DeviceDescription d = load("full.eds", 3);
    EXPECT_TRUE(d.findings.empty()) << dump(d);
    EXPECT_EQ(d.od.size(), 15U);
}

TEST(EdsFixture, FileInfoIsKeptAsWritten) {
    DeviceDescription d = load("full.eds");
    EXPECT_EQ(d.file_info.file_name, "full.eds");
    EXPECT_EQ(d.file_info.file_version, "3");
    EXPECT_EQ(d.file_info.file_revision, "7");
    EXPECT_EQ(d.file_info.eds_version, "4.0");
    EXPECT_EQ(d.file_info.description, "codrive test device");
    EXPECT_EQ(d.file_info.creation_time, "09:15AM");
    EXPECT_EQ(d.file_info.modification_date, "11-21-2026");
    EXPECT_EQ(d.file_info.modified_by, "codrive tests");
    EXPECT_EQ(d.comments, (std::vector<std::string>{"first comment line", "second comment line"}));
}

TEST(EdsFixture, DeviceInfoReadsBaudRatesGranularityPdoCountsAndLss) {
    DeviceDescription d = load("full.eds");
    const DeviceInfo& di = d.device_info;
    EXPECT_EQ(di.vendor_name, "codrive");
    EXPECT_EQ(di.vendor_number, 0xABU);
    EXPECT_EQ(di.product_name, "Test Drive");
    EXPECT_EQ(di.product_number, 0x1234U);
    EXPECT_EQ(di.revision_number, 0x00010002U);
    EXPECT_EQ(di.order_code, "TD-1");
    EXPECT_EQ(di.baud_rates, (std::vector<unsigned>{125, 250, 500, 1000}));
    EXPECT_FALSE(di.simple_boot_up_master);
    EXPECT_TRUE(di.simple_boot_up_slave);
    EXPECT_EQ(di.granularity, 8);
    EXPECT_EQ(di.nr_of_rx_pdo, 2);
    EXPECT_EQ(di.nr_of_tx_pdo, 3);
    EXPECT_TRUE(di.lss_supported);
}

TEST(EdsFixture, DummyUsageListsMappableDummies) {
    DeviceDescription d = load("full.eds");
    EXPECT_EQ(d.dummy_usage.entries.size(), 4U);
    EXPECT_FALSE(d.dummy_usage.supported(DataType::Boolean));
    EXPECT_TRUE(d.dummy_usage.supported(DataType::Integer8));
    EXPECT_TRUE(d.dummy_usage.supported(DataType::Unsigned8));
    EXPECT_TRUE(d.dummy_usage.supported(DataType::Unsigned32));
    EXPECT_FALSE(d.dummy_usage.supported(DataType::Integer16));
}

TEST(EdsFixture, VarObjectsCarryTypeAccessMappingDefaultAndLimits) {
    DeviceDescription d = load("full.eds");
    const Object* o = d.od.find(0x2004);
    ASSERT_NE(o, nullptr);
    EXPECT_EQ(o->code, ObjectCode::Var);
    EXPECT_EQ(o->name, "Temperature offset");
    const SubObject& s = o->subs.at(0);
    EXPECT_EQ(s.name, "Temperature offset");
    EXPECT_EQ(s.type, DataType::Integer16);
    EXPECT_EQ(s.access, Access::Rw);
    EXPECT_TRUE(s.pdo_mappable);
    EXPECT_EQ(s.default_value->as_int(), -25);
    EXPECT_EQ(s.value.as_int(), -25);
    EXPECT_EQ(s.low_limit->as_int(), -100);
    EXPECT_EQ(s.high_limit->as_int(), 100);
    EXPECT_EQ(s.default_text, "-25");
    // Limits are enforced by the dictionary like an SDO server would.
    const std::uint8_t too_big[] = {0xC8, 0x00}; // 200
    EXPECT_FALSE(d.od.check_write(0x2004, 0, too_big).has_value());

    const SubObject* gain = d.od.find(0x2000, 0);
    ASSERT_NE(gain, nullptr);
    EXPECT_EQ(gain->type, DataType::Real32);
    EXPECT_FLOAT_EQ(*d.od.get<float>(0x2000, 0), 1.5F);
    EXPECT_DOUBLE_EQ(*gain->low_limit->as_double(), -10.0);

    EXPECT_EQ(d.od.find(0x2001, 0)->value.to_string(), "AB-42 rev. C");
    EXPECT_EQ(d.od.find(0x2003, 0)->value.to_string(), "01 02 A0 FF");
}

TEST(EdsFixture, AccessTypesDecidePdoDirection) {
    DeviceDescription d = load("full.eds");
    const SubObject* cw = d.od.find(0x6040, 0);
    ASSERT_NE(cw, nullptr);
    EXPECT_EQ(cw->access, Access::Rww);
    EXPECT_TRUE(cw->mappable(PdoDir::Rpdo));
    EXPECT_FALSE(cw->mappable(PdoDir::Tpdo));
    EXPECT_TRUE(d.od.find(0x1001, 0)->mappable(PdoDir::Tpdo));
    EXPECT_FALSE(d.od.find(0x1000, 0)->pdo_mappable);
    EXPECT_EQ(d.od.find(0x1018, 0)->access, Access::Const);
}

TEST(EdsFixture, DeftypeAndDomainObjects) {
    DeviceDescription d = load("full.eds");
    const Object* t = d.od.find(0x0007);
    ASSERT_NE(t, nullptr);
    EXPECT_EQ(t->code, ObjectCode::Deftype);
    EXPECT_EQ(d.od.get<std::uint32_t>(0x0007, 0), 32U);
    const Object* blob = d.od.find(0x2002);
    ASSERT_NE(blob, nullptr);
    EXPECT_EQ(blob->code, ObjectCode::Domain);
    EXPECT_EQ(blob->subs.at(0).type, DataType::Domain); // DataType may be omitted for DOMAIN
    const Object* pdo_comm = d.od.find(0x0020);
    ASSERT_NE(pdo_comm, nullptr);
    EXPECT_EQ(pdo_comm->code, ObjectCode::Defstruct);
    EXPECT_EQ(pdo_comm->subs.size(), 3U);
    EXPECT_EQ(d.od.get<std::uint8_t>(0x0020, 1), 7);
    EXPECT_EQ(d.od.name_of(0x0020, 2), "PDO_COMMUNICATION_PARAMETER.Transmission type");
}

TEST(EdsFixture, RecordSubObjectsAndObjFlags) {
    DeviceDescription d = load("full.eds");
    const Object* id = d.od.find(0x1018);
    ASSERT_NE(id, nullptr);
    EXPECT_EQ(id->code, ObjectCode::Record);
    EXPECT_EQ(id->obj_flags, 1U);
    EXPECT_EQ(id->subs.size(), 5U);
    EXPECT_EQ(id->subs.at(4).obj_flags, 2U);
    EXPECT_EQ(d.od.get<std::uint32_t>(0x1018, 2), 0x1234U);
    EXPECT_EQ(d.od.name_of(0x1018, 1), "Identity object.Vendor-ID");
    EXPECT_EQ(d.od.name_of(0x1000, 0), "Device type");
}

TEST(EdsFixture, CompactSubObjGeneratesCountAndNamedSubObjects) {
    DeviceDescription d = load("full.eds");
    const Object* errors = d.od.find(0x1003);
    ASSERT_NE(errors, nullptr);
    EXPECT_EQ(errors->code, ObjectCode::Array);
    ASSERT_EQ(errors->subs.size(), 5U);
    const SubObject& s0 = errors->subs.at(0);
    EXPECT_EQ(s0.name, "NrOfObjects");
    EXPECT_EQ(s0.type, DataType::Unsigned8);
    EXPECT_EQ(s0.access, Access::Ro);
    EXPECT_EQ(s0.value.as_uint(), 4U);
    // [1003Name] names sub-objects 1 and 4; 2 and 3 get "<name><subindex>".
    EXPECT_EQ(errors->subs.at(1).name, "Newest error");
    EXPECT_EQ(errors->subs.at(2).name, "Pre-defined error field2");
    EXPECT_EQ(errors->subs.at(3).name, "Pre-defined error field3");
    EXPECT_EQ(errors->subs.at(4).name, "Oldest error");
    for (std::uint8_t i = 1; i <= 4; ++i) {
        EXPECT_EQ(errors->subs.at(i).type, DataType::Unsigned32);
        EXPECT_EQ(errors->subs.at(i).access, Access::Ro);
    }
}

TEST(EdsFixture, CompactValuesOverrideTheObjectDefaultAndMayUseNodeId) {
    DeviceDescription d = load("full.eds", 3);
    const Object* hb = d.od.find(0x1016);
    ASSERT_NE(hb, nullptr);
    ASSERT_EQ(hb->subs.size(), 4U);
    EXPECT_EQ(d.od.get<std::uint32_t>(0x1016, 1), 0x000501F4U);
    EXPECT_EQ(d.od.get<std::uint32_t>(0x1016, 2), 0U); // the object's DefaultValue
    EXPECT_EQ(d.od.get<std::uint32_t>(0x1016, 3), 0x00060003U);
    EXPECT_EQ(hb->subs.at(3).default_text, "$NODEID+0x00060000");
    // Limits of the object apply to every generated sub-object.
    EXPECT_EQ(hb->subs.at(2).high_limit->as_uint(), 0x007FFFFFU);
}

TEST(EdsFixture, NodeIdArithmeticInEitherOrder) {
    DeviceDescription d = load("full.eds", 0x7F);
    EXPECT_EQ(d.od.get<std::uint32_t>(0x1400, 1), 0x27FU);      // 0x200+$NODEID
    EXPECT_EQ(d.od.get<std::uint32_t>(0x1800, 1), 0x400001FFU); // $NODEID+0x40000180
    EXPECT_EQ(d.od.find(0x1400, 1)->default_text, "0x200+$NODEID");
    EXPECT_EQ(d.node_id, std::optional<NodeId>(0x7F));
}

TEST(EdsFixture, WithoutNodeIdExpressionsHoldTheirBase) {
    DeviceDescription d = load("full.eds");
    EXPECT_FALSE(d.node_id.has_value());
    EXPECT_EQ(d.od.get<std::uint32_t>(0x1400, 1), 0x200U);
    assign_node_id(d, 5);
    EXPECT_EQ(d.od.get<std::uint32_t>(0x1400, 1), 0x205U);
    EXPECT_EQ(d.od.find(0x1400, 1)->default_value->as_uint(), 0x205U);
    EXPECT_EQ(d.od.get<std::uint32_t>(0x1016, 3), 0x00060005U);
    EXPECT_EQ(d.node_id, std::optional<NodeId>(5));
}

TEST(EdsFixture, DcfCommissioningIsRead) {
    DeviceDescription d = load("device.dcf");
    EXPECT_TRUE(d.findings.empty()) << dump(d);
    const DeviceCommissioning& c = d.commissioning;
    EXPECT_EQ(c.node_id, std::optional<NodeId>(5));
    EXPECT_EQ(c.node_name, std::optional<std::string>("left wheel"));
    EXPECT_EQ(c.baudrate, std::optional<unsigned>(500));
    EXPECT_EQ(c.net_number, std::optional<std::uint32_t>(1));
    EXPECT_EQ(c.network_name, std::optional<std::string>("cart"));
    EXPECT_EQ(c.canopen_manager, std::optional<bool>(false));
    EXPECT_EQ(c.lss_serial_number, std::optional<std::uint32_t>(0x00C0FFEE));
}

TEST(EdsFixture, DcfParameterValueOverridesDefaultValue) {
    DeviceDescription d = load("device.dcf");
    const SubObject* hb = d.od.find(0x1017, 0);
    ASSERT_NE(hb, nullptr);
    EXPECT_EQ(hb->value.as_uint(), 100U);
    EXPECT_EQ(hb->default_value->as_uint(), 0U);
    EXPECT_EQ(hb->parameter_text, "100");
    // Both evaluate $NODEID with the DCF's NodeID (5).
    const SubObject* cob = d.od.find(0x1800, 1);
    ASSERT_NE(cob, nullptr);
    EXPECT_EQ(cob->default_value->as_uint(), 0x185U);
    EXPECT_EQ(cob->value.as_uint(), 0x80000185U);
    // assign_node_id re-evaluates both, and the ParameterValue still wins.
    assign_node_id(d, 6);
    EXPECT_EQ(cob->default_value->as_uint(), 0x186U);
    EXPECT_EQ(cob->value.as_uint(), 0x80000186U);
}

TEST(EdsFixture, MisspeltCommissioningSectionIsReadWithAWarning) {
    const std::string text = eds_test::eds_head({}) + "[DeviceCommissioning]\nNodeID=4\n";
    DeviceDescription d = parse_eds(text, "t.dcf");
    EXPECT_EQ(d.commissioning.node_id, std::optional<NodeId>(4));
    EXPECT_NE(eds_test::find(d, EdsSeverity::Warning, 8, "spelt [DeviceComissioning]"), nullptr)
        << dump(d);
}

} // namespace
} // namespace codrive
