// SPDX-License-Identifier: Apache-2.0
// Typed value text for decoded SDO data and PDO entries, straight into an output buffer.
#pragma once

#include <codrive/dump/object_catalog.hpp>

#include <fmt/format.h>

#include <cstdint>
#include <span>

namespace codrive::dump {

/// Appends a value: quoted strings (non-printables as \xNN, cut after 64 characters), hex octets
/// (cut after 32 bytes), decimal signed, decimal or hex (`info.hex`) unsigned, reals. If the
/// data length does not fit the type, the bytes are shown as for an unknown type: 1..8 bytes as
/// `0x…` little-endian unsigned, printable text quoted, anything else as hex octets.
void format_value(fmt::memory_buffer& out, const ObjectInfo& info,
                  std::span<const std::uint8_t> data);

/// Appends " (OPERATION ENABLED)" for a statusword, " (enable operation)" for a controlword and
/// " (cyclic synchronous position (CSP))" for modes of operation (display), judged by the index
/// (any CiA 402 axis); nothing otherwise.
void format_cia402_meaning(fmt::memory_buffer& out, std::uint16_t index, std::uint64_t raw);

/// Appends bytes as "11 22 33" (cut after `max` bytes with " …").
void format_hex_bytes(fmt::memory_buffer& out, std::span<const std::uint8_t> data,
                      std::size_t max = 32);

} // namespace codrive::dump
