// SPDX-License-Identifier: Apache-2.0
// SYNC producer: absolute deadlines, counter, statistics and hook (CiA 301 §7.2.5).
#include <codrive/core/virtual_bus.hpp>
#include <codrive/sync/producer.hpp>

#include <gtest/gtest.h>

#include <random>
#include <vector>

namespace codrive::sync {
namespace {

class SyncProducerTest : public ::testing::Test {
protected:
    FakeClock clock;
    VirtualNetwork net{clock};
    VirtualBus& master_bus = net.endpoint("master");
    VirtualBus& node_bus = net.endpoint("node");
    SyncProducer producer{master_bus};
    std::vector<Frame> seen;

    void SetUp() override {
        node_bus.set_frame_handler([this](const Frame& f, TimePoint) { seen.push_back(f); });
    }
};

TEST_F(SyncProducerTest, RejectsInvalidConfiguration) {
    EXPECT_FALSE(producer.configure({Duration{0}, 0, 0x80}));
    EXPECT_FALSE(producer.configure({milliseconds(1), 1, 0x80}));
    EXPECT_FALSE(producer.configure({milliseconds(1), 241, 0x80}));
    EXPECT_FALSE(producer.configure({milliseconds(1), 0, 0x800}));
    EXPECT_TRUE(producer.configure({milliseconds(1), 240, 0x80}));
}

TEST_F(SyncProducerTest, WithoutCounterSendsDlcZero) {
    ASSERT_TRUE(producer.configure({milliseconds(1), 0, 0x80}));
    producer.start(clock.now());
    net.run_until(clock, clock.now() + microseconds(4500), {&producer});
    ASSERT_EQ(seen.size(), 5U); // 0, 1, 2, 3, 4 ms
    for (const auto& f : seen) {
        EXPECT_EQ(f.id, 0x80U);
        EXPECT_EQ(f.len, 0);
        EXPECT_FALSE(f.rtr());
    }
}

TEST_F(SyncProducerTest, CounterRunsFromOneToOverflowAndWraps) {
    ASSERT_TRUE(producer.configure({milliseconds(1), 3, 0x80}));
    producer.start(clock.now());
    net.run_until(clock, clock.now() + microseconds(6500), {&producer});
    ASSERT_EQ(seen.size(), 7U);
    const std::vector<std::uint8_t> expected{1, 2, 3, 1, 2, 3, 1};
    for (std::size_t i = 0; i < seen.size(); ++i) {
        EXPECT_EQ(seen[i].len, 1);
        EXPECT_EQ(seen[i].data[0], expected[i]) << "SYNC " << i;
    }
    EXPECT_EQ(producer.last_counter(), 1);
}

TEST_F(SyncProducerTest, LateTicksDoNotDrift) {
    ASSERT_TRUE(producer.configure({milliseconds(1), 0, 0x80}));
    const TimePoint start = clock.now();
    producer.start(start);
    std::mt19937 rng(42);
    std::uniform_int_distribution<int> late_us(0, 900);
    std::vector<TimePoint> ideals;
    producer.set_hook([&](const SyncInfo& info) { ideals.push_back(info.ideal); });
    Duration max_late{0};
    for (int k = 0; k < 1000; ++k) {
        const TimePoint deadline = producer.next_deadline();
        ASSERT_EQ(deadline, start + milliseconds(k)) << "cycle " << k;
        const Duration late = microseconds(late_us(rng));
        max_late = std::max(max_late, late);
        clock.set(deadline + late);
        producer.on_tick(clock.now());
    }
    EXPECT_EQ(producer.next_deadline(), start + milliseconds(1000));
    ASSERT_EQ(ideals.size(), 1000U);
    EXPECT_EQ(ideals.back(), start + milliseconds(999));
    EXPECT_EQ(producer.sent(), 1000U);
    EXPECT_EQ(producer.skipped(), 0U);
    const auto& stats = producer.period_error();
    EXPECT_EQ(stats.count(), 1000U);
    EXPECT_GE(stats.min(), Duration{0});
    EXPECT_EQ(stats.max(), max_late);
    EXPECT_GT(stats.mean(), microseconds(300));
    EXPECT_LT(stats.mean(), microseconds(600));
    EXPECT_LE(stats.p99(), microseconds(900));
}

TEST_F(SyncProducerTest, TickLaterThanAPeriodSkipsMissedSlots) {
    ASSERT_TRUE(producer.configure({milliseconds(1), 0, 0x80}));
    const TimePoint start = clock.now();
    producer.start(start);
    producer.on_tick(start);
    clock.set(start + microseconds(3500));
    producer.on_tick(clock.now()); // slot 1 sent late, slots 2 and 3 skipped
    EXPECT_EQ(producer.sent(), 2U);
    EXPECT_EQ(producer.skipped(), 2U);
    EXPECT_EQ(producer.next_deadline(), start + milliseconds(4));
}

TEST_F(SyncProducerTest, EarlyTickSendsNothing) {
    ASSERT_TRUE(producer.configure({milliseconds(1), 0, 0x80}));
    producer.start(clock.now() + milliseconds(1));
    producer.on_tick(clock.now());
    EXPECT_EQ(producer.sent(), 0U);
}

TEST_F(SyncProducerTest, HookSeesEverySyncWithCounterAndCycle) {
    ASSERT_TRUE(producer.configure({microseconds(500), 2, 0x80}));
    std::vector<SyncInfo> infos;
    producer.set_hook([&](const SyncInfo& i) { infos.push_back(i); });
    const TimePoint start = clock.now();
    producer.start(start);
    net.run_until(clock, start + microseconds(1600), {&producer});
    ASSERT_EQ(infos.size(), 4U);
    EXPECT_EQ(infos[3].cycle, 3U);
    EXPECT_EQ(infos[3].counter, 2);
    EXPECT_EQ(infos[3].ideal, start + microseconds(1500));
    EXPECT_EQ(infos[3].actual, infos[3].ideal);
}

TEST_F(SyncProducerTest, StopCancelsTheDeadline) {
    ASSERT_TRUE(producer.configure({milliseconds(1), 0, 0x80}));
    producer.start(clock.now());
    producer.stop();
    EXPECT_EQ(producer.next_deadline(), kNever);
}

TEST(PeriodStats, PercentilesOfKnownDistribution) {
    PeriodStats s(microseconds(1));
    for (int i = 1; i <= 100; ++i) {
        s.add(microseconds(i));
    }
    EXPECT_EQ(s.count(), 100U);
    EXPECT_EQ(s.min(), microseconds(1));
    EXPECT_EQ(s.max(), microseconds(100));
    EXPECT_EQ(s.p50(), microseconds(50));
    EXPECT_EQ(s.p99(), microseconds(99));
    EXPECT_EQ(s.mean(), nanoseconds(50500));
}

TEST(PeriodStats, NegativeValuesSortBelowPositiveOnes) {
    PeriodStats s(microseconds(1));
    s.add(microseconds(-5));
    s.add(microseconds(-5));
    s.add(microseconds(-300));
    s.add(milliseconds(500));
    EXPECT_EQ(s.min(), microseconds(-300));
    EXPECT_EQ(s.percentile(0.25), microseconds(-300));
    EXPECT_EQ(s.p50(), microseconds(-5));
    EXPECT_EQ(s.percentile(1.0), milliseconds(500));
    s.reset();
    EXPECT_EQ(s.count(), 0U);
    EXPECT_EQ(s.p99(), Duration{0});
}

TEST(PeriodStats, LargeValuesKeepRelativePrecision) {
    PeriodStats s(microseconds(1));
    for (int i = 0; i < 1000; ++i) {
        s.add(milliseconds(10) + microseconds(20 * i)); // 10 ms .. 29.98 ms
    }
    const double p50 = to_us(s.p50());
    const double p99 = to_us(s.p99());
    EXPECT_NEAR(p50, 19980.0, 19980.0 / 64);
    EXPECT_NEAR(p99, 29780.0, 29780.0 / 64);
    EXPECT_LE(s.p50(), s.p99());
}

TEST(PeriodStats, HoursAndNanosecondsFitTheSameHistogram) {
    PeriodStats s(microseconds(1));
    s.add(nanoseconds(10));
    s.add(std::chrono::hours(100));
    EXPECT_EQ(s.p50(), nanoseconds(10));
    EXPECT_EQ(s.max(), std::chrono::hours(100));
}

} // namespace
} // namespace codrive::sync
