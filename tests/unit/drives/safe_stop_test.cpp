// SPDX-License-Identifier: Apache-2.0
// drives::safe_stop: quick stop, standstill, then disable voltage — never a disable that cuts
// the quick-stop ramp (the motor would coast), within the time budget (fake clock, 1 ms cycles).
#include "rig.hpp"

#include <codrive/drives/safe_stop.hpp>

#include <gtest/gtest.h>

#include <algorithm>

namespace codrive::drives::testing {
namespace {

using cia402::State;
using std::chrono::milliseconds;

/// Index of the first `value` in `log` at or after `from`, or log.size().
std::size_t find_from(const std::vector<std::uint16_t>& log, std::uint16_t value,
                      std::size_t from = 0) {
    const auto it = std::find(log.begin() + static_cast<std::ptrdiff_t>(from), log.end(), value);
    return static_cast<std::size_t>(it - log.begin());
}

DriveVoid run_safe_stop(Rig& rig, milliseconds budget, int max_cycles = 5000) {
    return rig.run(
        [&](Axis::Done d) {
            EXPECT_TRUE(safe_stop(rig.axis(), rig.clock.now() + budget, rig.clock, std::move(d)));
        },
        max_cycles);
}

// DS-BVS default 605Ah = 6 (DS-BVS §6.2.89): decelerate on the quick-stop ramp and stay in
// QUICK STOP ACTIVE, bit 10 set once halted (§6.2.81). Disable voltage only after that.
TEST(SafeStop, WaitsForStandstillInQuickStopActiveBeforeDisablingVoltage) {
    Rig rig(ds_bvs_profile());
    rig.dev.model(1).stop_ramp_cycles = 50; // 50 ms on the ramp
    rig.cycles(2);
    ASSERT_TRUE(rig.run([&](auto d) { rig.axis().enable(d); }));
    const std::size_t before = rig.dev.controlword_log(1).size();
    auto r = run_safe_stop(rig, milliseconds(1000));
    ASSERT_TRUE(r) << r.error().message;
    EXPECT_EQ(rig.axis().state(), State::SwitchOnDisabled);
    EXPECT_EQ(rig.dev.model(1).ramps_cut, 0) << "disable voltage cut the quick-stop ramp";
    const auto log = rig.dev.controlword_log(1);
    const std::size_t qs = find_from(log, 0x0002, before);
    ASSERT_LT(qs, log.size()) << "no quick stop (0x0002) sent";
    EXPECT_LT(find_from(log, 0x0000, qs), log.size()) << "no disable voltage after standstill";
}

// AKD2G default 605Ah = 2 (AKD2G §5.4.3): decelerate, then SWITCH ON DISABLED by itself.
TEST(SafeStop, LetsADriveWithOption2FinishItsRampIntoSwitchOnDisabled) {
    Rig rig(generic_profile()); // 605Ah = 2
    rig.dev.model(1).stop_ramp_cycles = 80;
    rig.cycles(2);
    ASSERT_TRUE(rig.run([&](auto d) { rig.axis().enable(d); }));
    auto r = run_safe_stop(rig, milliseconds(1000));
    ASSERT_TRUE(r) << r.error().message;
    EXPECT_EQ(rig.axis().state(), State::SwitchOnDisabled);
    EXPECT_EQ(rig.dev.model(1).ramps_cut, 0);
}

// The ramp is longer than the budget: cutting it would make the motor coast, so the quick stop
// stays commanded, no disable voltage goes out, and the caller learns why.
TEST(SafeStop, ABudgetShorterThanTheRampLeavesTheQuickStopCommandedAndSaysSo) {
    Rig rig(ds_bvs_profile());
    rig.dev.model(1).stop_ramp_cycles = 3000; // 3 s on the ramp, 1 s budget
    rig.cycles(2);
    ASSERT_TRUE(rig.run([&](auto d) { rig.axis().enable(d); }));
    const std::size_t before = rig.dev.controlword_log(1).size();
    const TimePoint t0 = rig.clock.now();
    auto r = run_safe_stop(rig, milliseconds(1000));
    ASSERT_FALSE(r);
    EXPECT_EQ(r.error().code, make_error_code(DriveErrc::Timeout));
    EXPECT_NE(r.error().message.find("still on its quick-stop ramp"), std::string::npos)
        << r.error().message;
    EXPECT_LE(rig.clock.now() - t0, milliseconds(1000));
    rig.cycles(20); // nothing further is sent after the sequence ended
    EXPECT_EQ(rig.axis().state(), State::QuickStopActive);
    EXPECT_EQ(rig.dev.model(1).ramps_cut, 0);
    const auto log = rig.dev.controlword_log(1);
    EXPECT_EQ(log.back(), 0x0002);
    EXPECT_EQ(find_from(log, 0x0000, before), log.size()) << "disable voltage during the ramp";
}

// An axis found in QUICK STOP ACTIVE may be on its ramp still: it gets the same wait.
TEST(SafeStop, AnAxisAlreadyInQuickStopActiveIsDisabledOnlyAtStandstill) {
    Rig rig(ds_bvs_profile());
    rig.dev.model(1).stop_ramp_cycles = 40;
    rig.cycles(2);
    ASSERT_TRUE(rig.run([&](auto d) { rig.axis().enable(d); }));
    rig.axis().quick_stop([](DriveVoid) {});
    rig.cycles(5); // the ramp has started
    ASSERT_EQ(rig.axis().state(), State::QuickStopActive);
    auto r = run_safe_stop(rig, milliseconds(1000));
    ASSERT_TRUE(r) << r.error().message;
    EXPECT_EQ(rig.axis().state(), State::SwitchOnDisabled);
    EXPECT_EQ(rig.dev.model(1).ramps_cut, 0);
}

// A drive that ignores the quick stop (stuck in OPERATION ENABLED): the disable is still tried
// with the rest of the budget, and the whole sequence keeps to the budget.
TEST(SafeStop, ADriveThatIgnoresTheQuickStopStillGetsDisableVoltageWithinTheBudget) {
    Rig rig(ds_bvs_profile());
    rig.cycles(2);
    ASSERT_TRUE(rig.run([&](auto d) { rig.axis().enable(d); }));
    rig.dev.model(1).stuck = true;
    const TimePoint t0 = rig.clock.now();
    auto r = run_safe_stop(rig, milliseconds(1000));
    ASSERT_FALSE(r);
    EXPECT_LE(rig.clock.now() - t0, milliseconds(1002));
    EXPECT_EQ(rig.dev.controlword_log(1).back(), 0x0000) << "disable voltage not tried";
}

// 605Ah = 0 (disable drive function): the drive goes to SWITCH ON DISABLED at once, which the
// drive's own configuration chose; the sequence ends there.
TEST(SafeStop, Option0EndsInSwitchOnDisabledAtOnce) {
    Rig rig(ds_bvs_profile());
    rig.cycles(2);
    ASSERT_TRUE(rig.dev.od().set<std::int16_t>(0x605A, 0, 0));
    ASSERT_TRUE(rig.run([&](auto d) { rig.axis().enable(d); }));
    auto r = run_safe_stop(rig, milliseconds(1000), 20);
    ASSERT_TRUE(r) << r.error().message;
    EXPECT_EQ(rig.axis().state(), State::SwitchOnDisabled);
}

} // namespace
} // namespace codrive::drives::testing
