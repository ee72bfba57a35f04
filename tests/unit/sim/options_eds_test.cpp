// SPDX-License-Identifier: Apache-2.0
// codrive-sim command-line specs and the EDS a simulated node writes about itself.
#include "device_test_support.hpp"

#include <codrive/core/eds.hpp>
#include <codrive/sim/options.hpp>

using namespace codrive;
using namespace codrive::sim;
using namespace codrive::sim::testing;

TEST(SimOptions, NodeSpecsNameIdProfileAndAxes) {
    NodeSpec s;
    std::string err;
    ASSERT_TRUE(parse_node_spec("1:akd2g", s, err)) << err;
    EXPECT_EQ(s.node, 1);
    EXPECT_EQ(s.profile->name(), "akd2g");
    EXPECT_EQ(s.axes, 0U);
    ASSERT_TRUE(parse_node_spec("12:akd2g:1", s, err)) << err;
    EXPECT_EQ(s.axes, 1U);
    ASSERT_TRUE(parse_node_spec("2:ds-bvs", s, err)) << err;
    EXPECT_FALSE(parse_node_spec("0:akd2g", s, err));
    EXPECT_NE(err.find("1..127"), std::string::npos);
    EXPECT_FALSE(parse_node_spec("3:foo", s, err));
    EXPECT_NE(err.find("unknown profile 'foo'"), std::string::npos);
    EXPECT_FALSE(parse_node_spec("3:ds-bvs:2", s, err));
    EXPECT_FALSE(parse_node_spec("akd2g", s, err));
}

TEST(SimOptions, FaultSpecsNameNodeAxisKindAndTime) {
    FaultSpec f;
    std::string err;
    ASSERT_TRUE(parse_fault_spec("1:sto@2s", f, err)) << err;
    EXPECT_EQ(f.node, 1);
    EXPECT_EQ(f.axis, 0U);
    EXPECT_EQ(f.kind, FaultKind::Sto);
    EXPECT_EQ(f.after, seconds(2));
    ASSERT_TRUE(parse_fault_spec("2.2:overcurrent@500ms", f, err)) << err;
    EXPECT_EQ(f.axis, 1U);
    EXPECT_EQ(f.kind, FaultKind::OverCurrent);
    EXPECT_EQ(f.after, milliseconds(500));
    ASSERT_TRUE(parse_fault_spec("3:reset", f, err)) << err;
    EXPECT_EQ(f.kind, FaultKind::NodeReset);
    EXPECT_EQ(f.after, Duration{0});
    ASSERT_TRUE(parse_fault_spec("3:heartbeat-loss@1.5s", f, err)) << err;
    EXPECT_EQ(f.after, milliseconds(1500));
    EXPECT_FALSE(parse_fault_spec("3:melt@1s", f, err));
    EXPECT_NE(err.find("unknown fault 'melt'"), std::string::npos);
    EXPECT_FALSE(parse_fault_spec("3.3:sto", f, err));
    EXPECT_FALSE(parse_fault_spec("3:sto@soon", f, err));
}

TEST(SimEds, DescriptionRoundTripsThroughTheEdsWriterAndParser) {
    DeviceFixture f("akd2g");
    const DeviceDescription d = f.device.describe();
    EXPECT_EQ(d.device_info.vendor_number, 0x6AU);
    EXPECT_EQ(d.device_info.nr_of_rx_pdo, 4);
    const std::string text = write_eds(d);
    const DeviceDescription back = parse_eds(text, "akd2g.eds");
    for (const auto& finding : back.findings) {
        EXPECT_NE(finding.severity, EdsSeverity::Error) << format_finding(finding);
    }
    ASSERT_NE(back.od.find(0x6840, 0), nullptr);
    EXPECT_EQ(back.od.find(0x6840, 0)->access, Access::Rww);
    EXPECT_TRUE(back.od.find(0x6041, 0)->pdo_mappable);
    EXPECT_EQ(back.od.get<std::uint32_t>(0x1018, 1), 0x6AU);
    EXPECT_EQ(back.od.get<std::uint32_t>(0x6502, 0), 0xADU);
    EXPECT_EQ(back.od.size(), f.device.od().size());
}

TEST(SimEds, DescriptionCarriesFactoryValuesNotLiveOnes) {
    DeviceFixture f("ds-bvs", 1);
    f.start();
    ASSERT_TRUE(f.write<std::int32_t>(0x607A, 0, 777));
    const DeviceDescription d = f.device.describe();
    EXPECT_EQ(d.od.get<std::int32_t>(0x607A, 0), 0);
    EXPECT_EQ(d.od.get<std::int8_t>(0x6060, 0), 3);
}

TEST(SimProfiles, EveryProfileBuildsADeviceWithItsAxes) {
    for (const SimProfile* p : all_profiles()) {
        const std::string name(p->name());
        DeviceFixture f(name.c_str(), 9);
        EXPECT_EQ(f.device.axis_count(), p->default_axes) << name;
        EXPECT_EQ(f.device.od().get<std::uint32_t>(0x1000, 0), p->device_type()) << name;
        EXPECT_NE(f.device.od().find(0x6040), nullptr);
        EXPECT_NE(f.device.od().find(0x1A00), nullptr);
    }
}
