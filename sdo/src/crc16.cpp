// SPDX-License-Identifier: Apache-2.0
// Table-driven CRC-16-CCITT for SDO block transfers.
#include <codrive/sdo/crc16.hpp>

#include <array>

namespace codrive::sdo {
namespace {

constexpr std::uint16_t kPolynomial = 0x1021;

constexpr std::array<std::uint16_t, 256> kTable = [] {
    std::array<std::uint16_t, 256> table{};
    for (unsigned byte = 0; byte < 256; ++byte) {
        auto crc = static_cast<std::uint16_t>(byte << 8);
        for (int bit = 0; bit < 8; ++bit) {
            crc = static_cast<std::uint16_t>((crc & 0x8000U) != 0 ? (crc << 1) ^ kPolynomial
                                                                  : crc << 1);
        }
        table[byte] = crc;
    }
    return table;
}();

} // namespace

std::uint16_t crc16_ccitt(std::span<const std::uint8_t> data, std::uint16_t crc) {
    for (const std::uint8_t b : data) {
        crc = static_cast<std::uint16_t>((crc << 8) ^ kTable[((crc >> 8) ^ b) & 0xFFU]);
    }
    return crc;
}

} // namespace codrive::sdo
