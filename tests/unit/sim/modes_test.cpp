// SPDX-License-Identifier: Apache-2.0
// Modes of operation of the simulated axis move the motor model as the profiles describe.
#include "sim_test_support.hpp"

#include <cmath>

using namespace codrive;
using namespace codrive::sim;
using namespace codrive::sim::testing;
namespace obj = cia::obj;
namespace sw = cia::sw;

namespace {

void select_mode(AxisFixture& f, std::int8_t mode, unsigned i = 0) {
    ASSERT_TRUE(f.write<std::int8_t>(obj::kModesOfOperation, mode, i));
    f.run_ms(1);
    ASSERT_EQ(f.read<std::int8_t>(obj::kModesOfOperationDisplay, i), mode);
}

} // namespace

TEST(SimModes, ProfilePositionReachesTargetAndSetsTargetReached) {
    AxisFixture f("akd2g");
    select_mode(f, 1);
    f.enable();
    ASSERT_TRUE(f.write<std::int32_t>(obj::kTargetPosition, 655360)); // 10 rev
    f.controlword(0x1F);
    f.run_ms(1);
    EXPECT_NE(f.statusword() & sw::kOpMode12, 0) << "set-point acknowledged";
    EXPECT_EQ(f.statusword() & sw::kTargetReached, 0);
    f.controlword(0x0F);
    f.run_ms(1);
    EXPECT_EQ(f.statusword() & sw::kOpMode12, 0) << "ack follows bit 4";
    ASSERT_TRUE(f.run_until([&] { return (f.statusword() & sw::kTargetReached) != 0; }, 5000));
    EXPECT_NEAR(f.read<std::int32_t>(obj::kPositionActual), 655360, 700);
    f.run_ms(50);
    EXPECT_EQ(f.read<std::int32_t>(obj::kVelocityActual), 0);
    EXPECT_NEAR(f.read<std::int32_t>(obj::kPositionActual), 655360, 1);
}

TEST(SimModes, ProfilePositionMoveTakesTheTrapezoidTime) {
    AxisFixture f("akd2g");
    select_mode(f, 1);
    f.enable();
    // 10 rev at 10 rev/s with 100 rev/s²: 0.1 s ramps + 0.9 s cruise = 1.1 s.
    f.write<std::int32_t>(obj::kTargetPosition, 655360);
    f.controlword(0x1F);
    int ms = 0;
    f.run_ms(1);
    while ((f.statusword() & sw::kTargetReached) == 0 && ms < 5000) {
        f.run_ms(1);
        ++ms;
    }
    EXPECT_NEAR(ms, 1100, 60);
}

TEST(SimModes, ProfilePositionRelativeAddsToThePreviousTarget) {
    AxisFixture f("ds-bvs");
    select_mode(f, 1);
    f.enable();
    f.write<std::int32_t>(obj::kTargetPosition, 1000);
    f.controlword(0x5F); // relative
    f.run_ms(1);
    f.controlword(0x4F);
    ASSERT_TRUE(f.run_until([&] { return (f.statusword() & sw::kTargetReached) != 0; }, 10000));
    f.controlword(0x5F);
    f.run_ms(1);
    f.controlword(0x4F);
    ASSERT_TRUE(f.run_until([&] { return (f.statusword() & sw::kTargetReached) != 0; }, 10000));
    EXPECT_NEAR(f.read<std::int32_t>(obj::kPositionActual), 2000, 5);
}

TEST(SimModes, DsBvsProfilePositionMoveOf20000IncrementsReachesTheTarget) {
    // 20,000 increments are 40 revolutions at 500 increments per revolution: the simulated
    // DS-BVS machine must leave room for it (it used to stop at its 10.5 rev stop: 5,250).
    AxisFixture f("ds-bvs");
    select_mode(f, 1);
    f.enable();
    ASSERT_TRUE(f.write<std::int32_t>(obj::kTargetPosition, 20000));
    f.controlword(0x1F);
    f.run_ms(1);
    f.controlword(0x0F);
    ASSERT_TRUE(f.run_until([&] { return (f.statusword() & sw::kTargetReached) != 0; }, 20000));
    EXPECT_NEAR(f.read<std::int32_t>(obj::kPositionActual), 20000, 5);
    EXPECT_FALSE(f.axis().motor().blocked());
}

TEST(SimModes, ChangeSetImmediatelyRetargetsAMovingAxis) {
    AxisFixture f("akd2g");
    select_mode(f, 1);
    f.enable();
    f.write<std::int32_t>(obj::kTargetPosition, 6553600);
    f.controlword(0x1F);
    f.run_ms(300);
    f.controlword(0x0F);
    f.run_ms(1);
    f.write<std::int32_t>(obj::kTargetPosition, 0);
    f.controlword(0x3F); // change set immediately
    f.run_ms(1);
    f.controlword(0x2F);
    ASSERT_TRUE(f.run_until([&] { return (f.statusword() & sw::kTargetReached) != 0; }, 5000));
    EXPECT_NEAR(f.read<std::int32_t>(obj::kPositionActual), 0, 700);
}

TEST(SimModes, BufferedSetPointRunsAfterTheCurrentMove) {
    AxisFixture f("akd2g");
    select_mode(f, 1);
    f.enable();
    f.write<std::int32_t>(obj::kTargetPosition, 65536);
    f.controlword(0x1F);
    f.run_ms(10);
    f.controlword(0x0F);
    f.run_ms(1);
    f.write<std::int32_t>(obj::kTargetPosition, 131072);
    f.controlword(0x1F); // buffered: bit 5 = 0
    f.run_ms(1);
    f.controlword(0x0F);
    ASSERT_TRUE(f.run_until([&] { return (f.statusword() & sw::kTargetReached) != 0; }, 5000));
    EXPECT_NEAR(f.read<std::int32_t>(obj::kPositionActual), 131072, 700);
}

TEST(SimModes, HaltStopsAProfilePositionMoveAndReleaseResumesIt) {
    AxisFixture f("akd2g");
    select_mode(f, 1);
    f.enable();
    f.write<std::int32_t>(obj::kTargetPosition, 655360);
    f.controlword(0x1F);
    f.run_ms(200);
    f.controlword(0x11F);
    f.run_ms(300);
    EXPECT_EQ(f.read<std::int32_t>(obj::kVelocityActual), 0);
    EXPECT_NE(f.statusword() & sw::kTargetReached, 0) << "halted at standstill";
    f.controlword(0x1F);
    EXPECT_EQ(f.statusword() & sw::kTargetReached, 0) << "resumed";
    ASSERT_TRUE(f.run_until([&] { return (f.statusword() & sw::kTargetReached) != 0; }, 5000));
    EXPECT_NEAR(f.read<std::int32_t>(obj::kPositionActual), 655360, 700);
}

TEST(SimModes, ProfileVelocityReachesSpeedAndReportsTargetReached) {
    AxisFixture f("ds-bvs");
    select_mode(f, 3);
    f.enable();
    f.write<std::int32_t>(obj::kTargetVelocity, 600); // rpm; 6083h = 1000 rpm/s → 0.6 s
    f.controlword(0x0F);
    f.run_ms(100);
    EXPECT_EQ(f.statusword() & sw::kTargetReached, 0);
    ASSERT_TRUE(f.run_until([&] { return (f.statusword() & sw::kTargetReached) != 0; }, 3000));
    EXPECT_NEAR(f.read<std::int32_t>(obj::kVelocityActual), 600, 1);
    EXPECT_EQ(f.statusword() & sw::kOpMode12, 0) << "speed is not 0";
    f.write<std::int32_t>(obj::kTargetVelocity, 0);
    ASSERT_TRUE(f.run_until([&] { return (f.statusword() & sw::kOpMode12) != 0; }, 3000));
}

TEST(SimModes, ProfileVelocityMaxProfileVelocityClamps) {
    AxisFixture f("ds-bvs");
    select_mode(f, 3);
    f.enable();
    f.write<std::int32_t>(obj::kTargetVelocity, 5000); // 607Fh = 1000 rpm
    f.run_ms(1050); // 1 s ramp; much longer and the axis reaches its mechanical stop
    EXPECT_NEAR(f.read<std::int32_t>(obj::kVelocityActual), 1000, 1);
}

TEST(SimModes, ProfileTorqueAcceleratesTheMotor) {
    AxisFixture f("akd2g");
    select_mode(f, 4);
    f.enable();
    f.write<std::int16_t>(obj::kTargetTorque, 200);
    f.run_ms(100);
    EXPECT_GT(f.read<std::int32_t>(obj::kVelocityActual), 0);
    EXPECT_NEAR(f.read<std::int16_t>(obj::kTorqueActual), 200, 1);
    EXPECT_NE(f.statusword() & sw::kTargetReached, 0);
}

TEST(SimModes, CyclicSyncPositionFollowsSetPoints) {
    AxisFixture f("akd2g");
    select_mode(f, 8);
    f.enable();
    // A 2 ms cycle streaming a 2 rev/s ramp.
    std::int32_t target = 0;
    for (int k = 0; k < 500; ++k) {
        target += 262;
        f.write<std::int32_t>(obj::kTargetPosition, target);
        f.run_ms(2);
    }
    EXPECT_NE(f.statusword() & sw::kOpMode12, 0);
    EXPECT_EQ(f.statusword() & sw::kOpMode13, 0);
    EXPECT_NEAR(f.read<std::int32_t>(obj::kPositionActual), target, 300);
    EXPECT_LT(std::abs(f.read<std::int32_t>(obj::kFollowingErrorActual)), 300);
}

TEST(SimModes, CyclicSyncPositionLagStaysWithinOneSetPointWhenSetPointsComeIrregularly) {
    AxisFixture f("akd2g");
    select_mode(f, 8);
    f.enable();
    // 1,000 increments per set-point, nominally every 4 ms; every fifth one comes 5 ms late and
    // the next one 3 ms early (a loaded real-time cycle).
    std::int32_t target = 0;
    double worst = 0;
    for (int k = 0; k < 400; ++k) {
        target += 1000;
        f.write<std::int32_t>(obj::kTargetPosition, target);
        const int period = k % 5 == 3 ? 9 : (k % 5 == 4 ? 1 : 4);
        for (int ms = 0; ms < period; ++ms) {
            f.run_ms(1);
            const double lag = target - f.read<std::int32_t>(obj::kPositionActual);
            worst = std::max(worst, std::abs(lag));
        }
    }
    // One set-point step of interpolation lag plus the servo's lag behind its demand.
    EXPECT_LT(worst, 2 * 1000 + 300) << "lag accumulated over irregular set-points";
    f.run_ms(20);
    EXPECT_NEAR(f.read<std::int32_t>(obj::kPositionActual), target, 5) << "no overshoot at the end";
}

TEST(SimModes, CyclicSyncVelocityAndTorqueUseTheirSetPoints) {
    AxisFixture f("ds-bvs");
    select_mode(f, 9);
    f.enable();
    f.write<std::int32_t>(obj::kTargetVelocity, 120);
    f.run_ms(20);
    EXPECT_NEAR(f.read<std::int32_t>(obj::kVelocityActual), 120, 1);
    select_mode(f, 10);
    f.write<std::int16_t>(obj::kTargetTorque, -100);
    f.run_ms(50);
    EXPECT_LT(f.read<std::int32_t>(obj::kVelocityActual), 120);
    EXPECT_EQ(f.read<std::int16_t>(obj::kTorqueActual), -100);
}

TEST(SimModes, JammedMotorRaisesFollowingErrorFault) {
    AxisFixture f("akd2g");
    select_mode(f, 1);
    f.enable();
    f.axis().motor().set_jammed(true);
    f.write<std::int32_t>(obj::kTargetPosition, 6553600);
    f.controlword(0x1F);
    ASSERT_TRUE(f.run_until([&] { return f.state() == cia::State::Fault; }, 3000));
    // No 603Fh on the AKD2G (§5.6): AXIS1.FAULT1 (5004h:01, §5.3.84) lists the fault.
    EXPECT_EQ(f.od.get<std::uint16_t>(0x5004, 1).value_or(0), 0x8611);
}

TEST(SimModes, LimitSwitchesAndHomeSwitchShowIn60FD) {
    AxisFixture f("akd2g");
    f.axis().motor().set_world(-11 * 65536.0);
    f.run_ms(1);
    EXPECT_EQ(f.read<std::uint32_t>(obj::kDigitalInputs) & 0x7, 0x1U);
    f.axis().motor().set_world(2.5 * 65536.0);
    f.run_ms(1);
    EXPECT_EQ(f.read<std::uint32_t>(obj::kDigitalInputs) & 0x7, 0x4U);
}
