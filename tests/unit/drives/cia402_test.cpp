// SPDX-License-Identifier: Apache-2.0
// CiA 402 constants: state decoding for every statusword pattern and every transition's command.
#include <codrive/drives/cia402.hpp>

#include <gtest/gtest.h>

#include <array>

namespace codrive::drives::cia402 {
namespace {

// Expected state from the CiA 402 "state coding" table, written bit by bit.
State expected_state(unsigned s) {
    const bool rtso = (s & 0x01) != 0;
    const bool so = (s & 0x02) != 0;
    const bool oe = (s & 0x04) != 0;
    const bool f = (s & 0x08) != 0;
    const bool qs = (s & 0x20) != 0;
    const bool sod = (s & 0x40) != 0;
    if (!sod && !f && !oe && !so && !rtso) {
        return State::NotReadyToSwitchOn;
    }
    if (sod && !f && !oe && !so && !rtso) {
        return State::SwitchOnDisabled;
    }
    if (!sod && qs && !f && !oe && !so && rtso) {
        return State::ReadyToSwitchOn;
    }
    if (!sod && qs && !f && !oe && so && rtso) {
        return State::SwitchedOn;
    }
    if (!sod && qs && !f && oe && so && rtso) {
        return State::OperationEnabled;
    }
    if (!sod && !qs && !f && oe && so && rtso) {
        return State::QuickStopActive;
    }
    if (!sod && f && oe && so && rtso) {
        return State::FaultReactionActive;
    }
    if (!sod && f && !oe && !so && !rtso) {
        return State::Fault;
    }
    return State::Unknown;
}

TEST(Cia402, DecodesEveryStatuswordPattern) {
    for (unsigned v = 0; v <= 0xFFFF; ++v) {
        ASSERT_EQ(decode_state(static_cast<std::uint16_t>(v)), expected_state(v & 0x7F))
            << "statusword 0x" << std::hex << v;
    }
}

TEST(Cia402, StateBitsRoundTrip) {
    for (State s : {State::NotReadyToSwitchOn, State::SwitchOnDisabled, State::ReadyToSwitchOn,
                    State::SwitchedOn, State::OperationEnabled, State::QuickStopActive,
                    State::FaultReactionActive, State::Fault}) {
        EXPECT_EQ(decode_state(state_bits(s)), s) << to_string(s);
        EXPECT_EQ(decode_state(static_cast<std::uint16_t>(state_bits(s) | 0xFF90)), s);
    }
}

struct TransitionCase {
    int transition;
    Command command;
    std::uint16_t controlword;
};

// CiA 402 transitions with the controlword the master sends (bits 0-3, 7).
constexpr std::array<TransitionCase, 15> kTransitions{{
    {2, Command::Shutdown, 0x0006},
    {3, Command::SwitchOn, 0x0007},
    {4, Command::EnableOperation, 0x000F},
    {5, Command::DisableOperation, 0x0007},
    {6, Command::Shutdown, 0x0006},
    {7, Command::DisableVoltage, 0x0000},
    {7, Command::QuickStop, 0x0002},
    {8, Command::Shutdown, 0x0006},
    {9, Command::DisableVoltage, 0x0000},
    {10, Command::DisableVoltage, 0x0000},
    {10, Command::QuickStop, 0x0002},
    {11, Command::QuickStop, 0x0002},
    {12, Command::DisableVoltage, 0x0000},
    {15, Command::FaultReset, 0x0080},
    {16, Command::EnableOperation, 0x000F},
}};

TEST(Cia402, EveryTransitionHasItsControlword) {
    for (const auto& t : kTransitions) {
        EXPECT_EQ(command_bits(t.command), t.controlword) << "transition " << t.transition;
        auto decoded = decode_command(t.controlword);
        ASSERT_TRUE(decoded.has_value()) << "transition " << t.transition;
        // 0x07 means switch on or disable operation, 0x0F enable operation (or 3+4).
        EXPECT_EQ(command_bits(*decoded), t.controlword) << "transition " << t.transition;
    }
}

TEST(Cia402, DecodeCommandIgnoresDontCareBits) {
    EXPECT_EQ(decode_command(0x000B), Command::QuickStop);       // AKD2G quick stop 0x0B
    EXPECT_EQ(decode_command(0x010F), Command::EnableOperation); // with halt
    EXPECT_EQ(decode_command(0x001F), Command::EnableOperation); // PP new set-point
    EXPECT_EQ(decode_command(0x0085), Command::FaultReset);
    EXPECT_EQ(decode_command(0x000D), Command::DisableVoltage);
    EXPECT_EQ(decode_command(0x000E), Command::Shutdown);
}

TEST(Cia402, ModeNamesAndSupportedBits) {
    EXPECT_EQ(mode_name(8), "cyclic synchronous position (CSP)");
    EXPECT_EQ(mode_name(-3), "manufacturer mode -3");
    EXPECT_EQ(supported_mode_bit(Mode::CyclicSyncTorque), 1U << 9);
    EXPECT_EQ(supported_mode_bit(Mode::Homing), 1U << 5);
    EXPECT_EQ(to_string(State::SwitchOnDisabled), "SWITCH ON DISABLED");
}

} // namespace
} // namespace codrive::drives::cia402
