// SPDX-License-Identifier: Apache-2.0
// Sync manager and FMMU register records (ET1100 datasheet §2 register 0x0600 and 0x0800).
#include <codrive/ethercat/registers.hpp>

#include <codrive/core/endian.hpp>

namespace codrive::ethercat {

std::array<std::uint8_t, 8> SyncManager::encode() const {
    std::array<std::uint8_t, 8> b{};
    put_le<std::uint16_t>(b.data(), start);
    put_le<std::uint16_t>(b.data() + 2, length);
    b[4] = control;
    b[5] = status;
    b[6] = activate;
    b[7] = pdi_control;
    return b;
}

SyncManager SyncManager::decode(std::span<const std::uint8_t> bytes) {
    SyncManager s;
    s.start = get_le<std::uint16_t>(bytes.data());
    s.length = get_le<std::uint16_t>(bytes.data() + 2);
    s.control = bytes[4];
    s.status = bytes[5];
    s.activate = bytes[6];
    s.pdi_control = bytes[7];
    return s;
}

std::array<std::uint8_t, 16> Fmmu::encode() const {
    std::array<std::uint8_t, 16> b{};
    put_le<std::uint32_t>(b.data(), logical_start);
    put_le<std::uint16_t>(b.data() + 4, length);
    b[6] = logical_start_bit;
    b[7] = logical_end_bit;
    put_le<std::uint16_t>(b.data() + 8, physical_start);
    b[10] = physical_start_bit;
    b[11] = type;
    b[12] = activate;
    return b;
}

Fmmu Fmmu::decode(std::span<const std::uint8_t> bytes) {
    Fmmu f;
    f.logical_start = get_le<std::uint32_t>(bytes.data());
    f.length = get_le<std::uint16_t>(bytes.data() + 4);
    f.logical_start_bit = bytes[6];
    f.logical_end_bit = bytes[7];
    f.physical_start = get_le<std::uint16_t>(bytes.data() + 8);
    f.physical_start_bit = bytes[10];
    f.type = bytes[11];
    f.activate = bytes[12];
    return f;
}

} // namespace codrive::ethercat
