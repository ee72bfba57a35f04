// SPDX-License-Identifier: Apache-2.0
// EventRateLimiter: a flood of one kind becomes its first sentence plus one summary per interval.
#include <codrive/core/event_rate_limiter.hpp>

#include <gtest/gtest.h>

#include <string>
#include <vector>

namespace codrive {
namespace {

constexpr const char* kKey = "node 3: TPDO1 (0x183) missing after SYNC";

struct Printed {
    std::vector<std::string> lines;
    EventRateLimiter::Sink sink() {
        return [this](std::string_view s) { lines.emplace_back(s); };
    }
};

std::string missing(int sync) {
    return std::string(kKey) + " " + std::to_string(sync) + " (expected every SYNC)";
}

TEST(EventRateLimiter, FloodOfOneKindPrintsFirstThenOneSummaryPerSecond) {
    FakeClock clock;
    Printed out;
    EventRateLimiter limiter(out.sink(), seconds(1));
    // 1 ms SYNC, the TPDO missing after every one for 2.5 s: 2,500 events.
    for (int i = 0; i < 2500; ++i) {
        limiter.offer(kKey, missing(i), clock.now());
        clock.advance(milliseconds(1));
        if (limiter.next_deadline() <= clock.now()) {
            limiter.on_tick(clock.now());
        }
    }
    ASSERT_EQ(out.lines.size(), 3U);
    EXPECT_EQ(out.lines[0], missing(0));
    EXPECT_EQ(out.lines[1], std::string(kKey) + " \u00d7999 in the last 1 s");
    EXPECT_EQ(out.lines[2], std::string(kKey) + " \u00d71000 in the last 1 s");
    // The last half second is summarised when the interval ends, and then the kind goes quiet.
    clock.advance(milliseconds(500));
    limiter.on_tick(clock.now());
    ASSERT_EQ(out.lines.size(), 4U);
    EXPECT_EQ(out.lines[3], std::string(kKey) + " \u00d7500 in the last 1 s");
    EXPECT_EQ(limiter.suppressed_total(), 2499U);
}

TEST(EventRateLimiter, OtherKindsAndNodesAreNotHiddenByAFlood) {
    FakeClock clock;
    Printed out;
    EventRateLimiter limiter(out.sink(), seconds(1));
    for (int i = 0; i < 100; ++i) {
        limiter.offer(kKey, missing(i), clock.now());
        clock.advance(milliseconds(1));
    }
    limiter.offer("node 4: heartbeat lost", "node 4: heartbeat lost after 300 ms", clock.now());
    limiter.offer("node 3: EMCY 0x2310", "node 3: EMCY 0x2310 (current)", clock.now());
    ASSERT_EQ(out.lines.size(), 3U);
    EXPECT_EQ(out.lines[1], "node 4: heartbeat lost after 300 ms");
    EXPECT_EQ(out.lines[2], "node 3: EMCY 0x2310 (current)");
}

TEST(EventRateLimiter, AnEventAfterAQuietIntervalIsPrintedInFull) {
    FakeClock clock;
    Printed out;
    EventRateLimiter limiter(out.sink(), seconds(1));
    limiter.offer(kKey, missing(1), clock.now());
    clock.advance(seconds(1));
    limiter.on_tick(clock.now()); // nothing suppressed: no summary, the kind is freed
    EXPECT_EQ(limiter.next_deadline(), kNever);
    clock.advance(seconds(3));
    limiter.offer(kKey, missing(4000), clock.now());
    ASSERT_EQ(out.lines.size(), 2U);
    EXPECT_EQ(out.lines[1], missing(4000));
}

TEST(EventRateLimiter, LateTickStillSummarisesBeforeTheNextEvent) {
    FakeClock clock;
    Printed out;
    EventRateLimiter limiter(out.sink(), seconds(1));
    limiter.offer(kKey, missing(1), clock.now());
    limiter.offer(kKey, missing(2), clock.now());
    clock.advance(milliseconds(1500)); // no on_tick() in between
    limiter.offer(kKey, missing(3), clock.now());
    ASSERT_EQ(out.lines.size(), 2U);
    EXPECT_EQ(out.lines[1], std::string(kKey) + " \u00d71 in the last 1.5 s");
    limiter.flush(clock.now() + milliseconds(200));
    ASSERT_EQ(out.lines.size(), 3U);
    EXPECT_EQ(out.lines[2], std::string(kKey) + " \u00d71 in the last 0.2 s");
}

TEST(EventRateLimiter, ZeroIntervalPassesEveryEvent) {
    FakeClock clock;
    Printed out;
    EventRateLimiter limiter(out.sink(), Duration::zero());
    for (int i = 0; i < 10; ++i) {
        limiter.offer(kKey, missing(i), clock.now());
    }
    EXPECT_EQ(out.lines.size(), 10U);
}

TEST(EventRateLimiter, MoreKindsThanSlotsArePassedOnNotDropped) {
    FakeClock clock;
    Printed out;
    EventRateLimiter limiter(out.sink(), seconds(1), 2);
    limiter.offer("a", "a", clock.now());
    limiter.offer("b", "b", clock.now());
    limiter.offer("c", "c1", clock.now());
    limiter.offer("c", "c2", clock.now());
    EXPECT_EQ(out.lines, (std::vector<std::string>{"a", "b", "c1", "c2"}));
}

} // namespace
} // namespace codrive
