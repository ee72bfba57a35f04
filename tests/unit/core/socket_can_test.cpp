// SPDX-License-Identifier: Apache-2.0
// SocketCAN pieces that need no interface: error-frame decoding and clear open errors.
#include <codrive/core/can_interface.hpp>
#include <codrive/core/socket_can_bus.hpp>

#include <gtest/gtest.h>
#include <linux/can/error.h>

using namespace codrive;

TEST(ErrorFrame, BusOffDecodes) {
    Frame f;
    f.flags = Frame::kError;
    f.id = CAN_ERR_BUSOFF;
    f.len = 8;
    auto events = decode_error_frame(f);
    ASSERT_EQ(events.size(), 1U);
    EXPECT_EQ(events[0].kind, BusEvent::Kind::StateChanged);
    EXPECT_EQ(events[0].state, BusState::BusOff);
}

TEST(ErrorFrame, ControllerPassiveWithCounters) {
    Frame f;
    f.flags = Frame::kError;
    f.id = CAN_ERR_CRTL | CAN_ERR_CNT;
    f.len = 8;
    f.data[1] = CAN_ERR_CRTL_TX_PASSIVE;
    f.data[6] = 128;
    f.data[7] = 3;
    auto events = decode_error_frame(f);
    ASSERT_EQ(events.size(), 1U);
    EXPECT_EQ(events[0].state, BusState::ErrorPassive);
    EXPECT_EQ(to_string(events[0]), "bus state error-passive (tx errors 128, rx errors 3)");
}

TEST(ErrorFrame, WarningOverflowProtocolAckRestart) {
    Frame f;
    f.flags = Frame::kError;
    f.id = CAN_ERR_CRTL | CAN_ERR_PROT | CAN_ERR_ACK | CAN_ERR_RESTARTED;
    f.len = 8;
    f.data[1] = CAN_ERR_CRTL_RX_WARNING | CAN_ERR_CRTL_RX_OVERFLOW;
    f.data[2] = CAN_ERR_PROT_STUFF;
    auto events = decode_error_frame(f);
    ASSERT_EQ(events.size(), 5U);
    EXPECT_EQ(events[0].kind, BusEvent::Kind::ControllerProblem);
    EXPECT_EQ(events[1].state, BusState::ErrorWarning);
    EXPECT_EQ(events[2].kind, BusEvent::Kind::ProtocolError);
    EXPECT_EQ(events[2].detail, "stuff error");
    EXPECT_EQ(events[3].kind, BusEvent::Kind::NoAck);
    EXPECT_EQ(events[4].kind, BusEvent::Kind::Restarted);
}

TEST(SocketCanBus, OpeningAMissingInterfaceSaysWhy) {
    auto bus = SocketCanBus::open("nosuchcan9");
    ASSERT_FALSE(bus);
    // Without SocketCAN in the kernel the error says so; with it, the interface is missing.
    const bool expected =
        bus.error() == CoreErrc::NoSocketCan || bus.error() == CoreErrc::NoSuchInterface;
    EXPECT_TRUE(expected) << bus.error().message();
    EXPECT_EQ(socketcan_available(), bus.error() != CoreErrc::NoSocketCan);
}

TEST(CanInterface, MissingInterfaceIsNamed) {
    CanInterface iface("nosuchcan9");
    EXPECT_FALSE(iface.exists());
    auto info = iface.info();
    ASSERT_FALSE(info);
    EXPECT_EQ(describe_interface_error("nosuchcan9", "read state", info.error()),
              "nosuchcan9: cannot read state: no such network interface (check `ip link show`)");
}

// The location byte is named as linux/can/error.h names it; a transceiver status is in hex.
TEST(ErrorFrame, ProtocolErrorLocationIsNamedAndTransceiverStatusIsHex) {
    Frame f;
    f.flags = Frame::kError;
    f.id = CAN_ERR_PROT | CAN_ERR_TRX;
    f.len = 8;
    f.data[2] = CAN_ERR_PROT_FORM | CAN_ERR_PROT_TX;
    f.data[3] = CAN_ERR_PROT_LOC_ACK_DEL;
    f.data[4] = CAN_ERR_TRX_CANL_SHORT_TO_GND;
    auto events = decode_error_frame(f);
    ASSERT_EQ(events.size(), 2U);
    EXPECT_EQ(events[0].detail, "form error on transmission in the ACK delimiter");
    EXPECT_EQ(events[1].detail, "status 0x70");
    f.data[3] = 0x1F; // not a location linux/can/error.h defines
    EXPECT_EQ(decode_error_frame(f).at(0).detail, "form error on transmission (location 0x1F)");
}
