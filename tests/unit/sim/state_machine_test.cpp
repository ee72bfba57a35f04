// SPDX-License-Identifier: Apache-2.0
// CiA 402 device state machine of the simulated axis: every transition 0–16 and option codes.
#include "sim_test_support.hpp"

using namespace codrive;
using namespace codrive::sim;
using namespace codrive::sim::testing;
using cia::State;

TEST(SimStateMachine, PowerOnEndsInSwitchOnDisabled) { // transitions 0, 1
    AxisFixture f("akd2g");
    EXPECT_EQ(f.state(), State::SwitchOnDisabled);
    EXPECT_NE(f.statusword() & cia::sw::kRemote, 0);
}

TEST(SimStateMachine, ShutdownSwitchOnEnableWalkTransitions2To4) {
    AxisFixture f("akd2g");
    f.controlword(0x06);
    EXPECT_EQ(f.state(), State::ReadyToSwitchOn); // 2
    f.controlword(0x07);
    EXPECT_EQ(f.state(), State::SwitchedOn); // 3
    f.controlword(0x0F);
    EXPECT_EQ(f.state(), State::OperationEnabled); // 4
    EXPECT_EQ(f.statusword() & 0x6F, 0x27);
}

TEST(SimStateMachine, EnableFromReadyGoesThroughSwitchedOnOnTheNextStep) {
    AxisFixture f("ds-bvs");
    f.controlword(0x06);
    f.controlword(0x0F);
    EXPECT_EQ(f.state(), State::SwitchedOn);
    f.run_ms(1);
    EXPECT_EQ(f.state(), State::OperationEnabled);
}

TEST(SimStateMachine, DisableOperationShutdownAndDisableVoltageFromEnabled) {
    AxisFixture f("akd2g");
    f.enable();
    f.controlword(0x07); // 5 (ramp with 6084h, then SWITCHED ON)
    f.run_until([&] { return f.state() == State::SwitchedOn; }, 100);
    EXPECT_EQ(f.state(), State::SwitchedOn);
    f.controlword(0x06); // 6
    EXPECT_EQ(f.state(), State::ReadyToSwitchOn);
    f.controlword(0x00); // 7
    EXPECT_EQ(f.state(), State::SwitchOnDisabled);
    f.enable();
    f.controlword(0x06); // 8
    EXPECT_EQ(f.state(), State::ReadyToSwitchOn);
    f.controlword(0x07);
    f.controlword(0x0F);
    f.controlword(0x00); // 9
    EXPECT_EQ(f.state(), State::SwitchOnDisabled);
    f.controlword(0x06);
    f.controlword(0x07);
    f.controlword(0x02); // 10 (quick stop from SWITCHED ON)
    EXPECT_EQ(f.state(), State::SwitchOnDisabled);
}

TEST(SimStateMachine, QuickStopOption2EndsInSwitchOnDisabled) { // 11, then 12
    AxisFixture f("akd2g");
    ASSERT_EQ(f.read<std::int16_t>(cia::obj::kQuickStopOption), 2);
    f.enable();
    f.controlword(0x0B);
    EXPECT_EQ(f.state(), State::QuickStopActive);
    EXPECT_EQ(f.statusword() & cia::sw::kQuickStop, 0);
    EXPECT_TRUE(f.run_until([&] { return f.state() == State::SwitchOnDisabled; }, 200));
}

TEST(SimStateMachine, QuickStopOption6StaysAndEnableReturnsToOperation) { // 11, 16
    AxisFixture f("ds-bvs");
    ASSERT_EQ(f.read<std::int16_t>(cia::obj::kQuickStopOption), 6);
    f.enable();
    f.controlword(0x0B);
    EXPECT_EQ(f.state(), State::QuickStopActive);
    f.run_ms(200);
    EXPECT_EQ(f.state(), State::QuickStopActive);
    EXPECT_NE(f.statusword() & cia::sw::kTargetReached, 0);
    f.controlword(0x0F);
    EXPECT_EQ(f.state(), State::OperationEnabled);
}

TEST(SimStateMachine, DisableVoltageLeavesQuickStopActive) { // 12
    AxisFixture f("ds-bvs");
    f.enable();
    f.controlword(0x0B);
    f.controlword(0x00);
    EXPECT_EQ(f.state(), State::SwitchOnDisabled);
}

// The AKD2G has no 603Fh (manual §5.6): AXIS1.FAULT1 (5004h:01, §5.3.84) lists the fault.
TEST(SimStateMachine, FaultReactionThenFaultThenResetOnRisingEdge) { // 13, 14, 15
    AxisFixture f("akd2g");
    f.enable();
    f.axis().inject(FaultKind::OverCurrent);
    EXPECT_EQ(f.state(), State::FaultReactionActive);
    EXPECT_TRUE(f.run_until([&] { return f.state() == State::Fault; }, 200));
    EXPECT_EQ(f.od.get<std::uint16_t>(0x5004, 1).value_or(0), 0xFF07);
    f.controlword(0x00);
    f.controlword(0x80);
    EXPECT_EQ(f.state(), State::SwitchOnDisabled);
    EXPECT_EQ(f.od.get<std::uint16_t>(0x5004, 1).value_or(0), 0);
    ASSERT_FALSE(f.events.empty());
    EXPECT_EQ(f.events.front().kind, AxisEvent::Kind::FaultRaised);
    EXPECT_EQ(f.events.back().kind, AxisEvent::Kind::FaultsCleared);
}

TEST(SimStateMachine, FaultResetNeedsAnEdge) {
    AxisFixture f("ds-bvs");
    f.controlword(0x80);
    f.axis().inject(FaultKind::OverCurrent);
    f.run_ms(2);
    EXPECT_EQ(f.state(), State::Fault);
    f.controlword(0x80); // still high: no edge
    EXPECT_EQ(f.state(), State::Fault);
    f.controlword(0x00);
    f.controlword(0x80);
    EXPECT_EQ(f.state(), State::SwitchOnDisabled);
}

TEST(SimStateMachine, DsBvsFaultReactionOption0DisablesImmediately) {
    AxisFixture f("ds-bvs");
    f.enable();
    f.axis().inject(FaultKind::FollowingError);
    f.run_ms(1);
    EXPECT_EQ(f.state(), State::Fault);
}

TEST(SimStateMachine, StoBlocksSwitchOnAndSetsBit8OnAkd2g) {
    AxisFixture f("akd2g");
    f.axis().set_sto(true);
    EXPECT_NE(f.statusword() & cia::sw::kManufacturer8, 0);
    EXPECT_NE(f.statusword() & cia::sw::kWarning, 0); // W9000
    f.controlword(0x06);
    f.controlword(0x07);
    EXPECT_EQ(f.state(), State::ReadyToSwitchOn);
    f.axis().set_sto(false);
    f.controlword(0x0F);
    EXPECT_EQ(f.state(), State::SwitchedOn);
}

TEST(SimStateMachine, StoWhileEnabledFaultsAndResetFailsUntilReleased) {
    AxisFixture f("akd2g");
    f.enable();
    f.axis().inject(FaultKind::Sto);
    f.run_ms(2);
    EXPECT_EQ(f.state(), State::Fault);
    EXPECT_EQ(f.od.get<std::uint16_t>(0x5004, 1).value_or(0), 0xFF0B);
    f.controlword(0x80);
    EXPECT_EQ(f.state(), State::Fault);
    f.axis().set_sto(false);
    f.controlword(0x00);
    f.controlword(0x80);
    EXPECT_EQ(f.state(), State::SwitchOnDisabled);
}

TEST(SimStateMachine, UnsupportedModeAndQuickStopOptionAreRefused) {
    AxisFixture f("akd2g");
    EXPECT_EQ(f.write<std::int8_t>(cia::obj::kModesOfOperation, 7).error(), SdoAbort::InvalidValue);
    EXPECT_EQ(f.write<std::int16_t>(cia::obj::kQuickStopOption, 3).error(), SdoAbort::InvalidValue);
    EXPECT_TRUE(f.write<std::int16_t>(cia::obj::kQuickStopOption, 5));
    EXPECT_EQ(f.write<std::int8_t>(cia::obj::kHomingMethod, 3).error(), SdoAbort::InvalidValue);
}

TEST(SimStateMachine, Akd2gSecondAxisLivesAtPlus0x800WithItsOwnStateMachine) {
    AxisFixture f("akd2g", 2);
    ASSERT_NE(f.od.find(0x6840), nullptr);
    ASSERT_NE(f.od.find(0x6D02), nullptr);
    ASSERT_NE(f.od.find(0x5102), nullptr);
    f.enable(1);
    EXPECT_EQ(f.state(1), State::OperationEnabled);
    EXPECT_EQ(f.state(0), State::SwitchOnDisabled);
    EXPECT_EQ(f.od.get<std::uint32_t>(0x6D02, 0), 0xADU);
}

TEST(SimStateMachine, PowerOnForgetsFaults) {
    AxisFixture f("akd2g");
    f.axis().inject(FaultKind::OverCurrent);
    f.run_ms(1);
    f.axis().power_on();
    EXPECT_EQ(f.state(), State::SwitchOnDisabled);
    EXPECT_TRUE(f.axis().faults().empty());
}
