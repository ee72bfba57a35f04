// SPDX-License-Identifier: Apache-2.0
// How many bit times a frame occupies on the bus: the one truth for every bus-load figure.
#pragma once

#include <codrive/core/frame.hpp>

#include <cstdint>

namespace codrive::dump {

/// Bits a frame occupies on the bus in the worst case of bit stuffing, including the 3-bit
/// interframe space: classic 11-bit 47 + 8n + ⌊(34 + 8n − 1)/4⌋, 29-bit 67 + 8n + ⌊(54 + 8n −
/// 1)/4⌋ (Davis et al., "Controller Area Network (CAN) schedulability analysis", 2007).
[[nodiscard]] std::uint32_t frame_bits_worst_case(const Frame& f);

/// Bits a classic frame occupies on the bus with its real stuff bits, including the 3-bit
/// interframe space. The frame is laid out as ISO 11898-1 §10.4 sends it (SOF, identifier, RTR or
/// SRR/IDE/identifier extension/RTR, reserved bits, DLC, data, 15-bit CRC with polynomial 0x4599),
/// a stuff bit is counted after every five equal bits from SOF to the end of the CRC (§10.5, the
/// stuff bit itself starts the next run), and the unstuffed tail (CRC delimiter, ACK slot and
/// delimiter, 7-bit EOF, 3-bit intermission) adds 13. The result lies between 47 + 8n and
/// frame_bits_worst_case(). A remote frame sends no data whatever its DLC. CAN FD frames have a
/// different layout and a second bit rate; they are counted with frame_bits_worst_case() at the
/// arbitration rate (an estimate).
[[nodiscard]] std::uint32_t frame_bits_exact(const Frame& f);

} // namespace codrive::dump
