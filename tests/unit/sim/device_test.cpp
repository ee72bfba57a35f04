// SPDX-License-Identifier: Apache-2.0
// SimDevice on the virtual bus: boot-up, SDO access, heartbeat, EMCY, PDOs, faults, resets.
#include "device_test_support.hpp"

#include <codrive/drives/cia402.hpp>

using namespace codrive;
using namespace codrive::sim;
using namespace codrive::sim::testing;
namespace cia = drives::cia402;

namespace {
Frame nmt_cmd(std::uint8_t cs, NodeId node) {
    return Frame::make(0x000, {cs, node});
}
} // namespace

TEST(SimDevice, SendsBootUpOnStartAndIsPreOperational) {
    DeviceFixture f("akd2g");
    EXPECT_TRUE(f.frames.empty()) << "silent before power-on";
    f.start();
    const auto boot = f.with_id(0x703);
    ASSERT_EQ(boot.size(), 1U);
    EXPECT_EQ(boot[0].len, 1);
    EXPECT_EQ(boot[0].data[0], 0x00);
    EXPECT_EQ(f.device.nmt_state(), nmt::NmtState::PreOperational);
    EXPECT_EQ(f.device.summary(), "node 3 akd2g (2 axes)");
}

TEST(SimDevice, SdoReadsIdentityAndDeviceType) {
    DeviceFixture f("akd2g");
    f.start();
    auto vendor = f.read<std::uint32_t>(0x1018, 1);
    ASSERT_TRUE(vendor) << vendor.error().to_string();
    EXPECT_EQ(*vendor, 0x6AU);
    EXPECT_EQ(*f.read<std::uint32_t>(0x1018, 2), 0x11210100U); // two axes
    EXPECT_EQ(*f.read<std::uint32_t>(0x1000, 0), 0x00020192U);
    auto name = f.read<std::string>(0x1008, 0);
    ASSERT_TRUE(name);
    EXPECT_EQ(*name, "AKD2G-SPE-6V03D-A1C1-0000"); // segmented upload
    EXPECT_EQ(*f.read<std::uint32_t>(0x6502, 0), 0xADU);
    EXPECT_EQ(*f.read<std::uint32_t>(0x6D02, 0), 0xADU); // axis 2 at +0x800
}

TEST(SimDevice, DsBvsIdentityAndDefaults) {
    DeviceFixture f("ds-bvs", 1);
    f.start();
    EXPECT_EQ(*f.read<std::int8_t>(0x6060, 0), 3);
    EXPECT_EQ(*f.read<std::int8_t>(0x6098, 0), 17);
    EXPECT_EQ(*f.read<std::int16_t>(0x605A, 0), 6);
    EXPECT_EQ(*f.read<std::uint32_t>(0x6502, 0), 0x3AFU);
    EXPECT_EQ(*f.read<std::uint32_t>(0x1800, 1), 0x40000181U);
    EXPECT_EQ(*f.read<std::uint8_t>(0x1600, 0), 0U);
    auto r = f.read<std::uint32_t>(0x6840, 0);
    ASSERT_FALSE(r);
    EXPECT_EQ(r.error().abort_code(), 0x06020000U);
}

TEST(SimDevice, ControlwordWrittenBySdoRunsTheStateMachine) {
    DeviceFixture f("akd2g");
    f.start();
    ASSERT_TRUE(f.write<std::uint16_t>(0x6040, 0, 0x06));
    EXPECT_EQ(cia::decode_state(*f.read<std::uint16_t>(0x6041, 0)), cia::State::ReadyToSwitchOn);
    ASSERT_TRUE(f.write<std::uint16_t>(0x6040, 0, 0x0F));
    f.run_ms(2);
    EXPECT_EQ(cia::decode_state(*f.read<std::uint16_t>(0x6041, 0)), cia::State::OperationEnabled);
    EXPECT_EQ(cia::decode_state(*f.read<std::uint16_t>(0x6841, 0)), cia::State::SwitchOnDisabled);
    auto ro = f.write<std::uint16_t>(0x6041, 0, 0);
    ASSERT_FALSE(ro);
    EXPECT_EQ(ro.error().abort_code(), 0x06010002U);
}

TEST(SimDevice, HeartbeatProducerFollows1017AndNmtState) {
    DeviceFixture f("ds-bvs", 5);
    f.start();
    ASSERT_TRUE(f.write<std::uint16_t>(0x1017, 0, 100));
    f.frames.clear();
    f.run_ms(350);
    auto hb = f.with_id(0x705);
    ASSERT_EQ(hb.size(), 3U);
    EXPECT_EQ(hb[0].data[0], 0x7F);
    f.send(nmt_cmd(0x01, 5));
    f.frames.clear();
    f.run_ms(100);
    hb = f.with_id(0x705);
    ASSERT_EQ(hb.size(), 1U);
    EXPECT_EQ(hb[0].data[0], 0x05);
    f.send(nmt_cmd(0x02, 0)); // stop, all nodes
    f.frames.clear();
    f.run_ms(100);
    hb = f.with_id(0x705);
    ASSERT_EQ(hb.size(), 1U);
    EXPECT_EQ(hb[0].data[0], 0x04);
}

TEST(SimDevice, NmtResetNodeProducesBootUpAndRestoresDefaults) {
    DeviceFixture f("akd2g");
    f.start();
    ASSERT_TRUE(f.write<std::uint16_t>(0x1017, 0, 50));
    ASSERT_TRUE(f.write<std::int32_t>(0x607A, 0, 1234));
    f.frames.clear();
    f.send(nmt_cmd(0x81, 3));
    const auto boot = f.with_id(0x703);
    ASSERT_EQ(boot.size(), 1U);
    EXPECT_EQ(boot[0].data[0], 0x00);
    EXPECT_EQ(*f.read<std::uint16_t>(0x1017, 0), 0U);
    EXPECT_EQ(*f.read<std::int32_t>(0x607A, 0), 0);
    EXPECT_EQ(f.device.stats().boot_ups, 2U);
}

TEST(SimDevice, ResetCommunicationKeepsApplicationParameters) {
    DeviceFixture f("akd2g");
    f.start();
    ASSERT_TRUE(f.write<std::uint16_t>(0x1017, 0, 50));
    ASSERT_TRUE(f.write<std::int32_t>(0x607A, 0, 1234));
    f.send(nmt_cmd(0x82, 3));
    EXPECT_EQ(*f.read<std::uint16_t>(0x1017, 0), 0U);
    EXPECT_EQ(*f.read<std::int32_t>(0x607A, 0), 1234);
}

TEST(SimDevice, OverCurrentRaisesProfileEmcyAnd603FAndResetSendsEmcyZero) {
    DeviceFixture f("akd2g");
    f.start();
    f.device.inject(1, FaultKind::OverCurrent, f.clock.now());
    f.run_ms(5);
    ASSERT_EQ(f.emcy_codes(3), (std::vector<std::uint16_t>{0xFF07}));
    const auto e = f.with_id(0x83).front();
    EXPECT_EQ(e.len, 8);
    EXPECT_EQ(e.data[2], 0x01) << "AKD2G uses only the generic bit";
    EXPECT_EQ(e.data[3], 0) << "no axis byte: the manual documents none";
    EXPECT_EQ(*f.read<std::uint16_t>(0x5104, 1), 0xFF07) << "AXIS2.FAULT1 names the axis";
    EXPECT_EQ(*f.read<std::uint16_t>(0x5004, 1), 0) << "AXIS1.FAULT1";
    EXPECT_EQ(*f.read<std::uint8_t>(0x1001, 0), 0x01);
    EXPECT_EQ(*f.read<std::uint8_t>(0x1003, 0), 1U);
    EXPECT_EQ(*f.read<std::uint32_t>(0x1003, 1) & 0xFFFF, 0xFF07U);
    ASSERT_TRUE(f.write<std::uint16_t>(0x6840, 0, 0x80));
    f.run_ms(2);
    EXPECT_EQ(f.emcy_codes(3), (std::vector<std::uint16_t>{0xFF07, 0x0000}));
    EXPECT_EQ(*f.read<std::uint8_t>(0x1001, 0), 0x00);
}

TEST(SimDevice, EachInjectedFaultRaisesTheProfileCode) {
    for (const char* name : {"akd2g", "ds-bvs"}) {
        DeviceFixture f(name, 2, 1);
        f.start();
        const SimProfile& p = *find_profile(name);
        ASSERT_TRUE(f.write<std::uint16_t>(0x6040, 0, 0x06));
        ASSERT_TRUE(f.write<std::uint16_t>(0x6040, 0, 0x07));
        ASSERT_TRUE(f.write<std::uint16_t>(0x6040, 0, 0x0F));
        f.run_ms(2);
        f.device.inject(0, FaultKind::Sto, f.clock.now());
        f.run_ms(50);
        f.device.axis(0).set_sto(false);
        f.write<std::uint16_t>(0x6040, 0, 0x80);
        f.write<std::uint16_t>(0x6040, 0, 0x00);
        f.device.inject(0, FaultKind::FollowingError, f.clock.now());
        f.run_ms(50);
        f.write<std::uint16_t>(0x6040, 0, 0x80);
        f.write<std::uint16_t>(0x6040, 0, 0x00);
        f.device.inject(0, FaultKind::OverCurrent, f.clock.now());
        f.run_ms(50);
        EXPECT_EQ(f.emcy_codes(2),
                  (std::vector<std::uint16_t>{p.sto_code, 0, p.following_error_code, 0,
                                              p.over_current_code}))
            << name;
        // The AKD2G has no 603Fh (§5.6): its axis fault list 5004h (§5.3.84) names the code.
        const std::uint16_t where = p.akd2g_objects ? 0x5004 : 0x603F;
        EXPECT_EQ(*f.read<std::uint16_t>(where, p.akd2g_objects ? 1 : 0), p.over_current_code)
            << name;
    }
}

TEST(SimDevice, Akd2gHeartbeatConsumerLossRaisesF7002) {
    DeviceFixture f("akd2g");
    f.start();
    ASSERT_TRUE(f.write<std::uint32_t>(0x1016, 1, (0x7FU << 16) | 100U)); // master = node 127
    f.send(Frame::make(0x77F, {0x05}));
    f.run_ms(50);
    f.send(Frame::make(0x77F, {0x05}));
    f.run_ms(50);
    EXPECT_TRUE(f.emcy_codes(3).empty());
    f.run_ms(200);
    const auto codes = f.emcy_codes(3);
    ASSERT_FALSE(codes.empty());
    EXPECT_EQ(codes.front(), 0x8130);
    EXPECT_EQ(*f.read<std::uint16_t>(0x5004, 1), 0x8130) << "AXIS1.FAULT1 (no 603Fh, §5.6)";
    EXPECT_EQ(cia::decode_state(*f.read<std::uint16_t>(0x6041, 0)), cia::State::Fault);
}

TEST(SimDevice, DsBvsHeartbeatLossAppliesErrorBehaviourAndAbortConnection) {
    DeviceFixture f("ds-bvs", 1);
    f.start();
    ASSERT_TRUE(f.write<std::uint8_t>(0x1029, 1, 0)); // → pre-operational
    ASSERT_TRUE(f.write<std::int16_t>(0x6007, 0, 3)); // quick stop
    ASSERT_TRUE(f.write<std::uint32_t>(0x1016, 1, (0x7FU << 16) | 100U));
    f.send(nmt_cmd(0x01, 1));
    ASSERT_EQ(f.device.nmt_state(), nmt::NmtState::Operational);
    ASSERT_TRUE(f.write<std::uint16_t>(0x6040, 0, 0x06));
    ASSERT_TRUE(f.write<std::uint16_t>(0x6040, 0, 0x07));
    ASSERT_TRUE(f.write<std::uint16_t>(0x6040, 0, 0x0F));
    f.send(Frame::make(0x77F, {0x05}));
    f.run_ms(300);
    EXPECT_EQ(f.emcy_codes(1), (std::vector<std::uint16_t>{0x8130}));
    EXPECT_EQ(f.device.nmt_state(), nmt::NmtState::PreOperational);
    EXPECT_EQ(cia::decode_state(*f.read<std::uint16_t>(0x6041, 0)), cia::State::QuickStopActive);
    EXPECT_EQ(*f.read<std::uint8_t>(0x1001, 0) & 0x10, 0x10);
    EXPECT_EQ(*f.read<std::uint16_t>(0x4080, 1), 0x8130);
}

TEST(SimDevice, ControlObjectInjectsFaultsAndResetsTheNode) {
    DeviceFixture f("akd2g");
    f.start();
    ASSERT_TRUE(f.write<std::uint8_t>(0x2FF1, 1, 1)); // STO on axis 2
    EXPECT_EQ(*f.read<std::uint8_t>(0x2FF1, 1), 1U);
    EXPECT_NE(*f.read<std::uint16_t>(0x6841, 0) & 0x0100, 0) << "statusword bit 8";
    EXPECT_EQ(f.emcy_codes(3), (std::vector<std::uint16_t>{0xFF0C})) << "W9000 while disabled";
    ASSERT_TRUE(f.write<std::uint8_t>(0x2FF1, 1, 0));
    ASSERT_TRUE(f.write<std::uint8_t>(0x2FF0, 3, 1)); // following error on axis 1
    EXPECT_EQ(*f.read<std::uint16_t>(0x5004, 1), 0x8611);
    f.frames.clear();
    ASSERT_TRUE(f.write<std::uint8_t>(0x2FF0, 5, 1)); // reset node: response first
    f.run_ms(2);
    ASSERT_GE(f.frames.size(), 2U);
    EXPECT_EQ(f.frames[0].id, 0x583U);
    EXPECT_EQ(f.with_id(0x703).size(), 1U);
    EXPECT_EQ(*f.read<std::uint16_t>(0x5004, 1), 0);
}

TEST(SimDevice, StoreAndRestoreSignatures) {
    DeviceFixture f("ds-bvs", 1);
    f.start();
    auto bad = f.write<std::uint32_t>(0x1010, 1, 0x12345678);
    ASSERT_FALSE(bad);
    EXPECT_EQ(bad.error().abort_code(), 0x08000020U);
    EXPECT_TRUE(f.write<std::uint32_t>(0x1010, 1, 0x65766173));
    EXPECT_EQ(*f.read<std::uint32_t>(0x1010, 1), 1U);
    f.send(nmt_cmd(0x01, 1));
    auto state = f.write<std::uint32_t>(0x1011, 1, 0x64616F6C);
    ASSERT_FALSE(state);
    EXPECT_EQ(state.error().abort_code(), 0x08000022U) << "DS-BVS restores only in pre-op";
}

TEST(SimDevice, Akd2gDefaultPdosCarryStatuswordAndPositionWhenOperational) {
    DeviceFixture f("akd2g");
    f.start();
    f.send(nmt_cmd(0x01, 3));
    f.frames.clear();
    // RPDO1 (0x203): controlword 0x0006 + target 0 → statusword changes → TPDO1 (0x183).
    f.send(Frame::make(0x203, {0x06, 0x00, 0, 0, 0, 0}));
    f.run_ms(20);
    const auto tpdo = f.with_id(0x183);
    ASSERT_FALSE(tpdo.empty());
    EXPECT_EQ(tpdo.back().len, 7) << "the profile's CSP layout: 6041h, 6064h, 6061h";
    EXPECT_EQ(cia::decode_state(
                  static_cast<std::uint16_t>(tpdo.back().data[0] | (tpdo.back().data[1] << 8))),
              cia::State::ReadyToSwitchOn);
}

TEST(SimDevice, CspThroughSyncPdosFollowsSetPoints) {
    DeviceFixture f("ds-bvs", 1);
    f.start();
    // RPDO1 = 6040 + 607A (type 1), TPDO1 = 6041 + 6064 (type 1); mapped in pre-operational.
    ASSERT_TRUE(f.write<std::uint8_t>(0x1400, 2, 1));
    ASSERT_TRUE(f.write<std::uint32_t>(0x1600, 1, 0x60400010));
    ASSERT_TRUE(f.write<std::uint32_t>(0x1600, 2, 0x607A0020));
    ASSERT_TRUE(f.write<std::uint8_t>(0x1600, 0, 2));
    ASSERT_TRUE(f.write<std::uint8_t>(0x1800, 2, 1));
    ASSERT_TRUE(f.write<std::uint32_t>(0x1A00, 1, 0x60410010));
    ASSERT_TRUE(f.write<std::uint32_t>(0x1A00, 2, 0x60640020));
    ASSERT_TRUE(f.write<std::uint8_t>(0x1A00, 0, 2));
    ASSERT_TRUE(f.write<std::int8_t>(0x6060, 0, 8));
    f.send(nmt_cmd(0x01, 1));
    const auto rpdo = [&](std::uint16_t cw, std::int32_t pos) {
        std::array<std::uint8_t, 6> d{};
        put_le<std::uint16_t>(d.data(), cw);
        put_le<std::int32_t>(d.data() + 2, pos);
        f.send(Frame::make(0x201, d));
        f.send(Frame::make(0x080, {}));
        f.run_ms(2);
    };
    rpdo(0x06, 0);
    rpdo(0x07, 0);
    rpdo(0x0F, 0);
    std::int32_t pos = 0;
    for (int k = 0; k < 200; ++k) {
        pos += 4; // 4 counts per 2 ms = 240 rpm at 500 counts/rev
        rpdo(0x0F, pos);
    }
    f.run_ms(20);
    const auto tpdo = f.with_id(0x181);
    ASSERT_FALSE(tpdo.empty());
    const auto& last = tpdo.back();
    EXPECT_EQ(cia::decode_state(get_le<std::uint16_t>(last.data.data())),
              cia::State::OperationEnabled);
    // The TPDO of a SYNC is sampled before that SYNC's set-point acts, and the drive
    // interpolates to a set-point over one period (CSP): two set-points (8 counts) behind.
    EXPECT_NEAR(get_le<std::int32_t>(last.data.data() + 2), pos, 8);
}
