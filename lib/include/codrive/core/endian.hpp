// SPDX-License-Identifier: Apache-2.0
// Little-endian codecs for CANopen data (CiA 301 §7.1: all multi-byte values are little-endian).
#pragma once

#include <bit>
#include <cstdint>
#include <cstring>
#include <span>
#include <type_traits>

namespace codrive {

/// Reads a T (integral or float) from the first sizeof(T) bytes, little-endian.
/// The caller guarantees the span is long enough.
template <typename T>
[[nodiscard]] inline T get_le(const std::uint8_t* p) {
    static_assert(std::is_trivially_copyable_v<T>);
    if constexpr (std::is_floating_point_v<T>) {
        using U = std::conditional_t<sizeof(T) == 4, std::uint32_t, std::uint64_t>;
        return std::bit_cast<T>(get_le<U>(p));
    } else {
        using U = std::make_unsigned_t<T>;
        U v = 0;
        for (std::size_t i = 0; i < sizeof(T); ++i) {
            v = static_cast<U>(v | (static_cast<U>(p[i]) << (8 * i)));
        }
        return static_cast<T>(v);
    }
}

template <typename T>
[[nodiscard]] inline T get_le(std::span<const std::uint8_t> s, std::size_t offset = 0) {
    return get_le<T>(s.data() + offset);
}

/// Writes v as sizeof(T) little-endian bytes at p.
template <typename T>
inline void put_le(std::uint8_t* p, T v) {
    if constexpr (std::is_floating_point_v<T>) {
        using U = std::conditional_t<sizeof(T) == 4, std::uint32_t, std::uint64_t>;
        put_le<U>(p, std::bit_cast<U>(v));
    } else {
        using U = std::make_unsigned_t<T>;
        auto u = static_cast<U>(v);
        for (std::size_t i = 0; i < sizeof(T); ++i) {
            p[i] = static_cast<std::uint8_t>(u >> (8 * i));
        }
    }
}

template <typename T>
inline void put_le(std::span<std::uint8_t> s, std::size_t offset, T v) {
    put_le<T>(s.data() + offset, v);
}

/// Reads an unsigned value of `n` bytes (1..8), little-endian.
[[nodiscard]] inline std::uint64_t get_le_n(const std::uint8_t* p, std::size_t n) {
    std::uint64_t v = 0;
    for (std::size_t i = 0; i < n && i < 8; ++i) {
        v |= static_cast<std::uint64_t>(p[i]) << (8 * i);
    }
    return v;
}

/// Writes the low `n` bytes (1..8) of v little-endian.
inline void put_le_n(std::uint8_t* p, std::uint64_t v, std::size_t n) {
    for (std::size_t i = 0; i < n && i < 8; ++i) {
        p[i] = static_cast<std::uint8_t>(v >> (8 * i));
    }
}

} // namespace codrive
