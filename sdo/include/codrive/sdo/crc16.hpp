// SPDX-License-Identifier: Apache-2.0
// CRC-16-CCITT as used by SDO block transfers (CiA 301 §7.2.4.3.16).
#pragma once

#include <cstdint>
#include <span>

namespace codrive::sdo {

/// CRC-16 with polynomial x^16 + x^12 + x^5 + 1 (0x1021), initial value 0, no reflection, no
/// final XOR — the CRC CiA 301 specifies for block transfers. Feed data in pieces by passing
/// the previous result as `crc`; crc16_ccitt("123456789") == 0x31C3.
[[nodiscard]] std::uint16_t crc16_ccitt(std::span<const std::uint8_t> data, std::uint16_t crc = 0);

} // namespace codrive::sdo
