// SPDX-License-Identifier: Apache-2.0
// Hand-written appenders for the per-frame hot path (fmt's format-string parsing costs more than
// the whole decode of a PDO; these write digits straight into the output buffer).
#pragma once

#include <fmt/format.h>

#include <cstdint>
#include <cstring>
#include <string_view>

namespace codrive::dump::text {

inline constexpr char kHexDigits[] = "0123456789ABCDEF";

inline void put(fmt::memory_buffer& b, std::string_view s) {
    b.append(s.data(), s.data() + s.size());
}

/// Decimal, at least `width` digits (zero padded).
inline void put_uint(fmt::memory_buffer& b, std::uint64_t v, unsigned width = 1) {
    char tmp[24];
    char* p = tmp + sizeof tmp;
    do {
        *--p = static_cast<char>('0' + v % 10);
        v /= 10;
    } while (v != 0);
    while (tmp + sizeof tmp - p < static_cast<std::ptrdiff_t>(width) && p > tmp) {
        *--p = '0';
    }
    b.append(p, tmp + sizeof tmp);
}

inline void put_int(fmt::memory_buffer& b, std::int64_t v) {
    if (v < 0) {
        b.push_back('-');
        put_uint(b, static_cast<std::uint64_t>(-(v + 1)) + 1U);
    } else {
        put_uint(b, static_cast<std::uint64_t>(v));
    }
}

/// Upper-case hex, exactly `digits` digits (1..16), no prefix.
inline void put_hex(fmt::memory_buffer& b, std::uint64_t v, unsigned digits) {
    char tmp[16];
    for (unsigned i = 0; i < digits && i < 16; ++i) {
        tmp[digits - 1 - i] = kHexDigits[(v >> (4 * i)) & 0xF];
    }
    b.append(tmp, tmp + digits);
}

inline void put_byte_hex(fmt::memory_buffer& b, std::uint8_t v) {
    const char tmp[2] = {kHexDigits[v >> 4], kHexDigits[v & 0xF]};
    b.append(tmp, tmp + 2);
}

} // namespace codrive::dump::text

namespace codrive::dump::text {

/// Writes into a region reserved up front: no capacity check per piece. The caller reserves an
/// upper bound of what it writes; the destructor trims the buffer to what was written.
class Cursor {
public:
    Cursor(fmt::memory_buffer& b, std::size_t max) : b_(b), old_(b.size()) {
        b_.resize(old_ + max);
        p_ = b_.data() + old_;
    }
    ~Cursor() { b_.resize(static_cast<std::size_t>(p_ - b_.data())); }
    Cursor(const Cursor&) = delete;
    Cursor& operator=(const Cursor&) = delete;

    void put(char c) { *p_++ = c; }
    void put(std::string_view s) {
        std::memcpy(p_, s.data(), s.size());
        p_ += s.size();
    }
    void put(const char* s, std::size_t n) {
        std::memcpy(p_, s, n);
        p_ += n;
    }
    void spaces(std::size_t n) {
        std::memset(p_, ' ', n);
        p_ += n;
    }
    void uint(std::uint64_t v, unsigned width = 1) {
        char tmp[24];
        char* q = tmp + sizeof tmp;
        do {
            *--q = static_cast<char>('0' + v % 10);
            v /= 10;
        } while (v != 0);
        while (tmp + sizeof tmp - q < static_cast<std::ptrdiff_t>(width) && q > tmp) {
            *--q = '0';
        }
        put(q, static_cast<std::size_t>(tmp + sizeof tmp - q));
    }
    void sint(std::int64_t v) {
        if (v < 0) {
            put('-');
            uint(static_cast<std::uint64_t>(-(v + 1)) + 1U);
        } else {
            uint(static_cast<std::uint64_t>(v));
        }
    }
    void hex(std::uint64_t v, unsigned digits) {
        for (unsigned i = 0; i < digits; ++i) {
            p_[digits - 1 - i] = kHexDigits[(v >> (4 * i)) & 0xF];
        }
        p_ += digits;
    }
    void byte_hex(std::uint8_t v) {
        p_[0] = kHexDigits[v >> 4];
        p_[1] = kHexDigits[v & 0xF];
        p_ += 2;
    }
    /// Characters written since `mark()`.
    [[nodiscard]] char* pos() const { return p_; }

private:
    fmt::memory_buffer& b_;
    std::size_t old_;
    char* p_;
};

} // namespace codrive::dump::text
