// SPDX-License-Identifier: Apache-2.0
// Heartbeat consumer and producer (CiA 301 §7.2.8.3.2) on the virtual bus.
#include <codrive/core/virtual_bus.hpp>
#include <codrive/nmt/heartbeat_consumer.hpp>
#include <codrive/nmt/heartbeat_producer.hpp>

#include <gtest/gtest.h>

#include <vector>

namespace codrive::nmt {
namespace {

using Kind = ErrorControlEventKind;

class HeartbeatTest : public ::testing::Test {
protected:
    FakeClock clock;
    VirtualNetwork net{clock};
    VirtualBus& master_bus = net.endpoint("master");
    VirtualBus& node_bus = net.endpoint("node2");
    HeartbeatConsumer consumer;
    HeartbeatProducer producer{node_bus, 2};
    std::vector<ErrorControlEvent> events;

    void SetUp() override {
        master_bus.set_frame_handler(
            [this](const Frame& f, TimePoint t) { consumer.on_frame(f, t); });
        consumer.set_handler([this](const ErrorControlEvent& e) { events.push_back(e); });
    }
    void heartbeat(std::uint8_t state) {
        ASSERT_TRUE(node_bus.send(Frame::make(0x702, {state})));
        net.deliver();
    }
    std::vector<Kind> kinds() const {
        std::vector<Kind> k;
        for (const auto& e : events) {
            k.push_back(e.kind);
        }
        return k;
    }
};

TEST_F(HeartbeatTest, LostExactlyAtConsumerTimeAndNotBefore) {
    ASSERT_TRUE(consumer.configure(2, milliseconds(250)));
    heartbeat(0x05);
    const TimePoint t0 = clock.now();
    events.clear();
    EXPECT_EQ(consumer.next_deadline(), t0 + milliseconds(250));
    net.run_until(clock, t0 + milliseconds(250) - nanoseconds(1), {&consumer});
    EXPECT_TRUE(events.empty());
    EXPECT_FALSE(consumer.lost(2));
    net.run_until(clock, t0 + milliseconds(250), {&consumer});
    ASSERT_EQ(events.size(), 1U);
    EXPECT_EQ(events[0].kind, Kind::HeartbeatLost);
    EXPECT_EQ(events[0].node, 2);
    EXPECT_EQ(events[0].time, t0 + milliseconds(250));
    EXPECT_EQ(events[0].state, NmtState::Operational);
    EXPECT_EQ(events[0].text, "node 2: heartbeat lost after 250 ms (consumer time 250 ms)");
    EXPECT_TRUE(consumer.lost(2));
    // Reported once per loss.
    net.run_until(clock, t0 + seconds(5), {&consumer});
    EXPECT_EQ(events.size(), 1U);
}

TEST_F(HeartbeatTest, LateTickReportsTheActualSilence) {
    ASSERT_TRUE(consumer.configure(2, milliseconds(250)));
    heartbeat(0x05);
    events.clear();
    clock.advance(milliseconds(300));
    consumer.on_tick(clock.now());
    ASSERT_EQ(events.size(), 1U);
    EXPECT_EQ(events[0].text, "node 2: heartbeat lost after 300 ms (consumer time 250 ms)");
}

TEST_F(HeartbeatTest, RegularHeartbeatsKeepTheNodeAlive) {
    ASSERT_TRUE(consumer.configure(2, milliseconds(150)));
    producer.set_state(NmtState::Operational);
    producer.set_period(milliseconds(100), clock.now());
    net.run_until(clock, clock.now() + seconds(2), {&consumer, &producer});
    EXPECT_EQ(kinds(), std::vector<Kind>{Kind::StateChanged});
    EXPECT_FALSE(consumer.lost(2));
    EXPECT_EQ(producer.sent(), 20U);
}

TEST_F(HeartbeatTest, RecoveredWhenHeartbeatsReturn) {
    ASSERT_TRUE(consumer.configure(2, milliseconds(100)));
    heartbeat(0x7F);
    net.run_until(clock, clock.now() + milliseconds(400), {&consumer});
    heartbeat(0x7F);
    ASSERT_EQ(kinds(), (std::vector<Kind>{Kind::StateChanged, Kind::HeartbeatLost,
                                          Kind::HeartbeatRecovered}));
    EXPECT_EQ(events[2].text, "node 2: heartbeat recovered after 400 ms (state pre-operational)");
    EXPECT_FALSE(consumer.lost(2));
}

TEST_F(HeartbeatTest, StateChangeIsReported) {
    ASSERT_TRUE(consumer.configure(2, milliseconds(100)));
    heartbeat(0x7F);
    heartbeat(0x7F);
    heartbeat(0x05);
    ASSERT_EQ(kinds(), (std::vector<Kind>{Kind::StateChanged, Kind::StateChanged}));
    EXPECT_EQ(events[1].text, "node 2: state changed from pre-operational to operational");
    EXPECT_EQ(events[1].state, NmtState::Operational);
}

TEST_F(HeartbeatTest, BootUpOfRunningNodeIsUnexpected) {
    ASSERT_TRUE(consumer.configure(2, milliseconds(100)));
    heartbeat(0x05);
    events.clear();
    heartbeat(0x00);
    ASSERT_EQ(kinds(), std::vector<Kind>{Kind::UnexpectedBootUp});
    EXPECT_EQ(events[0].text,
              "node 2: unexpected boot-up (the node was reset; it was operational)");
    // A rebooted node is not monitored until it produces heartbeats again: no spurious loss.
    net.run_until(clock, clock.now() + seconds(1), {&consumer});
    EXPECT_EQ(events.size(), 1U);
}

TEST_F(HeartbeatTest, FirstBootUpAndExpectedBootUpAreNormal) {
    ASSERT_TRUE(consumer.configure(2, milliseconds(100)));
    heartbeat(0x00);
    heartbeat(0x7F);
    consumer.expect_boot_up(2);
    heartbeat(0x00);
    EXPECT_EQ(kinds(), (std::vector<Kind>{Kind::BootUp, Kind::StateChanged, Kind::BootUp}));
    EXPECT_EQ(events[0].text, "node 2: boot-up");
}

TEST_F(HeartbeatTest, UnconfiguredNodesAndRtrAreIgnored) {
    ASSERT_TRUE(node_bus.send(Frame::make(0x703, {0x05})));
    ASSERT_TRUE(node_bus.send(Frame::make_rtr(0x702, 1)));
    net.deliver();
    EXPECT_TRUE(events.empty());
    EXPECT_EQ(consumer.next_deadline(), kNever);
}

TEST_F(HeartbeatTest, MalformedHeartbeatIsCounted) {
    ASSERT_TRUE(consumer.configure(2, milliseconds(100)));
    heartbeat(0x42);
    heartbeat(0x85); // toggle bit has no place in a heartbeat
    EXPECT_EQ(consumer.malformed(), 2U);
    EXPECT_TRUE(events.empty());
}

TEST_F(HeartbeatTest, Configure1016EntryDecodesNodeAndTime) {
    ASSERT_TRUE(consumer.configure_from_1016(0x000200FAU)); // node 2, 250 ms
    heartbeat(0x05);
    EXPECT_EQ(consumer.next_deadline(), clock.now() + milliseconds(250));
    EXPECT_FALSE(consumer.configure(0, milliseconds(10)));
}

TEST_F(HeartbeatTest, ZeroConsumerTimeReportsStateButNeverLoss) {
    ASSERT_TRUE(consumer.configure(2, milliseconds(0)));
    heartbeat(0x05);
    net.run_until(clock, clock.now() + seconds(1), {&consumer});
    EXPECT_EQ(kinds(), std::vector<Kind>{Kind::StateChanged});
}

TEST_F(HeartbeatTest, ProducerSendsBootUpThenStateOnAbsoluteGrid) {
    std::vector<std::pair<TimePoint, Frame>> seen;
    master_bus.set_frame_handler([&](const Frame& f, TimePoint t) { seen.emplace_back(t, f); });
    const TimePoint t0 = clock.now();
    ASSERT_TRUE(producer.send_boot_up());
    producer.set_period(milliseconds(100), t0);
    // Tick 30 ms late every time: the deadlines stay on t0 + k·100 ms.
    for (int k = 1; k <= 5; ++k) {
        clock.set(t0 + milliseconds(100 * k + 30));
        producer.on_tick(clock.now());
        EXPECT_EQ(producer.next_deadline(), t0 + milliseconds(100 * (k + 1)));
    }
    net.deliver();
    ASSERT_EQ(seen.size(), 6U);
    EXPECT_EQ(seen[0].second, Frame::make(0x702, {0x00}));
    EXPECT_EQ(seen[1].second, Frame::make(0x702, {0x7F}));
}

} // namespace
} // namespace codrive::nmt
