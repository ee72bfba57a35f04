// SPDX-License-Identifier: Apache-2.0
// Bus bit times of a frame: worst-case and exact bit stuffing.
#include <codrive/dump/frame_bits.hpp>

#include <array>

namespace codrive::dump {

std::uint32_t frame_bits_worst_case(const Frame& f) {
    const std::uint32_t data_bits = f.rtr() ? 0U : 8U * f.len;
    if (f.extended()) {
        return 67U + data_bits + (54U + data_bits - 1U) / 4U;
    }
    return 47U + data_bits + (34U + data_bits - 1U) / 4U;
}

namespace {

// The stuffed part of a frame (SOF to the end of the CRC field), fed one bit at a time: keeps the
// CRC of the bits so far and the number of stuff bits the transmitter inserts.
class StuffCounter {
public:
    void bits(std::uint32_t value, unsigned count) {
        for (unsigned i = count; i-- > 0;) {
            bit((value >> i) & 1U);
        }
    }
    // The CRC sequence is stuffed but not part of its own computation (ISO 11898-1 §10.4.2.6).
    void crc_field() {
        const std::uint32_t crc = crc_;
        for (unsigned i = 15; i-- > 0;) {
            stuff((crc >> i) & 1U);
        }
    }
    [[nodiscard]] std::uint32_t stuff_bits() const { return stuff_bits_; }
    [[nodiscard]] std::uint32_t crc() const { return crc_; }

private:
    void bit(std::uint32_t b) {
        // CRC-15/CAN: shift in, xor 0x4599 when the bit leaving the register differs from b.
        const std::uint32_t feedback = ((crc_ >> 14) & 1U) ^ b;
        crc_ = (crc_ << 1) & 0x7FFFU;
        if (feedback != 0) {
            crc_ ^= 0x4599U;
        }
        stuff(b);
    }
    void stuff(std::uint32_t b) {
        if (run_ > 0 && b == last_) {
            ++run_;
        } else {
            last_ = b;
            run_ = 1;
        }
        if (run_ == 5) {
            ++stuff_bits_; // the complement goes on the bus and begins a run of its own
            last_ ^= 1U;
            run_ = 1;
        }
    }
    std::uint32_t crc_ = 0;
    std::uint32_t last_ = 0;
    unsigned run_ = 0;
    std::uint32_t stuff_bits_ = 0;
};

} // namespace

std::uint32_t frame_bits_exact(const Frame& f) {
    if (f.fd()) {
        return frame_bits_worst_case(f);
    }
    const unsigned n = f.rtr() ? 0U : (f.len > 8 ? 8U : f.len);
    const unsigned dlc = f.len > 15 ? 15U : f.len;
    StuffCounter s;
    s.bits(0, 1); // SOF, dominant
    std::uint32_t fixed = 1U;
    if (f.extended()) {
        s.bits((f.id >> 18) & 0x7FFU, 11); // base identifier
        s.bits(1, 1);                      // SRR, recessive
        s.bits(1, 1);                      // IDE, recessive
        s.bits(f.id & 0x3FFFFU, 18);       // identifier extension
        s.bits(f.rtr() ? 1U : 0U, 1);
        s.bits(0, 2); // r1, r0
        fixed += 11 + 1 + 1 + 18 + 1 + 2;
    } else {
        s.bits(f.id & 0x7FFU, 11);
        s.bits(f.rtr() ? 1U : 0U, 1);
        s.bits(0, 2); // IDE dominant, r0
        fixed += 11 + 1 + 2;
    }
    s.bits(dlc, 4);
    for (unsigned i = 0; i < n; ++i) {
        s.bits(f.data[i], 8);
    }
    s.crc_field();
    fixed += 4 + 8 * n + 15;
    // CRC delimiter, ACK slot, ACK delimiter, end of frame (7), intermission (3): never stuffed.
    return fixed + s.stuff_bits() + 13U;
}

} // namespace codrive::dump
