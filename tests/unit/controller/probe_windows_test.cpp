// SPDX-License-Identifier: Apache-2.0
// The timer probe's windows (`codrive latency --window`): which slots each window holds, when a
// window counts as complete for the thread that reports it, which one is the worst, and the
// memory bound of many windows. From given wake-ups: no clock, no sleeping.
#include "../../../controller/src/probe_recorder.hpp"

#include <gtest/gtest.h>

namespace codrive::controller {
namespace {

using detail::ProbeRecorder;

/// Wake-ups at a 1 ms cycle for `duration`, each 50 us late, except the one at `stall_at`,
/// `stall` late (the slots it passed are skipped, as the probe does).
void run(ProbeRecorder& r, Duration duration, Duration stall_at = Duration::zero(),
         Duration stall = Duration::zero()) {
    const Duration cycle = milliseconds(1);
    for (Duration slot = cycle; slot <= duration; slot += cycle) {
        const Duration late = slot == stall_at ? stall : microseconds(50);
        const auto missed = late >= cycle ? static_cast<std::uint64_t>(late / cycle) : 0U;
        r.add(slot, late, missed);
        slot += cycle * static_cast<long>(missed);
    }
    r.finish(duration);
}

TEST(ProbeWindows, EachWindowHoldsItsSlotsAndTheStallNamesTheWorst) {
    ProbeRecorder r(milliseconds(1), milliseconds(300), milliseconds(100));
    run(r, milliseconds(300), milliseconds(150), microseconds(2500));
    const TimerLatency s = r.summary();
    ASSERT_EQ(s.windows.size(), 3U);
    EXPECT_EQ(s.windows[0].wakeups, 100U) << "the slot at 100 ms ends the first window";
    EXPECT_EQ(s.windows[1].wakeups, 98U) << "two slots skipped by the stall";
    EXPECT_EQ(s.windows[1].skipped_slots, 2U);
    EXPECT_EQ(s.windows[2].wakeups, 100U);
    EXPECT_EQ(s.windows[0].max, microseconds(50));
    EXPECT_EQ(s.windows[1].max, microseconds(2500));
    EXPECT_EQ(s.windows[1].from, milliseconds(100));
    EXPECT_EQ(s.windows[1].to, milliseconds(200));
    EXPECT_EQ(s.wakeups, 298U);
    EXPECT_EQ(s.skipped_slots, 2U);
    ASSERT_NE(s.worst_window(), nullptr);
    EXPECT_EQ(s.worst_window()->number, 2U);
    const std::string text = s.to_string();
    EXPECT_NE(text.find("worst of 3 windows: window 2 (0.1-0.2 s): 98 wake-ups, max 2.5 ms, 1 "
                        "half a cycle late or more, 2 slot(s) skipped\nverdict: not sound"),
              std::string::npos)
        << text;
}

TEST(ProbeWindows, AWindowIsCompleteOnlyOnceTheNextOneHasAWakeUp) {
    ProbeRecorder r(milliseconds(1), milliseconds(300), milliseconds(100));
    r.add(milliseconds(100), microseconds(10), 0);
    EXPECT_EQ(r.windows_done(), 0U) << "the slot at 100 ms still belongs to the first window";
    r.add(milliseconds(101), microseconds(10), 0);
    EXPECT_EQ(r.windows_done(), 1U);
    EXPECT_EQ(r.window(0).wakeups, 1U);
    r.add(milliseconds(250), microseconds(10), 0);
    EXPECT_EQ(r.windows_done(), 2U) << "the second window ends when the third has a wake-up";
    EXPECT_EQ(r.window(1).wakeups, 1U);
    r.finish(milliseconds(300));
    EXPECT_EQ(r.windows_done(), 3U);
}

TEST(ProbeWindows, AStallLongerThanAWindowLeavesThatWindowEmptyNotLost) {
    ProbeRecorder r(milliseconds(1), milliseconds(400), milliseconds(100));
    r.add(milliseconds(99), microseconds(10), 0);
    // The wake-up for the slot at 100 ms comes 150 ms late: 150 slots skipped, the next
    // wake-up is for the slot at 251 ms. The second window has none of its own.
    r.add(milliseconds(100), milliseconds(150), 150);
    r.add(milliseconds(251), microseconds(10), 0);
    EXPECT_EQ(r.windows_done(), 2U);
    r.finish(milliseconds(400));
    const TimerLatency s = r.summary();
    ASSERT_EQ(s.windows.size(), 4U);
    EXPECT_EQ(s.windows[0].skipped_slots, 150U) << "counted where the late wake-up was due";
    EXPECT_EQ(s.windows[1].wakeups, 0U);
    EXPECT_EQ(s.windows[1].max, Duration::zero());
    EXPECT_EQ(s.windows[2].wakeups, 1U);
    EXPECT_EQ(s.worst_window()->number, 1U);
}

TEST(ProbeWindows, WithoutStallsTheWorstIsTheLatestWakeUpAndTheLastWindowMayBeShorter) {
    ProbeRecorder r(milliseconds(1), milliseconds(250), milliseconds(100));
    run(r, milliseconds(250), milliseconds(220), microseconds(400));
    const TimerLatency s = r.summary();
    ASSERT_EQ(s.windows.size(), 3U);
    EXPECT_EQ(s.windows[2].to, milliseconds(250));
    EXPECT_EQ(s.windows[2].wakeups, 50U);
    EXPECT_EQ(s.worst_window()->number, 3U);
    EXPECT_EQ(s.verdict(), TimerVerdict::Sound);
}

TEST(ProbeWindows, WindowsTooShortForTheRunAreWidenedNotAllocatedByTheBillion) {
    ProbeRecorder r(milliseconds(1), seconds(3600), microseconds(1));
    r.finish(seconds(3600));
    const TimerLatency s = r.summary();
    EXPECT_EQ(s.windows.size(), ProbeRecorder::kMaxWindows);
    EXPECT_EQ(s.windows[0].to - s.windows[0].from, milliseconds(36));
}

TEST(ProbeWindows, ARunStoppedEarlyEndsItsLastWindowThereAndLeavesTheRestOut) {
    ProbeRecorder r(milliseconds(1), milliseconds(300), milliseconds(100));
    run(r, milliseconds(150)); // Ctrl-C at 150 ms
    const TimerLatency s = r.summary();
    ASSERT_EQ(s.windows.size(), 2U) << "the third window was never reached";
    EXPECT_EQ(s.windows[1].from, milliseconds(100));
    EXPECT_EQ(s.windows[1].to, milliseconds(150));
    EXPECT_EQ(s.windows[1].wakeups, 50U);
    EXPECT_EQ(s.wakeups, 150U);
}

TEST(ProbeWindows, NoWindowsNoWorstLine) {
    ProbeRecorder r(milliseconds(1), milliseconds(100), Duration::zero());
    run(r, milliseconds(100));
    const TimerLatency s = r.summary();
    EXPECT_TRUE(s.windows.empty());
    EXPECT_EQ(s.worst_window(), nullptr);
    EXPECT_EQ(s.to_string().find("worst"), std::string::npos);
    EXPECT_EQ(s.wakeups, 100U);
}

} // namespace
} // namespace codrive::controller
