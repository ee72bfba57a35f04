// SPDX-License-Identifier: Apache-2.0
// Axis power state machine: enable from every state, every command's controlword, the fault
// reset edge, quick stop, readable timeouts, cyclic and SDO-polled operation.
#include "rig.hpp"

#include <gtest/gtest.h>

#include <algorithm>

namespace codrive::drives::testing {
namespace {

using cia402::State;

bool contains(const std::vector<std::uint16_t>& log, std::initializer_list<std::uint16_t> seq) {
    return std::search(log.begin(), log.end(), seq.begin(), seq.end()) != log.end();
}

TEST(Axis, EnableFromSwitchOnDisabledStepsThroughTransitions2To4) {
    Rig rig(generic_profile());
    rig.cycles(3);
    ASSERT_EQ(rig.axis().state(), State::SwitchOnDisabled);
    auto r = rig.run([&](auto done) { rig.axis().enable(done); });
    ASSERT_TRUE(r.has_value()) << r.error().message;
    EXPECT_EQ(rig.axis().state(), State::OperationEnabled);
    EXPECT_TRUE(contains(rig.dev.controlword_log(1), {0x0006, 0x0007, 0x000F}));
}

class EnableFrom : public ::testing::TestWithParam<State> {};

TEST_P(EnableFrom, EveryStartStateReachesOperationEnabled) {
    Rig rig(ds_bvs_profile()); // 605Ah = 6: quick stop stays in QUICK STOP ACTIVE
    rig.cycles(2);
    // Hold the device in the start state for one cycle so the axis sees it.
    rig.dev.model(1).stuck = true;
    rig.dev.model(1).state = GetParam();
    rig.cycles(1);
    rig.dev.model(1).stuck = false;
    const auto before = rig.dev.controlword_log(1).size();
    auto r = rig.run([&](auto done) { rig.axis().enable(done); });
    ASSERT_TRUE(r.has_value()) << r.error().message;
    EXPECT_EQ(rig.axis().state(), State::OperationEnabled);
    if (GetParam() == State::QuickStopActive) { // transition 16
        const auto log = rig.dev.controlword_log(1);
        ASSERT_EQ(log.size(), before + 1);
        EXPECT_EQ(log.back(), 0x000F);
    }
}

INSTANTIATE_TEST_SUITE_P(States, EnableFrom,
                         ::testing::Values(State::NotReadyToSwitchOn, State::SwitchOnDisabled,
                                           State::ReadyToSwitchOn, State::SwitchedOn,
                                           State::OperationEnabled, State::QuickStopActive,
                                           State::FaultReactionActive, State::Fault));

TEST(Axis, CommandsSendTheirControlwords) {
    Rig rig(generic_profile());
    rig.cycles(2);
    ASSERT_TRUE(rig.run([&](auto d) { rig.axis().enable(d); }));
    ASSERT_TRUE(rig.run([&](auto d) { rig.axis().switch_on(d); })); // 5: disable operation
    EXPECT_EQ(rig.axis().state(), State::SwitchedOn);
    EXPECT_EQ(rig.dev.controlword_log(1).back(), 0x0007);
    ASSERT_TRUE(rig.run([&](auto d) { rig.axis().shutdown(d); })); // 6
    EXPECT_EQ(rig.axis().state(), State::ReadyToSwitchOn);
    EXPECT_EQ(rig.dev.controlword_log(1).back(), 0x0006);
    ASSERT_TRUE(rig.run([&](auto d) { rig.axis().disable(d); })); // 7
    EXPECT_EQ(rig.axis().state(), State::SwitchOnDisabled);
    EXPECT_EQ(rig.dev.controlword_log(1).back(), 0x0000);
    ASSERT_TRUE(rig.run([&](auto d) { rig.axis().enable(d); }));
    ASSERT_TRUE(rig.run([&](auto d) { rig.axis().shutdown(d); })); // 8
    EXPECT_EQ(rig.axis().state(), State::ReadyToSwitchOn);
    ASSERT_TRUE(rig.run([&](auto d) { rig.axis().enable(d); }));
    ASSERT_TRUE(rig.run([&](auto d) { rig.axis().disable(d); })); // 9
    EXPECT_EQ(rig.axis().state(), State::SwitchOnDisabled);
}

TEST(Axis, QuickStopEndsInQuickStopActiveOrSwitchOnDisabledPerOptionCode) {
    Rig keep(ds_bvs_profile()); // 605Ah = 6
    keep.cycles(2);
    ASSERT_TRUE(keep.run([&](auto d) { keep.axis().enable(d); }));
    ASSERT_TRUE(keep.run([&](auto d) { keep.axis().quick_stop(d); }));
    EXPECT_EQ(keep.axis().state(), State::QuickStopActive);
    EXPECT_EQ(keep.dev.controlword_log(1).back(), 0x0002);

    Rig drop(generic_profile()); // 605Ah = 2: ramp, then SWITCH ON DISABLED
    drop.cycles(2);
    ASSERT_TRUE(drop.run([&](auto d) { drop.axis().enable(d); }));
    ASSERT_TRUE(drop.run([&](auto d) { drop.axis().quick_stop(d); }));
    drop.cycles(3);
    EXPECT_EQ(drop.axis().state(), State::SwitchOnDisabled);
}

TEST(Axis, FaultResetIsARisingEdgeOfBit7ThenBit7IsCleared) {
    Rig rig(generic_profile());
    rig.cycles(2);
    ASSERT_TRUE(rig.run([&](auto d) { rig.axis().enable(d); }));
    rig.dev.trigger_fault(1, 0x8611);
    rig.cycles(3);
    ASSERT_EQ(rig.axis().state(), State::Fault);
    rig.dev.model(1).fault_cause = false;
    ASSERT_TRUE(rig.run([&](auto d) { rig.axis().fault_reset(d); }));
    EXPECT_EQ(rig.axis().state(), State::SwitchOnDisabled);
    const auto log = rig.dev.controlword_log(1);
    const auto edge = std::find_if(log.begin(), log.end(), [](auto v) { return (v & 0x80) != 0; });
    ASSERT_NE(edge, log.end());
    ASSERT_NE(edge, log.begin());
    EXPECT_EQ(*edge, 0x0080);
    EXPECT_EQ(*(edge - 1) & 0x80, 0); // bit 7 was low on the wire before: a rising edge
    rig.cycles(2);
    EXPECT_EQ(rig.axis().controlword() & 0x80, 0);
    EXPECT_EQ(rig.dev.controlword_log(1).back() & 0x80, 0);
}

TEST(Axis, FaultResetFailsReadablyWhileTheCauseIsPresent) {
    Rig rig(akd2g_profile());
    rig.cycles(2);
    rig.dev.trigger_fault(1, 0x8611);
    rig.axis().note_error_code(0x8611);
    rig.cycles(3);
    auto r = rig.run([&](auto d) { rig.axis().fault_reset(d); });
    ASSERT_FALSE(r.has_value());
    EXPECT_EQ(r.error().code, DriveErrc::Timeout);
    EXPECT_EQ(r.error().message,
              "node 5 axis 1: fault reset timed out in FAULT: the drive is in FAULT: error code "
              "0x8611 (F6001 Following error magnitude fault); fault reset (controlword bit 7) "
              "did not clear it, the cause is probably still present");
}

TEST(Axis, EnableTimeoutNamesStoOnAkd2g) {
    Rig rig(akd2g_profile());
    rig.dev.model(1).sto = true;
    rig.cycles(2);
    auto r = rig.run([&](auto d) { rig.axis().enable(d); });
    ASSERT_FALSE(r.has_value());
    EXPECT_EQ(r.error().code, DriveErrc::Timeout);
    EXPECT_EQ(r.error().message,
              "node 5 axis 1: enable timed out in READY TO SWITCH ON: STO active (statusword bit "
              "8)");
}

TEST(Axis, EnableTimeoutNamesMissingBusVoltage) {
    Rig rig(akd2g_profile());
    rig.dev.model(1).voltage = false;
    rig.cycles(2);
    auto r = rig.run([&](auto d) { rig.axis().enable(d); });
    ASSERT_FALSE(r.has_value());
    EXPECT_EQ(r.error().message, "node 5 axis 1: enable timed out in READY TO SWITCH ON: no DC "
                                 "bus voltage (statusword bit 4 clear)");
}

TEST(Axis, EnableTimeoutNamesMissingRemote) {
    Rig rig(akd2g_profile());
    rig.cycles(2);
    rig.dev.model(1).remote = false; // WorkBench took control: the drive ignores 6040h
    rig.dev.model(1).stuck = true;
    auto r = rig.run([&](auto d) { rig.axis().enable(d); });
    ASSERT_FALSE(r.has_value());
    EXPECT_NE(r.error().message.find("enable timed out in SWITCH ON DISABLED: the drive is "
                                     "not under fieldbus control (statusword bit 9 remote is 0"),
              std::string::npos)
        << r.error().message;
}

TEST(Axis, StuckInNotReadyToSwitchOnIsReported) {
    FakeDevice dev(generic_profile(), 1);
    FakeTransport tr(dev);
    tr.map_input(0x6041, 0);
    AxisConfig cfg;
    cfg.timeout = std::chrono::milliseconds(50);
    Axis axis(tr, cfg);
    std::optional<DriveVoid> result;
    axis.enable([&](DriveVoid r) { result = r; });
    FakeClock clock;
    // The device never steps: its statusword stays 0 = NOT READY TO SWITCH ON.
    for (int i = 0; i < 100 && !result; ++i) {
        clock.advance(std::chrono::milliseconds(1));
        axis.on_cycle(clock.now());
    }
    ASSERT_TRUE(result.has_value());
    ASSERT_FALSE(result->has_value());
    EXPECT_EQ(result->error().message, "node 5 axis 1: enable timed out in NOT READY TO SWITCH "
                                       "ON: the drive is still initialising (NOT READY TO "
                                       "SWITCH ON)");
}

TEST(Axis, WorksWithoutProcessDataBySdoPolling) {
    Rig rig(generic_profile(), /*cyclic_io=*/false);
    rig.cycles(5);
    EXPECT_EQ(rig.axis().state(), State::SwitchOnDisabled);
    ASSERT_TRUE(rig.run([&](auto d) { rig.axis().enable(d); }));
    EXPECT_EQ(rig.dev.model(1).state, State::OperationEnabled);
    EXPECT_GT(rig.tr.reads(), 0U);
    EXPECT_TRUE(contains(rig.dev.controlword_log(1), {0x0006, 0x0007, 0x000F}));
    ASSERT_TRUE(rig.run([&](auto d) { rig.axis().set_mode(cia402::Mode::ProfilePosition, d); }));
    auto r = rig.run([&](auto d) { rig.axis().move_to(1000, {}, d); });
    ASSERT_TRUE(r.has_value()) << r.error().message;
    EXPECT_EQ(rig.dev.model(1).position, 1000);
}

TEST(Axis, NewOperationCancelsTheRunningOne) {
    Rig rig(akd2g_profile());
    rig.dev.model(1).sto = true;
    rig.cycles(2);
    std::optional<DriveVoid> first;
    rig.axis().enable([&](DriveVoid r) { first = r; });
    rig.cycles(5);
    ASSERT_TRUE(rig.run([&](auto d) { rig.axis().disable(d); }));
    ASSERT_TRUE(first.has_value());
    EXPECT_EQ(first->error().code, DriveErrc::Cancelled);
    EXPECT_EQ(first->error().message, "node 5 axis 1: enable cancelled by disable");
}

TEST(Axis, StateChangesAreReported) {
    Rig rig(generic_profile());
    std::vector<State> seen;
    rig.axis().on_state_change([&](State, State to) { seen.push_back(to); });
    rig.cycles(2);
    ASSERT_TRUE(rig.run([&](auto d) { rig.axis().enable(d); }));
    const std::vector<State> want{State::SwitchOnDisabled, State::ReadyToSwitchOn,
                                  State::SwitchedOn, State::OperationEnabled};
    EXPECT_EQ(seen, want);
}

TEST(Axis, DualAxisAkd2gAxesHaveTheirOwnStateMachines) {
    Rig rig(akd2g_profile(), true, 2);
    rig.cycles(2);
    rig.dev.model(2).sto = true;
    ASSERT_TRUE(rig.run([&](auto d) { rig.axis(1).enable(d); }));
    EXPECT_EQ(rig.axis(1).state(), State::OperationEnabled);
    EXPECT_EQ(rig.axis(2).state(), State::SwitchOnDisabled);
    auto r = rig.run([&](auto d) { rig.axis(2).enable(d); });
    ASSERT_FALSE(r.has_value());
    EXPECT_EQ(r.error().message, "node 5 axis 2: enable timed out in READY TO SWITCH ON: STO "
                                 "active (statusword bit 8)");
    EXPECT_EQ(rig.axis(2).index(0x6040), 0x6840);
    EXPECT_EQ(rig.dev.od().get<std::uint16_t>(0x6840, 0), 0x0007);
    EXPECT_EQ(rig.dev.od().get<std::uint16_t>(0x6040, 0), 0x000F);
}

} // namespace
} // namespace codrive::drives::testing
