// SPDX-License-Identifier: Apache-2.0
// Node guarding and life guarding (CiA 301 §7.2.8.3.1) on the virtual bus.
#include <codrive/core/virtual_bus.hpp>
#include <codrive/nmt/node_guarding.hpp>

#include <gtest/gtest.h>

#include <vector>

namespace codrive::nmt {
namespace {

using Kind = ErrorControlEventKind;

class NodeGuardingTest : public ::testing::Test {
protected:
    FakeClock clock;
    VirtualNetwork net{clock};
    VirtualBus& master_bus = net.endpoint("master");
    VirtualBus& node_bus = net.endpoint("node3");
    NodeGuardingMaster guard{master_bus};
    NodeGuardingResponder responder{node_bus, 3};
    std::vector<ErrorControlEvent> master_events;
    std::vector<ErrorControlEvent> node_events;
    std::vector<Frame> replies;

    void SetUp() override {
        net.set_recording(true);
        master_bus.set_frame_handler([this](const Frame& f, TimePoint t) {
            replies.push_back(f);
            guard.on_frame(f, t);
        });
        node_bus.set_frame_handler(
            [this](const Frame& f, TimePoint t) { responder.on_frame(f, t); });
        guard.set_handler([this](const ErrorControlEvent& e) { master_events.push_back(e); });
        responder.set_handler([this](const ErrorControlEvent& e) { node_events.push_back(e); });
        responder.set_state(NmtState::Operational);
    }
    void run_for(Duration d) { net.run_until(clock, clock.now() + d, {&guard, &responder}); }
    std::vector<Kind> kinds() const {
        std::vector<Kind> k;
        for (const auto& e : master_events) {
            k.push_back(e.kind);
        }
        return k;
    }
};

TEST_F(NodeGuardingTest, RepliesAlternateToggleStartingAtZero) {
    ASSERT_TRUE(guard.add(3, milliseconds(100), 3, clock.now()));
    run_for(milliseconds(350));
    ASSERT_EQ(replies.size(), 4U); // RTRs at 0, 100, 200, 300 ms
    EXPECT_EQ(replies[0].data[0], 0x05);
    EXPECT_EQ(replies[1].data[0], 0x85);
    EXPECT_EQ(replies[2].data[0], 0x05);
    EXPECT_EQ(replies[3].data[0], 0x85);
    EXPECT_EQ(kinds(), std::vector<Kind>{Kind::StateChanged});
    EXPECT_EQ(guard.stats(3).requests, 4U);
    EXPECT_EQ(guard.stats(3).replies, 4U);
    EXPECT_EQ(guard.state(3), NmtState::Operational);
}

TEST_F(NodeGuardingTest, RequestIsAnRtrOn700PlusNode) {
    ASSERT_TRUE(guard.add(3, milliseconds(100), 3, clock.now()));
    guard.on_tick(clock.now());
    net.deliver();
    ASSERT_FALSE(net.recorded().empty());
    const Frame& rtr = net.recorded().front();
    EXPECT_TRUE(rtr.rtr());
    EXPECT_EQ(rtr.id, 0x703U);
}

TEST_F(NodeGuardingTest, ToggleErrorIsReportedAndNotCountedAsReply) {
    ASSERT_TRUE(guard.add(3, milliseconds(100), 3, clock.now()));
    run_for(milliseconds(150));
    responder.corrupt_next_toggle();
    run_for(milliseconds(100));
    ASSERT_EQ(kinds(), (std::vector<Kind>{Kind::StateChanged, Kind::GuardToggleError}));
    EXPECT_EQ(master_events[1].node, 3);
    EXPECT_EQ(master_events[1].text,
              "node 3: node guarding toggle error (expected toggle bit 0, got 1)");
    EXPECT_EQ(guard.stats(3).toggle_errors, 1U);
    // The responder's own toggle kept alternating, so the master resynchronises at once.
    run_for(milliseconds(500));
    EXPECT_EQ(guard.stats(3).toggle_errors, 2U);
    EXPECT_FALSE(guard.timed_out(3));
}

TEST_F(NodeGuardingTest, MissingRepliesTimeOutAfterLifeTime) {
    ASSERT_TRUE(guard.add(3, milliseconds(100), 3, clock.now()));
    run_for(milliseconds(50));
    const TimePoint last_reply = clock.now() - milliseconds(50);
    node_bus.set_connected(false);
    run_for(milliseconds(249));
    EXPECT_EQ(kinds(), std::vector<Kind>{Kind::StateChanged});
    run_for(milliseconds(1));
    ASSERT_EQ(kinds(), (std::vector<Kind>{Kind::StateChanged, Kind::GuardTimeout}));
    EXPECT_EQ(master_events[1].time, last_reply + milliseconds(300));
    EXPECT_EQ(master_events[1].text, "node 3: node guarding timeout: no valid reply for 300 ms "
                                     "(guard time 100 ms x life time factor 3)");
    EXPECT_TRUE(guard.timed_out(3));
    EXPECT_GE(guard.stats(3).missed, 2U);
    node_bus.set_connected(true);
    run_for(milliseconds(200));
    ASSERT_EQ(kinds().back(), Kind::GuardRecovered);
    EXPECT_FALSE(guard.timed_out(3));
}

TEST_F(NodeGuardingTest, BootUpRestartsToggleAndIsUnexpected) {
    ASSERT_TRUE(guard.add(3, milliseconds(100), 3, clock.now()));
    run_for(milliseconds(150)); // two replies: toggle 0, 1
    ASSERT_TRUE(node_bus.send(Frame::make(0x703, {0x00})));
    responder.reset_toggle();
    run_for(milliseconds(300));
    EXPECT_EQ(guard.stats(3).toggle_errors, 0U);
    ASSERT_GE(master_events.size(), 2U);
    EXPECT_EQ(master_events[1].kind, Kind::UnexpectedBootUp);
}

TEST_F(NodeGuardingTest, InvalidConfigurationIsRefused) {
    EXPECT_FALSE(guard.add(0, milliseconds(100), 3, clock.now()));
    EXPECT_FALSE(guard.add(3, milliseconds(0), 3, clock.now()));
    EXPECT_FALSE(guard.add(3, milliseconds(100), 0, clock.now()));
    EXPECT_EQ(guard.next_deadline(), kNever);
}

TEST_F(NodeGuardingTest, LifeGuardingDetectsMissingRequests) {
    responder.set_life_guarding(milliseconds(100), 2);
    ASSERT_TRUE(guard.add(3, milliseconds(100), 2, clock.now()));
    run_for(milliseconds(450));
    EXPECT_TRUE(node_events.empty());
    const TimePoint last_rtr = clock.now() - milliseconds(50);
    guard.remove(3);
    run_for(milliseconds(149));
    EXPECT_TRUE(node_events.empty());
    run_for(milliseconds(1));
    ASSERT_EQ(node_events.size(), 1U);
    EXPECT_EQ(node_events[0].kind, Kind::LifeGuardLost);
    EXPECT_EQ(node_events[0].time, last_rtr + milliseconds(200));
    EXPECT_EQ(node_events[0].text, "node 3: life guarding: no guard request from the NMT master "
                                   "for 200 ms (guard time 100 ms x life time factor 2)");
    EXPECT_TRUE(responder.life_guard_lost());
    ASSERT_TRUE(guard.add(3, milliseconds(100), 2, clock.now()));
    run_for(milliseconds(10));
    ASSERT_EQ(node_events.size(), 2U);
    EXPECT_EQ(node_events[1].kind, Kind::LifeGuardRecovered);
}

TEST_F(NodeGuardingTest, LifeGuardingStartsOnlyWithFirstRequest) {
    responder.set_life_guarding(milliseconds(100), 2);
    run_for(seconds(2));
    EXPECT_TRUE(node_events.empty());
}

} // namespace
} // namespace codrive::nmt
