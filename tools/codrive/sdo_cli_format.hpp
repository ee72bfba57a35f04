// SPDX-License-Identifier: Apache-2.0
// `codrive sdo` text handling: INDEX:SUB parsing, value types, value encoding and formatting.
#pragma once

#include <codrive/core/error.hpp>

#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

namespace codrive::cli {

struct Multiplexer {
    std::uint16_t index = 0;
    std::uint8_t subindex = 0;
};

/// "0x1018:1", "1018:01", "0x6040" (sub 0): both parts hex. nullopt if malformed.
[[nodiscard]] std::optional<Multiplexer> parse_multiplexer(std::string_view text);

/// The --type values.
enum class SdoValueType : std::uint8_t {
    U8,
    U16,
    U32,
    U64,
    I8,
    I16,
    I32,
    I64,
    F32,
    F64,
    Str,
    Hex,
    Domain
};
[[nodiscard]] std::optional<SdoValueType> parse_value_type(std::string_view name);
/// Size in bytes of a fixed-size type, 0 for str/hex/domain.
[[nodiscard]] std::size_t value_type_size(SdoValueType t);
[[nodiscard]] std::string_view to_string(SdoValueType t);

/// Encodes VALUE for `sdo write`; the error text is a sentence naming the value and the type.
[[nodiscard]] tl::expected<std::vector<std::uint8_t>, std::string>
encode_value(SdoValueType t, std::string_view text);
/// Formats read bytes; an error sentence if the size does not fit the type. Domain returns the
/// raw bytes as a string.
[[nodiscard]] tl::expected<std::string, std::string>
format_value(SdoValueType t, std::span<const std::uint8_t> bytes);
/// Without --type: "78 56 34 12 (0x12345678 = 305419896)"; only hex above 8 bytes.
[[nodiscard]] std::string format_untyped(std::span<const std::uint8_t> bytes);

} // namespace codrive::cli
