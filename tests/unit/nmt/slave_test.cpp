// SPDX-License-Identifier: Apache-2.0
// NMT slave state machine driven by the NMT master over the virtual bus.
#include <codrive/core/virtual_bus.hpp>
#include <codrive/nmt/heartbeat_consumer.hpp>
#include <codrive/nmt/heartbeat_producer.hpp>
#include <codrive/nmt/master.hpp>
#include <codrive/nmt/slave.hpp>

#include <gtest/gtest.h>

#include <vector>

namespace codrive::nmt {
namespace {

class NmtSlaveTest : public ::testing::Test {
protected:
    FakeClock clock;
    VirtualNetwork net{clock};
    VirtualBus& master_bus = net.endpoint("master");
    VirtualBus& node_bus = net.endpoint("node4");
    NmtMaster master{master_bus};
    NmtSlave slave{4};
    HeartbeatProducer heartbeat{node_bus, 4};
    HeartbeatConsumer consumer;
    std::vector<NmtCommand> resets;
    std::vector<ErrorControlEvent> events;

    void SetUp() override {
        node_bus.set_frame_handler([this](const Frame& f, TimePoint t) { slave.on_frame(f, t); });
        master_bus.set_frame_handler([this](const Frame& f, TimePoint t) {
            master.on_frame(f, t);
            consumer.on_frame(f, t);
        });
        slave.set_state_handler([this](NmtState, NmtState to) { heartbeat.set_state(to); });
        slave.set_reset_handler([this](NmtCommand c) {
            resets.push_back(c);
            slave.boot_up();
            ASSERT_TRUE(heartbeat.send_boot_up());
        });
        consumer.set_handler([this](const ErrorControlEvent& e) { events.push_back(e); });
        ASSERT_TRUE(consumer.configure(4, milliseconds(150)));
        slave.boot_up();
        ASSERT_TRUE(heartbeat.send_boot_up());
        heartbeat.set_period(milliseconds(100), clock.now());
    }
    void run_for(Duration d) { net.run_until(clock, clock.now() + d, {&heartbeat, &consumer}); }
};

TEST_F(NmtSlaveTest, CommandsMoveTheNodeThroughItsStates) {
    run_for(milliseconds(150));
    EXPECT_EQ(master.states().state(4), NmtState::PreOperational);
    ASSERT_TRUE(master.start(4));
    run_for(milliseconds(100));
    EXPECT_EQ(slave.state(), NmtState::Operational);
    EXPECT_TRUE(slave.pdo_allowed());
    EXPECT_EQ(master.states().state(4), NmtState::Operational);
    ASSERT_TRUE(master.stop(kAllNodes));
    run_for(milliseconds(100));
    EXPECT_EQ(slave.state(), NmtState::Stopped);
    EXPECT_FALSE(slave.sdo_allowed());
    EXPECT_EQ(master.states().state(4), NmtState::Stopped);
    ASSERT_TRUE(master.enter_pre_operational(4));
    run_for(milliseconds(100));
    EXPECT_EQ(master.states().state(4), NmtState::PreOperational);
}

TEST_F(NmtSlaveTest, CommandsForOtherNodesAreIgnored) {
    ASSERT_TRUE(master.start(5));
    run_for(milliseconds(10));
    EXPECT_EQ(slave.state(), NmtState::PreOperational);
}

TEST_F(NmtSlaveTest, ExpectedResetGivesBootUpNotUnexpected) {
    ASSERT_TRUE(master.start(4));
    run_for(milliseconds(250));
    events.clear();
    consumer.expect_boot_up(4);
    ASSERT_TRUE(master.reset_communication(4));
    run_for(milliseconds(250));
    ASSERT_EQ(resets, std::vector<NmtCommand>{NmtCommand::ResetCommunication});
    EXPECT_EQ(slave.state(), NmtState::PreOperational);
    ASSERT_FALSE(events.empty());
    EXPECT_EQ(events[0].kind, ErrorControlEventKind::BootUp);
}

TEST_F(NmtSlaveTest, ResetNotAnnouncedToConsumerIsUnexpected) {
    ASSERT_TRUE(master.start(4));
    run_for(milliseconds(250));
    events.clear();
    ASSERT_TRUE(master.reset_node(kAllNodes));
    run_for(milliseconds(10));
    ASSERT_FALSE(events.empty());
    EXPECT_EQ(events[0].kind, ErrorControlEventKind::UnexpectedBootUp);
    EXPECT_EQ(events[0].text,
              "node 4: unexpected boot-up (the node was reset; it was operational)");
}

TEST_F(NmtSlaveTest, MalformedNmtFramesAreCounted) {
    ASSERT_TRUE(master_bus.send(Frame::make(0x000, {0x07, 0x04})));
    run_for(milliseconds(1));
    EXPECT_EQ(slave.malformed(), 1U);
    EXPECT_EQ(slave.state(), NmtState::PreOperational);
}

} // namespace
} // namespace codrive::nmt
