// SPDX-License-Identifier: Apache-2.0
// A typed object value: raw little-endian bytes plus the CiA 301 data type, with text conversion.
#pragma once

#include <codrive/core/data_type.hpp>
#include <codrive/core/endian.hpp>
#include <codrive/core/error.hpp>

#include <cstdint>
#include <span>
#include <string>
#include <string_view>
#include <vector>

namespace codrive {

/// A value of a CiA 301 data type, held as its wire bytes (little-endian).
class Value {
public:
    Value() = default;
    Value(DataType type, std::vector<std::uint8_t> bytes) : type_(type), bytes_(std::move(bytes)) {}

    /// A zero value of the type (empty for variable-size types).
    static Value zero(DataType type);
    /// A value from an integer, range-checked against the type.
    static Result<Value> from_int(DataType type, std::int64_t v);
    static Result<Value> from_uint(DataType type, std::uint64_t v);
    static Result<Value> from_double(DataType type, double v);
    static Value from_string(std::string_view s, DataType type = DataType::VisibleString);

    /// Parses text: integers in decimal or hex (`0x1A`, `-5`), reals (`1.5`), booleans
    /// (`0`/`1`/`true`/`false`), strings verbatim, octet strings and domains as hex bytes
    /// (`01 02 AB` or `0102AB`). Errors name the text and the type.
    static Result<Value> parse(DataType type, std::string_view text);

    /// Human-readable text: decimal integers, reals, quoted-free strings, hex bytes.
    [[nodiscard]] std::string to_string() const;

    [[nodiscard]] DataType type() const { return type_; }
    [[nodiscard]] std::span<const std::uint8_t> bytes() const { return bytes_; }
    [[nodiscard]] std::vector<std::uint8_t>& mutable_bytes() { return bytes_; }
    [[nodiscard]] std::size_t size() const { return bytes_.size(); }

    /// Numeric views (sign-extended for signed types); nullopt for non-numeric types.
    [[nodiscard]] std::optional<std::int64_t> as_int() const;
    [[nodiscard]] std::optional<std::uint64_t> as_uint() const;
    [[nodiscard]] std::optional<double> as_double() const;

    friend bool operator==(const Value& a, const Value& b) = default;

private:
    DataType type_ = DataType::Unsigned8;
    std::vector<std::uint8_t> bytes_;
};

/// Sign-extends the low `bytes` bytes of raw.
[[nodiscard]] std::int64_t sign_extend(std::uint64_t raw, std::size_t bytes);

/// Hex dump "01 02 AB".
[[nodiscard]] std::string hex_bytes(std::span<const std::uint8_t> bytes);
/// Parses "01 02 AB", "0102AB", "01:02:ab" into bytes.
[[nodiscard]] Result<std::vector<std::uint8_t>> parse_hex_bytes(std::string_view text);

/// Parses an unsigned integer in decimal, or hex with 0x prefix. Used everywhere text carries
/// indexes and ids.
[[nodiscard]] std::optional<std::uint64_t> parse_uint(std::string_view text);
[[nodiscard]] std::optional<std::int64_t> parse_int(std::string_view text);

} // namespace codrive
