// SPDX-License-Identifier: Apache-2.0
// The timer-latency probe's summary and verdict (`codrive latency`), from given lateness
// samples: no clock, no sleeping. The measuring loop itself runs in the integration suite.
#include <codrive/controller/timer_probe.hpp>

#include <gtest/gtest.h>

#include <vector>

namespace codrive::controller {
namespace {

std::vector<Duration> samples(std::size_t n, Duration each) {
    return std::vector<Duration>(n, each);
}

TEST(TimerProbe, QuantilesAreTakenFromTheSortedSamples) {
    std::vector<Duration> v;
    for (int i = 1000; i >= 1; --i) { // 1..1000 us, out of order
        v.push_back(microseconds(i));
    }
    const auto r = summarize_lateness(v, milliseconds(10), 0);
    EXPECT_EQ(r.wakeups, 1000U);
    EXPECT_EQ(r.p50, microseconds(500));
    EXPECT_EQ(r.p99, microseconds(990));
    EXPECT_EQ(r.p999, microseconds(999));
    EXPECT_EQ(r.max, microseconds(1000));
    EXPECT_EQ(r.late_half_cycle, 0U);
    EXPECT_EQ(r.verdict(), TimerVerdict::Sound);
}

TEST(TimerProbe, AWakeUpWithinHalfACycleIsSound) {
    auto v = samples(999, microseconds(60));
    v.push_back(microseconds(499)); // just under half of 1 ms
    const auto r = summarize_lateness(v, milliseconds(1), 0);
    EXPECT_EQ(r.verdict(), TimerVerdict::Sound);
    const std::string text = r.to_string();
    EXPECT_NE(text.find("timer latency: 1000 wake-ups at a 1000 us cycle"), std::string::npos)
        << text;
    EXPECT_NE(text.find("lateness: p50 60 us, p99 60 us, p99.9 60 us, max 499 us; 0 wake-up(s) "
                        "half a cycle late or more, 0 a whole cycle or more (0 slot(s) skipped)"),
              std::string::npos)
        << text;
    EXPECT_NE(text.find("verdict: sound for a 1000 us cycle"), std::string::npos) << text;
}

TEST(TimerProbe, HalfACycleLateIsJitteryButSkipsNothing) {
    auto v = samples(999, microseconds(60));
    v.push_back(microseconds(500));
    const auto r = summarize_lateness(v, milliseconds(1), 0);
    EXPECT_EQ(r.late_half_cycle, 1U);
    EXPECT_EQ(r.late_whole_cycle, 0U);
    EXPECT_EQ(r.verdict(), TimerVerdict::Jittery);
    const std::string text = r.to_string();
    EXPECT_NE(text.find("verdict: jittery for a 1000 us cycle: no slot would be skipped, but "
                        "wake-ups came up to 500 us late"),
              std::string::npos)
        << text;
}

TEST(TimerProbe, AWholeCycleLateSaysHowManySlotsAMasterWouldSkip) {
    // What this project's 2-vCPU VM did to a 1 ms sleeper (docs/reliability.md, session 22).
    auto v = samples(9990, microseconds(80));
    v.push_back(microseconds(14100));
    v.push_back(microseconds(9000));
    const auto r = summarize_lateness(v, milliseconds(1), 14 + 9);
    EXPECT_EQ(r.late_whole_cycle, 2U);
    EXPECT_EQ(r.verdict(), TimerVerdict::SkipsCycles);
    const std::string text = r.to_string();
    EXPECT_NE(text.find("max 14.1 ms; 2 wake-up(s) half a cycle late or more, 2 a whole cycle or "
                        "more (23 slot(s) skipped)"),
              std::string::npos)
        << text;
    EXPECT_NE(text.find("verdict: not sound for a 1000 us cycle: a cyclic master here would have "
                        "skipped 23 slot(s), the worst wake-up 14.1 ms late; use a cycle and slave "
                        "watchdog well above 14.1 ms"),
              std::string::npos)
        << text;
}

TEST(TimerProbe, StallsBeyondASecondAreKeptExactlyAsTheMaximum) {
    auto v = samples(990, microseconds(70));
    for (int i = 0; i < 10; ++i) {
        v.push_back(milliseconds(2500) + microseconds(i));
    }
    const auto r = summarize_lateness(v, milliseconds(1), 25000);
    EXPECT_EQ(r.p99, microseconds(70));
    EXPECT_EQ(r.p999, milliseconds(2500) + microseconds(9)) << "past the bins: the maximum";
    EXPECT_EQ(r.max, milliseconds(2500) + microseconds(9));
    EXPECT_EQ(r.late_whole_cycle, 10U);
}

TEST(TimerProbe, HalfACycleIsComparedExactlyNotToTheMicrosecond) {
    // 1001 us cycle: half is 500.5 us. 500.4 us is within it, 500.5 us is not.
    std::vector<Duration> v{nanoseconds(500'400)};
    EXPECT_EQ(summarize_lateness(v, microseconds(1001), 0).verdict(), TimerVerdict::Sound);
    v.push_back(nanoseconds(500'500));
    EXPECT_EQ(summarize_lateness(v, microseconds(1001), 0).verdict(), TimerVerdict::Jittery);
}

TEST(TimerProbe, NoSamplesIsZeroNotACrash) {
    std::vector<Duration> none;
    const auto r = summarize_lateness(none, milliseconds(1), 0);
    EXPECT_EQ(r.wakeups, 0U);
    EXPECT_EQ(r.max, Duration::zero());
    EXPECT_EQ(r.verdict(), TimerVerdict::Sound);
}

} // namespace
} // namespace codrive::controller
