// SPDX-License-Identifier: Apache-2.0
// PDO layouts per mode that fit one 8-byte CAN frame per direction, shared by the profiles.
#pragma once

#include <codrive/drives/profile.hpp>

#include <array>

namespace codrive::drives::layouts {

using cia402::Mode;

// Receive PDOs (master → drive): controlword and the mode's set-point. 6060h stays out on
// purpose: an RPDO sent before the master knows the active mode would write 0 (no mode) into it;
// mode changes go over SDO and are confirmed by 6061h, which the TPDOs carry.
inline constexpr std::array<PdoEntry, 2> kRxPosition{{{0x6040, 0, 16}, {0x607A, 0, 32}}};
inline constexpr std::array<PdoEntry, 2> kRxVelocity{{{0x6040, 0, 16}, {0x60FF, 0, 32}}};
inline constexpr std::array<PdoEntry, 2> kRxTorque{{{0x6040, 0, 16}, {0x6071, 0, 16}}};
inline constexpr std::array<PdoEntry, 1> kRxHoming{{{0x6040, 0, 16}}};
inline constexpr std::array<PdoEntry, 2> kRxInterpolated{{{0x6040, 0, 16}, {0x60C1, 1, 32}}};

// Transmit PDOs (drive → master): statusword, the mode's actual value, mode display.
inline constexpr std::array<PdoEntry, 3> kTxPosition{
    {{0x6041, 0, 16}, {0x6064, 0, 32}, {0x6061, 0, 8}}};
inline constexpr std::array<PdoEntry, 3> kTxVelocity{
    {{0x6041, 0, 16}, {0x606C, 0, 32}, {0x6061, 0, 8}}};
inline constexpr std::array<PdoEntry, 3> kTxTorque{
    {{0x6041, 0, 16}, {0x6077, 0, 16}, {0x6061, 0, 8}}};

inline constexpr ModeLayout pp{Mode::ProfilePosition, kRxPosition, kTxPosition, 0};
inline constexpr ModeLayout pv{Mode::ProfileVelocity, kRxVelocity, kTxVelocity, 0};
inline constexpr ModeLayout pt{Mode::ProfileTorque, kRxTorque, kTxTorque, 0};
inline constexpr ModeLayout hm{Mode::Homing, kRxHoming, kTxPosition, 0};
inline constexpr ModeLayout ip{Mode::InterpolatedPosition, kRxInterpolated, kTxPosition, 0};
inline constexpr ModeLayout csp{Mode::CyclicSyncPosition, kRxPosition, kTxPosition, 0};
inline constexpr ModeLayout csv{Mode::CyclicSyncVelocity, kRxVelocity, kTxVelocity, 0};
inline constexpr ModeLayout cst{Mode::CyclicSyncTorque, kRxTorque, kTxTorque, 0};

} // namespace codrive::drives::layouts
