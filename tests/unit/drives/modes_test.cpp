// SPDX-License-Identifier: Apache-2.0
// Modes of operation against the scripted fake drive: mode change via 6061h, the PP set-point
// handshake, PV, PT, homing, CSP and their errors.
#include "rig.hpp"

#include <gtest/gtest.h>

#include <algorithm>

namespace codrive::drives::testing {
namespace {

using cia402::Mode;
using cia402::State;

Rig& enabled(Rig& rig, Mode mode) {
    rig.cycles(2);
    EXPECT_TRUE(rig.run([&](auto d) { rig.axis().set_mode(mode, d); }));
    EXPECT_TRUE(rig.run([&](auto d) { rig.axis().enable(d); }));
    return rig;
}

TEST(AxisModes, ModeChangeIsConfirmedBy6061) {
    Rig rig(akd2g_profile());
    rig.cycles(2);
    auto r = rig.run([&](auto d) { rig.axis().set_mode(Mode::CyclicSyncPosition, d); });
    ASSERT_TRUE(r.has_value()) << r.error().message;
    EXPECT_EQ(rig.axis().mode_display(), 8);
    EXPECT_EQ(rig.dev.od().get<std::int8_t>(0x6061, 0), 8);
}

TEST(AxisModes, ModeChangeBySdoWhenNotMapped) {
    Rig rig(ds_bvs_profile(), false);
    rig.cycles(4);
    auto r = rig.run([&](auto d) { rig.axis().set_mode(Mode::Homing, d); });
    ASSERT_TRUE(r.has_value()) << r.error().message;
    EXPECT_EQ(rig.dev.od().get<std::int8_t>(0x6061, 0), 6);
}

TEST(AxisModes, UnsupportedModeFailsAtOnce) {
    Rig rig(akd2g_profile());
    rig.cycles(2);
    auto r = rig.run([&](auto d) { rig.axis().set_mode(Mode::CyclicSyncTorque, d); });
    ASSERT_FALSE(r.has_value());
    EXPECT_EQ(r.error().code, DriveErrc::NotSupported);
    EXPECT_EQ(r.error().message, "node 5 axis 1: mode cyclic synchronous torque (CST) is not "
                                 "supported (6502h = 0x000000AD)");
}

TEST(AxisModes, SupportedModesAreDiscoveredFrom6502) {
    Rig rig(generic_profile());
    rig.dev.od().set<std::uint32_t>(0x6502, 0, 0x0000000D); // PP, PV, PT only
    rig.cycles(2);
    ASSERT_TRUE(rig.run([&](auto d) { rig.axis().discover(d); }));
    EXPECT_EQ(rig.axis().supported_modes(), 0x0DU);
    EXPECT_TRUE(rig.axis().supports_mode(1));
    EXPECT_FALSE(rig.axis().supports_mode(8));
}

TEST(AxisModes, ModeChangeTimesOutWhenTheDriveKeepsTheOldMode) {
    Rig rig(generic_profile());
    rig.dev.model(1).reject_modes = true;
    rig.cycles(2);
    auto r = rig.run([&](auto d) { rig.axis().set_mode(Mode::ProfileVelocity, d); });
    ASSERT_FALSE(r.has_value());
    EXPECT_EQ(r.error().message, "node 5 axis 1: mode change to profile velocity (PV) timed out: "
                                 "6061h still reports no mode");
}

TEST(AxisModes, ProfilePositionHandshake) {
    Rig rig(generic_profile());
    enabled(rig, Mode::ProfilePosition);
    auto r = rig.run([&](auto d) { rig.axis().move_to(2500, {}, d); });
    ASSERT_TRUE(r.has_value()) << r.error().message;
    EXPECT_EQ(rig.dev.model(1).position, 2500);
    const auto log = rig.dev.controlword_log(1);
    // New set-point (bit 4) until the ack (bit 12), then bit 4 back to 0.
    const std::vector<std::uint16_t> handshake{0x000F, 0x001F, 0x000F};
    EXPECT_NE(std::search(log.begin(), log.end(), handshake.begin(), handshake.end()), log.end())
        << ::testing::PrintToString(log);
    EXPECT_EQ(rig.axis().controlword(), 0x000F);
}

TEST(AxisModes, ProfilePositionOptionsSetBits5_6_9) {
    Rig rig(generic_profile());
    enabled(rig, Mode::ProfilePosition);
    MoveOptions rel;
    rel.relative = true;
    ASSERT_TRUE(rig.run([&](auto d) { rig.axis().move_to(300, rel, d); }));
    EXPECT_EQ(rig.dev.model(1).position, 300);
    ASSERT_TRUE(rig.run([&](auto d) { rig.axis().move_to(300, rel, d); }));
    EXPECT_EQ(rig.dev.model(1).position, 600);
    MoveOptions imm;
    imm.immediate = true;
    imm.change_on_setpoint = true;
    imm.velocity = 1000;
    ASSERT_TRUE(rig.run([&](auto d) { rig.axis().move_to(-100, imm, d); }));
    EXPECT_EQ(rig.dev.model(1).position, -100);
    EXPECT_EQ(rig.dev.od().get<std::uint32_t>(0x6081, 0), 1000U);
    const auto log = rig.dev.controlword_log(1);
    EXPECT_NE(std::find(log.begin(), log.end(), 0x005F), log.end()); // relative
    EXPECT_NE(std::find(log.begin(), log.end(), 0x023F), log.end()); // immediate + bit 9
}

TEST(AxisModes, ProfilePositionReportsFollowingError) {
    Rig rig(generic_profile());
    enabled(rig, Mode::ProfilePosition);
    rig.dev.model(1).following_error = true;
    rig.dev.model(1).step_size = 1;
    auto r = rig.run([&](auto d) { rig.axis().move_to(100000, {}, d); });
    ASSERT_FALSE(r.has_value());
    EXPECT_EQ(r.error().code, DriveErrc::FollowingError);
    EXPECT_EQ(r.error().message,
              "node 5 axis 1: move to 100000 failed: following error (statusword bit 13)");
}

TEST(AxisModes, MoveNeedsOperationEnabledAndTheRightMode) {
    Rig rig(generic_profile());
    rig.cycles(2);
    auto r = rig.run([&](auto d) { rig.axis().move_to(10, {}, d); });
    ASSERT_FALSE(r.has_value());
    EXPECT_EQ(r.error().code, DriveErrc::WrongState);
    EXPECT_EQ(r.error().message,
              "node 5 axis 1: move to 10 needs OPERATION ENABLED, the axis is in SWITCH ON "
              "DISABLED");
    enabled(rig, Mode::ProfileVelocity);
    r = rig.run([&](auto d) { rig.axis().move_to(10, {}, d); });
    ASSERT_FALSE(r.has_value());
    EXPECT_EQ(r.error().code, DriveErrc::WrongMode);
}

TEST(AxisModes, FaultDuringMoveNamesTheFault) {
    Rig rig(akd2g_profile());
    enabled(rig, Mode::ProfilePosition);
    rig.dev.model(1).step_size = 1;
    std::optional<DriveVoid> result;
    rig.axis().move_to(100000, {}, [&](DriveVoid r) { result = r; });
    rig.cycles(10);
    rig.dev.trigger_fault(1, 0x8611);
    rig.axis().note_error_code(0x8611);
    rig.cycles(5);
    ASSERT_TRUE(result.has_value());
    ASSERT_FALSE(result->has_value());
    EXPECT_EQ(result->error().code, DriveErrc::Fault);
    EXPECT_EQ(result->error().message,
              "node 5 axis 1: move to 100000 aborted: the axis entered FAULT: "
              "error code 0x8611 (F6001 Following error magnitude fault)");
}

TEST(AxisModes, ProfileVelocityAndTorqueWaitForTargetReached) {
    Rig rig(generic_profile());
    enabled(rig, Mode::ProfileVelocity);
    ASSERT_TRUE(rig.run([&](auto d) { rig.axis().run_velocity(1500, d); }));
    EXPECT_EQ(rig.dev.model(1).velocity, 1500);
    EXPECT_EQ(rig.axis().velocity_actual(), 1500);
    ASSERT_TRUE(rig.run([&](auto d) { rig.axis().set_mode(Mode::ProfileTorque, d); }));
    ASSERT_TRUE(rig.run([&](auto d) { rig.axis().run_torque(250, d); }));
    EXPECT_EQ(rig.dev.od().get<std::int16_t>(0x6071, 0), 250);
}

TEST(AxisModes, LateTpdoRepeatingAStaleTargetReachedDoesNotEndAVelocityChange) {
    Rig rig(generic_profile());
    rig.tr.count_inputs(true);
    enabled(rig, Mode::ProfileVelocity);
    ASSERT_TRUE(rig.run([&](auto d) { rig.axis().run_velocity(1500, d); }));
    ASSERT_NE(rig.axis().statusword() & 0x0400, 0) << "target reached at 1500";
    // The TPDOs stop arriving: the image keeps the statusword with bit 10 from the old target.
    rig.tr.stall_inputs(true);
    std::optional<DriveVoid> result;
    rig.axis().run_velocity(0, [&](DriveVoid r) { result = std::move(r); });
    rig.cycles(5);
    EXPECT_FALSE(result.has_value()) << "a repeated statusword is not a new sample";
    rig.tr.stall_inputs(false);
    rig.cycles(5);
    ASSERT_TRUE(result.has_value());
    EXPECT_TRUE(result->has_value());
    EXPECT_EQ(rig.axis().velocity_actual(), 0);
}

TEST(AxisModes, FollowingErrorActualIsReadFromTheProcessDataWhenMapped) {
    Rig rig(akd2g_profile());
    rig.cycles(2);
    EXPECT_FALSE(rig.axis().following_error_actual()) << "60F4h not mapped";
    rig.tr.map_input(0x60F4, 0);
    rig.axis().bind();
    ASSERT_TRUE(rig.dev.od().set<std::int32_t>(0x60F4, 0, -321));
    rig.cycles(1);
    EXPECT_EQ(rig.axis().following_error_actual(), -321);
}

TEST(AxisModes, HomingWritesParametersAndWaitsForAttained) {
    Rig rig(ds_bvs_profile());
    enabled(rig, Mode::Homing);
    HomingParams hp;
    hp.method = 17;
    hp.speed_switch = 200;
    hp.speed_zero = 20;
    hp.acceleration = 5000;
    hp.offset = 42;
    auto r = rig.run([&](auto d) { rig.axis().home(hp, d); });
    ASSERT_TRUE(r.has_value()) << r.error().message;
    EXPECT_EQ(rig.dev.od().get<std::int8_t>(0x6098, 0), 17);
    EXPECT_EQ(rig.dev.od().get<std::uint32_t>(0x6099, 1), 200U);
    EXPECT_EQ(rig.dev.od().get<std::uint32_t>(0x6099, 2), 20U);
    EXPECT_EQ(rig.dev.od().get<std::uint32_t>(0x609A, 0), 5000U);
    EXPECT_EQ(rig.dev.model(1).position, 42);
    EXPECT_EQ(rig.axis().controlword() & 0x10, 0); // start bit taken back
}

TEST(AxisModes, HomingErrorIsReported) {
    Rig rig(generic_profile());
    enabled(rig, Mode::Homing);
    rig.dev.model(1).homing_fail = true;
    auto r = rig.run([&](auto d) { rig.axis().home(HomingParams{}, d); });
    ASSERT_FALSE(r.has_value());
    EXPECT_EQ(r.error().code, DriveErrc::HomingError);
    EXPECT_EQ(r.error().message,
              "node 5 axis 1: homing (method 35) failed: homing error (statusword bit 13)");
}

TEST(AxisModes, HomingTimesOut) {
    Rig rig(generic_profile());
    enabled(rig, Mode::Homing);
    rig.dev.model(1).stuck = true;
    rig.dev.model(1).homing_cycles = 100000;
    auto r = rig.run([&](auto d) { rig.axis().home(HomingParams{}, d, milliseconds(50)); });
    ASSERT_FALSE(r.has_value());
    EXPECT_EQ(r.error().code, DriveErrc::Timeout);
    EXPECT_NE(r.error().message.find("homing (method 35) timed out in OPERATION ENABLED"),
              std::string::npos)
        << r.error().message;
}

TEST(AxisModes, CyclicSynchronousPositionFollowsEveryCycle) {
    Rig rig(akd2g_profile());
    enabled(rig, Mode::CyclicSyncPosition);
    for (int k = 1; k <= 20; ++k) {
        rig.axis().set_target_position(k * 10);
        rig.cycle();
    }
    rig.cycle();
    EXPECT_EQ(rig.dev.model(1).position, 200);
    EXPECT_TRUE(rig.axis().following_setpoints());
    EXPECT_EQ(rig.axis().position_actual(), 200);
}

TEST(AxisModes, CyclicSynchronousVelocityAndTorqueSendTheirTargets) {
    Rig rig(ds_bvs_profile());
    enabled(rig, Mode::CyclicSyncVelocity);
    rig.axis().set_target_velocity(-750);
    rig.cycles(2);
    EXPECT_EQ(rig.dev.od().get<std::int32_t>(0x60FF, 0), -750);
    EXPECT_TRUE(rig.axis().following_setpoints());
    ASSERT_TRUE(rig.run([&](auto d) { rig.axis().set_mode(Mode::CyclicSyncTorque, d); }));
    rig.axis().set_target_torque(-120);
    rig.cycles(2);
    EXPECT_EQ(rig.dev.od().get<std::int16_t>(0x6071, 0), -120);
    EXPECT_EQ(rig.axis().mode_display(), 10);
}

TEST(AxisModes, CspTargetFollowsTheActualPositionUntilEnabled) {
    Rig rig(generic_profile());
    rig.dev.model(1).position = 5000;
    rig.cycles(2);
    ASSERT_TRUE(rig.run([&](auto d) { rig.axis().set_mode(Mode::CyclicSyncPosition, d); }));
    ASSERT_TRUE(rig.run([&](auto d) { rig.axis().enable(d); }));
    rig.cycles(3);
    EXPECT_EQ(rig.dev.model(1).position, 5000); // no jump to the RPDO's initial 0
    EXPECT_EQ(rig.axis().target_position(), 5000);
}

} // namespace
} // namespace codrive::drives::testing
