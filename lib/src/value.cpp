// SPDX-License-Identifier: Apache-2.0
// Value construction, range checks and conversion to and from text.
#include <codrive/core/value.hpp>

#include "hex_digit.hpp"

#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <fmt/format.h>
#include <limits>
#include <string>

namespace codrive {
namespace {

std::string_view trim(std::string_view s) {
    while (!s.empty() && std::isspace(static_cast<unsigned char>(s.front())) != 0) {
        s.remove_prefix(1);
    }
    while (!s.empty() && std::isspace(static_cast<unsigned char>(s.back())) != 0) {
        s.remove_suffix(1);
    }
    return s;
}

// Range of an integer type of n bytes.
std::uint64_t umax(std::size_t n) {
    return n >= 8 ? std::numeric_limits<std::uint64_t>::max() : (std::uint64_t{1} << (8 * n)) - 1;
}
std::int64_t smax(std::size_t n) {
    return static_cast<std::int64_t>(umax(n) >> 1);
}
std::int64_t smin(std::size_t n) {
    return -smax(n) - 1;
}

} // namespace

std::int64_t sign_extend(std::uint64_t raw, std::size_t bytes) {
    if (bytes == 0 || bytes >= 8) {
        return static_cast<std::int64_t>(raw);
    }
    const unsigned shift = static_cast<unsigned>(64 - 8 * bytes);
    return static_cast<std::int64_t>(raw << shift) >> shift;
}

std::optional<std::uint64_t> parse_uint(std::string_view text) {
    text = trim(text);
    if (text.empty()) {
        return std::nullopt;
    }
    int base = 10;
    if (text.size() > 2 && text[0] == '0' && (text[1] == 'x' || text[1] == 'X')) {
        base = 16;
        text.remove_prefix(2);
    }
    std::uint64_t v = 0;
    for (char c : text) {
        const int d = detail::hex_digit(c);
        if (d < 0 || d >= base) {
            return std::nullopt;
        }
        const auto ubase = static_cast<std::uint64_t>(base);
        if (v >
            (std::numeric_limits<std::uint64_t>::max() - static_cast<std::uint64_t>(d)) / ubase) {
            return std::nullopt;
        }
        v = v * ubase + static_cast<std::uint64_t>(d);
    }
    return v;
}

std::optional<std::int64_t> parse_int(std::string_view text) {
    text = trim(text);
    bool neg = false;
    if (!text.empty() && (text[0] == '-' || text[0] == '+')) {
        neg = text[0] == '-';
        text.remove_prefix(1);
    }
    auto u = parse_uint(text);
    if (!u) {
        return std::nullopt;
    }
    if (neg) {
        if (*u > static_cast<std::uint64_t>(std::numeric_limits<std::int64_t>::max()) + 1) {
            return std::nullopt;
        }
        return static_cast<std::int64_t>(0 - *u);
    }
    if (*u > static_cast<std::uint64_t>(std::numeric_limits<std::int64_t>::max())) {
        return std::nullopt;
    }
    return static_cast<std::int64_t>(*u);
}

std::string hex_bytes(std::span<const std::uint8_t> bytes) {
    std::string out;
    out.reserve(bytes.size() * 3);
    for (std::size_t i = 0; i < bytes.size(); ++i) {
        if (i != 0) {
            out += ' ';
        }
        out += fmt::format("{:02X}", bytes[i]);
    }
    return out;
}

Result<std::vector<std::uint8_t>> parse_hex_bytes(std::string_view text) {
    std::vector<std::uint8_t> out;
    int hi = -1;
    for (char c : text) {
        if (std::isspace(static_cast<unsigned char>(c)) != 0 || c == ':' || c == '-' || c == ',') {
            if (hi >= 0) {
                return fail(CoreErrc::ParseError); // odd digit inside a byte group
            }
            continue;
        }
        const int d = detail::hex_digit(c);
        if (d < 0) {
            return fail(CoreErrc::ParseError);
        }
        if (hi < 0) {
            hi = d;
        } else {
            out.push_back(static_cast<std::uint8_t>(hi * 16 + d));
            hi = -1;
        }
    }
    if (hi >= 0) {
        return fail(CoreErrc::ParseError);
    }
    return out;
}

Value Value::zero(DataType type) {
    return Value(type, std::vector<std::uint8_t>(data_type_size(type), 0));
}

Result<Value> Value::from_int(DataType type, std::int64_t v) {
    const std::size_t n = data_type_size(type);
    if (is_signed_integer(type)) {
        if (v < smin(n) || v > smax(n)) {
            return fail(CoreErrc::OutOfRange);
        }
    } else if (is_unsigned_integer(type)) {
        if (v < 0 || static_cast<std::uint64_t>(v) > umax(n) ||
            (type == DataType::Boolean && v > 1)) {
            return fail(CoreErrc::OutOfRange);
        }
    } else if (is_real(type)) {
        return from_double(type, static_cast<double>(v));
    } else {
        return fail(CoreErrc::TypeMismatch);
    }
    Value out = zero(type);
    put_le_n(out.bytes_.data(), static_cast<std::uint64_t>(v), n);
    return out;
}

Result<Value> Value::from_uint(DataType type, std::uint64_t v) {
    const std::size_t n = data_type_size(type);
    if (is_unsigned_integer(type)) {
        if (v > umax(n) || (type == DataType::Boolean && v > 1)) {
            return fail(CoreErrc::OutOfRange);
        }
        Value out = zero(type);
        put_le_n(out.bytes_.data(), v, n);
        return out;
    }
    if (v > static_cast<std::uint64_t>(std::numeric_limits<std::int64_t>::max())) {
        return fail(CoreErrc::OutOfRange);
    }
    return from_int(type, static_cast<std::int64_t>(v));
}

Result<Value> Value::from_double(DataType type, double v) {
    Value out = zero(type);
    if (type == DataType::Real32) {
        if (std::isfinite(v) &&
            std::fabs(v) > static_cast<double>(std::numeric_limits<float>::max())) {
            return fail(CoreErrc::OutOfRange);
        }
        put_le<float>(out.bytes_.data(), static_cast<float>(v));
        return out;
    }
    if (type == DataType::Real64) {
        put_le<double>(out.bytes_.data(), v);
        return out;
    }
    if (std::nearbyint(v) != v) {
        return fail(CoreErrc::TypeMismatch);
    }
    return from_int(type, static_cast<std::int64_t>(v));
}

Value Value::from_string(std::string_view s, DataType type) {
    return Value(type, std::vector<std::uint8_t>(s.begin(), s.end()));
}

Result<Value> Value::parse(DataType type, std::string_view text) {
    if (type == DataType::VisibleString || type == DataType::UnicodeString) {
        return from_string(text, type);
    }
    if (type == DataType::OctetString || type == DataType::Domain) {
        auto bytes = parse_hex_bytes(text);
        if (!bytes) {
            return fail(bytes.error());
        }
        return Value(type, std::move(*bytes));
    }
    const std::string_view t = trim(text);
    if (type == DataType::Boolean) {
        if (t == "true" || t == "TRUE") {
            return from_uint(type, 1);
        }
        if (t == "false" || t == "FALSE") {
            return from_uint(type, 0);
        }
    }
    if (is_real(type)) {
        const std::string s(t);
        if (s.empty()) {
            return fail(CoreErrc::ParseError);
        }
        char* end = nullptr;
        errno = 0;
        const double d = std::strtod(s.c_str(), &end);
        if (end != s.c_str() + s.size() || errno == ERANGE) {
            return fail(CoreErrc::ParseError);
        }
        return from_double(type, d);
    }
    if (is_signed_integer(type)) {
        auto v = parse_int(t);
        if (!v) {
            return fail(CoreErrc::ParseError);
        }
        // Hex text for a signed type is a bit pattern: 0xFFFF for INTEGER16 is -1.
        if (t.size() > 2 && t[0] == '0' && (t[1] == 'x' || t[1] == 'X')) {
            const std::size_t n = data_type_size(type);
            const auto raw = static_cast<std::uint64_t>(*v);
            if (raw > umax(n)) {
                return fail(CoreErrc::OutOfRange);
            }
            return from_int(type, sign_extend(raw, n));
        }
        return from_int(type, *v);
    }
    if (is_unsigned_integer(type)) {
        auto v = parse_uint(t);
        if (!v) {
            if (!t.empty() && t[0] == '-') {
                return fail(CoreErrc::OutOfRange);
            }
            return fail(CoreErrc::ParseError);
        }
        return from_uint(type, *v);
    }
    if (type == DataType::TimeOfDay || type == DataType::TimeDifference) {
        auto v = parse_uint(t);
        if (!v || *v > umax(6)) {
            return fail(CoreErrc::ParseError);
        }
        Value out = zero(type);
        put_le_n(out.bytes_.data(), *v, 6);
        return out;
    }
    return fail(CoreErrc::NotSupported);
}

std::optional<std::int64_t> Value::as_int() const {
    const std::size_t n = data_type_size(type_);
    if (n == 0 || bytes_.size() < n || is_real(type_)) {
        return std::nullopt;
    }
    const std::uint64_t raw = get_le_n(bytes_.data(), n);
    if (is_signed_integer(type_)) {
        return sign_extend(raw, n);
    }
    if (raw > static_cast<std::uint64_t>(std::numeric_limits<std::int64_t>::max())) {
        return std::nullopt;
    }
    return static_cast<std::int64_t>(raw);
}

std::optional<std::uint64_t> Value::as_uint() const {
    const std::size_t n = data_type_size(type_);
    if (n == 0 || bytes_.size() < n || is_real(type_)) {
        return std::nullopt;
    }
    if (is_signed_integer(type_)) {
        const std::int64_t v = sign_extend(get_le_n(bytes_.data(), n), n);
        if (v < 0) {
            return std::nullopt;
        }
        return static_cast<std::uint64_t>(v);
    }
    return get_le_n(bytes_.data(), n);
}

std::optional<double> Value::as_double() const {
    if (type_ == DataType::Real32 && bytes_.size() >= 4) {
        return static_cast<double>(get_le<float>(bytes_.data()));
    }
    if (type_ == DataType::Real64 && bytes_.size() >= 8) {
        return get_le<double>(bytes_.data());
    }
    if (is_signed_integer(type_)) {
        auto v = as_int();
        return v ? std::optional<double>(static_cast<double>(*v)) : std::nullopt;
    }
    auto v = as_uint();
    return v ? std::optional<double>(static_cast<double>(*v)) : std::nullopt;
}

std::string Value::to_string() const {
    if (type_ == DataType::VisibleString || type_ == DataType::UnicodeString) {
        return {bytes_.begin(), bytes_.end()};
    }
    if (type_ == DataType::OctetString || type_ == DataType::Domain) {
        return hex_bytes(bytes_);
    }
    if (bytes_.size() < data_type_size(type_)) {
        return fmt::format("<{} bytes: {}>", bytes_.size(), hex_bytes(bytes_));
    }
    if (type_ == DataType::Real32) {
        return fmt::format("{}", get_le<float>(bytes_.data()));
    }
    if (type_ == DataType::Real64) {
        return fmt::format("{}", get_le<double>(bytes_.data()));
    }
    if (is_signed_integer(type_)) {
        return fmt::format("{}", *as_int());
    }
    return fmt::format("{}", get_le_n(bytes_.data(), data_type_size(type_)));
}

} // namespace codrive
