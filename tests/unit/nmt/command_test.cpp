// SPDX-License-Identifier: Apache-2.0
// NMT command frames, the NMT master and the node state table.
#include <codrive/core/virtual_bus.hpp>
#include <codrive/nmt/command.hpp>
#include <codrive/nmt/master.hpp>

#include <gtest/gtest.h>

#include <vector>

namespace codrive::nmt {
namespace {

TEST(NmtCommand, FramesCarryCommandSpecifierAndNode) {
    struct Case {
        NmtCommand command;
        std::uint8_t cs;
    };
    for (const auto& c :
         {Case{NmtCommand::Start, 0x01}, Case{NmtCommand::Stop, 0x02},
          Case{NmtCommand::EnterPreOperational, 0x80}, Case{NmtCommand::ResetNode, 0x81},
          Case{NmtCommand::ResetCommunication, 0x82}}) {
        auto f = make_command_frame(c.command, 5);
        ASSERT_TRUE(f);
        EXPECT_EQ(f->id, 0x000U);
        EXPECT_EQ(f->len, 2);
        EXPECT_FALSE(f->rtr());
        EXPECT_EQ(f->data[0], c.cs);
        EXPECT_EQ(f->data[1], 5);
        auto back = parse_command_frame(*f);
        ASSERT_TRUE(back);
        EXPECT_EQ(back->command, c.command);
        EXPECT_EQ(back->node, 5);
    }
}

TEST(NmtCommand, NodeZeroAddressesAllNodes) {
    auto f = make_command_frame(NmtCommand::ResetCommunication, kAllNodes);
    ASSERT_TRUE(f);
    EXPECT_EQ(f->data[1], 0);
}

TEST(NmtCommand, RejectsNodeIdAbove127) {
    auto f = make_command_frame(NmtCommand::Start, 128);
    ASSERT_FALSE(f);
    EXPECT_EQ(f.error(), make_error_code(CoreErrc::InvalidArgument));
}

TEST(NmtCommand, ParseRejectsShortFramesAndUnknownSpecifiers) {
    EXPECT_FALSE(parse_command_frame(Frame::make(0x000, {0x01})));
    EXPECT_FALSE(parse_command_frame(Frame::make(0x000, {0x03, 0x01})));
    EXPECT_FALSE(parse_command_frame(Frame::make(0x001, {0x01, 0x01})));
    EXPECT_FALSE(parse_command_frame(Frame::make(0x000, {0x01, 0x80})));
}

TEST(NmtCommand, CliNamesMapToCommands) {
    EXPECT_EQ(command_from_name("start"), NmtCommand::Start);
    EXPECT_EQ(command_from_name("stop"), NmtCommand::Stop);
    EXPECT_EQ(command_from_name("preop"), NmtCommand::EnterPreOperational);
    EXPECT_EQ(command_from_name("reset"), NmtCommand::ResetNode);
    EXPECT_EQ(command_from_name("reset-comm"), NmtCommand::ResetCommunication);
    EXPECT_FALSE(command_from_name("boot"));
    EXPECT_EQ(to_string(NmtCommand::ResetCommunication), "reset communication");
}

TEST(NmtState, DecodesStateBytesIgnoringToggle) {
    EXPECT_EQ(state_from_byte(0x00), NmtState::BootUp);
    EXPECT_EQ(state_from_byte(0x04), NmtState::Stopped);
    EXPECT_EQ(state_from_byte(0x85), NmtState::Operational);
    EXPECT_EQ(state_from_byte(0xFF), NmtState::PreOperational);
    EXPECT_FALSE(state_from_byte(0x06));
    EXPECT_EQ(to_string(NmtState::PreOperational), "pre-operational");
}

class NmtMasterTest : public ::testing::Test {
protected:
    FakeClock clock;
    VirtualNetwork net{clock};
    VirtualBus& master_bus = net.endpoint("master");
    VirtualBus& node_bus = net.endpoint("node");
    std::vector<Frame> at_node;
    NmtMaster master{master_bus};

    void SetUp() override {
        node_bus.set_frame_handler([this](const Frame& f, TimePoint) { at_node.push_back(f); });
        master_bus.set_frame_handler(
            [this](const Frame& f, TimePoint t) { master.on_frame(f, t); });
    }
};

TEST_F(NmtMasterTest, SendsCommandsOnTheBus) {
    ASSERT_TRUE(master.start(3));
    ASSERT_TRUE(master.stop(kAllNodes));
    ASSERT_TRUE(master.enter_pre_operational(4));
    net.deliver();
    ASSERT_EQ(at_node.size(), 3U);
    EXPECT_EQ(at_node[0], Frame::make(0x000, {0x01, 0x03}));
    EXPECT_EQ(at_node[1], Frame::make(0x000, {0x02, 0x00}));
    EXPECT_EQ(at_node[2], Frame::make(0x000, {0x80, 0x04}));
    EXPECT_EQ(master.commands_sent(), 3U);
}

TEST_F(NmtMasterTest, InvalidNodeIsRefusedWithoutSending) {
    EXPECT_FALSE(master.start(200));
    net.deliver();
    EXPECT_TRUE(at_node.empty());
}

TEST_F(NmtMasterTest, StateTableFollowsBootUpAndHeartbeats) {
    EXPECT_EQ(master.states().state(7), NmtState::Unknown);
    ASSERT_TRUE(node_bus.send(Frame::make(0x707, {0x00})));
    net.deliver();
    EXPECT_EQ(master.states().state(7), NmtState::BootUp);
    EXPECT_EQ(master.states().entry(7).boot_ups, 1U);
    ASSERT_TRUE(node_bus.send(Frame::make(0x707, {0x7F})));
    net.deliver();
    EXPECT_EQ(master.states().state(7), NmtState::PreOperational);
    ASSERT_TRUE(node_bus.send(Frame::make(0x707, {0x85}))); // guard reply, toggle set
    net.deliver();
    EXPECT_EQ(master.states().state(7), NmtState::Operational);
    EXPECT_EQ(master.states().entry(7).messages, 3U);
}

TEST_F(NmtMasterTest, ResetMarksNodeUnknownUntilBootUp) {
    ASSERT_TRUE(node_bus.send(Frame::make(0x702, {0x05})));
    net.deliver();
    ASSERT_TRUE(master.reset_node(2));
    EXPECT_EQ(master.states().state(2), NmtState::Unknown);
}

TEST_F(NmtMasterTest, MalformedErrorControlFramesAreCountedNotApplied) {
    ASSERT_TRUE(node_bus.send(Frame::make(0x702, {0x05})));
    ASSERT_TRUE(node_bus.send(Frame::make(0x702, {0x33})));
    ASSERT_TRUE(node_bus.send(Frame::make(0x702, std::span<const std::uint8_t>{})));
    net.deliver();
    EXPECT_EQ(master.states().state(2), NmtState::Operational);
    EXPECT_EQ(master.states().malformed(), 2U);
}

} // namespace
} // namespace codrive::nmt
