// SPDX-License-Identifier: Apache-2.0
// SYNC consumer: missing SYNC, counter jumps and length errors against the real producer.
#include <codrive/core/virtual_bus.hpp>
#include <codrive/sync/consumer.hpp>
#include <codrive/sync/producer.hpp>

#include <gtest/gtest.h>

#include <vector>

namespace codrive::sync {
namespace {

class SyncConsumerTest : public ::testing::Test {
protected:
    FakeClock clock;
    VirtualNetwork net{clock};
    VirtualBus& master_bus = net.endpoint("master");
    VirtualBus& node_bus = net.endpoint("node");
    SyncProducer producer{master_bus};
    SyncConsumer consumer;
    std::vector<SyncEvent> events;

    void SetUp() override {
        node_bus.set_frame_handler(
            [this](const Frame& f, TimePoint t) { consumer.on_frame(f, t); });
        consumer.set_handler([this](const SyncEvent& e) { events.push_back(e); });
    }
    void run_for(Duration d) { net.run_until(clock, clock.now() + d, {&producer, &consumer}); }
};

TEST_F(SyncConsumerTest, CounterWrapIsNotAJump) {
    ASSERT_TRUE(producer.configure({milliseconds(1), 4, 0x80}));
    ASSERT_TRUE(consumer.configure({5, 0x80, milliseconds(1), 1.5, 4}));
    std::vector<std::uint8_t> counters;
    consumer.set_hook([&](const SyncReception& r) { counters.push_back(r.counter); });
    producer.start(clock.now());
    run_for(microseconds(9500));
    EXPECT_TRUE(events.empty());
    EXPECT_EQ(counters, (std::vector<std::uint8_t>{1, 2, 3, 4, 1, 2, 3, 4, 1, 2}));
    EXPECT_EQ(consumer.last_interval(), milliseconds(1));
}

TEST_F(SyncConsumerTest, MissingSyncIsReportedAfterTimeoutThenRecovered) {
    ASSERT_TRUE(producer.configure({milliseconds(1), 0, 0x80}));
    ASSERT_TRUE(consumer.configure({5, 0x80, milliseconds(1), 1.5, 0}));
    const TimePoint start = clock.now();
    producer.start(start);
    run_for(microseconds(2500)); // SYNC at 0, 1, 2 ms
    producer.stop();
    run_for(microseconds(999)); // up to 3.499 ms: still within 1.5 periods of the last
    EXPECT_TRUE(events.empty());
    run_for(microseconds(1));
    ASSERT_EQ(events.size(), 1U);
    EXPECT_EQ(events[0].kind, SyncEventKind::Missing);
    EXPECT_EQ(events[0].time, start + microseconds(3500));
    EXPECT_EQ(events[0].text,
              "node 5: SYNC missing: none for 1.5 ms (communication cycle period 1 ms)");
    EXPECT_TRUE(consumer.missing());
    producer.start(clock.now());
    run_for(microseconds(100));
    ASSERT_EQ(events.size(), 2U);
    EXPECT_EQ(events[1].kind, SyncEventKind::Recovered);
}

TEST_F(SyncConsumerTest, LostSyncShowsAsCounterJump) {
    ASSERT_TRUE(producer.configure({milliseconds(1), 10, 0x80}));
    ASSERT_TRUE(consumer.configure({5, 0x80, Duration{0}, 1.5, 10}));
    int n = 0;
    net.set_fault_filter([&](const std::string&, const Frame& f) {
        FaultAction a;
        a.drop = f.id == 0x80 && ++n == 3; // third SYNC (counter 3) lost
        return a;
    });
    producer.start(clock.now());
    run_for(microseconds(4500));
    ASSERT_EQ(events.size(), 1U);
    EXPECT_EQ(events[0].kind, SyncEventKind::CounterJump);
    EXPECT_EQ(events[0].counter, 4);
    EXPECT_EQ(events[0].expected, 3);
    EXPECT_EQ(events[0].text, "node 5: SYNC counter 4 after 2, expected 3");
}

TEST_F(SyncConsumerTest, UnexpectedLengthIsReported) {
    ASSERT_TRUE(consumer.configure({0, 0x80, Duration{0}, 1.5, 0}));
    ASSERT_TRUE(master_bus.send(Frame::make(0x80, {0x01})));
    net.deliver();
    ASSERT_EQ(events.size(), 1U);
    EXPECT_EQ(events[0].kind, SyncEventKind::LengthError);
    EXPECT_EQ(events[0].text, "SYNC with 1 data bytes, expected 0 (1019h = 0)");
    EXPECT_EQ(consumer.received(), 0U);
}

TEST_F(SyncConsumerTest, NoMonitoringWithoutCyclePeriod) {
    ASSERT_TRUE(consumer.configure({0, 0x80, Duration{0}, 1.5, 0}));
    ASSERT_TRUE(master_bus.send(Frame::make(0x80, std::span<const std::uint8_t>{})));
    net.deliver();
    EXPECT_EQ(consumer.next_deadline(), kNever);
    EXPECT_EQ(consumer.received(), 1U);
}

TEST_F(SyncConsumerTest, RejectsInvalidConfiguration) {
    EXPECT_FALSE(consumer.configure({0, 0x80, milliseconds(1), 0.5, 0}));
    EXPECT_FALSE(consumer.configure({0, 0x80, milliseconds(1), 1.5, 1}));
    EXPECT_FALSE(consumer.configure({0, 0x1000, milliseconds(1), 1.5, 0}));
}

} // namespace
} // namespace codrive::sync
