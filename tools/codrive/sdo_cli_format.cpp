// SPDX-License-Identifier: Apache-2.0
// Value parsing and formatting for `codrive sdo`.
#include "sdo_cli_format.hpp"

#include <codrive/core/endian.hpp>
#include <codrive/core/value.hpp>

#include <array>
#include <charconv>
#include <cmath>
#include <fmt/format.h>
#include <limits>

namespace codrive::cli {
namespace {

struct TypeRow {
    SdoValueType type;
    std::string_view name;
    std::size_t size;
};

constexpr std::array kTypes{
    TypeRow{SdoValueType::U8, "u8", 1},         TypeRow{SdoValueType::U16, "u16", 2},
    TypeRow{SdoValueType::U32, "u32", 4},       TypeRow{SdoValueType::U64, "u64", 8},
    TypeRow{SdoValueType::I8, "i8", 1},         TypeRow{SdoValueType::I16, "i16", 2},
    TypeRow{SdoValueType::I32, "i32", 4},       TypeRow{SdoValueType::I64, "i64", 8},
    TypeRow{SdoValueType::F32, "f32", 4},       TypeRow{SdoValueType::F64, "f64", 8},
    TypeRow{SdoValueType::Str, "str", 0},       TypeRow{SdoValueType::Hex, "hex", 0},
    TypeRow{SdoValueType::Domain, "domain", 0},
};

std::optional<unsigned> parse_hex(std::string_view s, unsigned max) {
    if (s.size() > 2 && s[0] == '0' && (s[1] == 'x' || s[1] == 'X')) {
        s.remove_prefix(2);
    }
    unsigned v = 0;
    const auto* end = s.data() + s.size();
    const auto [ptr, ec] = std::from_chars(s.data(), end, v, 16);
    if (s.empty() || ec != std::errc() || ptr != end || v > max) {
        return std::nullopt;
    }
    return v;
}

bool is_signed(SdoValueType t) {
    return t == SdoValueType::I8 || t == SdoValueType::I16 || t == SdoValueType::I32 ||
           t == SdoValueType::I64;
}
bool is_unsigned(SdoValueType t) {
    return t == SdoValueType::U8 || t == SdoValueType::U16 || t == SdoValueType::U32 ||
           t == SdoValueType::U64;
}

} // namespace

std::optional<Multiplexer> parse_multiplexer(std::string_view text) {
    const auto colon = text.find(':');
    const auto index = parse_hex(text.substr(0, colon), 0xFFFF);
    if (!index) {
        return std::nullopt;
    }
    Multiplexer m;
    m.index = static_cast<std::uint16_t>(*index);
    if (colon != std::string_view::npos) {
        const auto sub = parse_hex(text.substr(colon + 1), 0xFF);
        if (!sub) {
            return std::nullopt;
        }
        m.subindex = static_cast<std::uint8_t>(*sub);
    }
    return m;
}

std::optional<SdoValueType> parse_value_type(std::string_view name) {
    for (const auto& row : kTypes) {
        if (row.name == name) {
            return row.type;
        }
    }
    return std::nullopt;
}

std::size_t value_type_size(SdoValueType t) {
    for (const auto& row : kTypes) {
        if (row.type == t) {
            return row.size;
        }
    }
    return 0;
}

std::string_view to_string(SdoValueType t) {
    for (const auto& row : kTypes) {
        if (row.type == t) {
            return row.name;
        }
    }
    return "?";
}

tl::expected<std::vector<std::uint8_t>, std::string> encode_value(SdoValueType t,
                                                                  std::string_view text) {
    const std::size_t size = value_type_size(t);
    std::vector<std::uint8_t> out(size);
    const auto bad = [&](std::string_view why) {
        return tl::unexpected(
            fmt::format("'{}' is not a valid {} value ({})", text, to_string(t), why));
    };
    if (is_unsigned(t)) {
        const auto v = parse_uint(text);
        if (!v) {
            return bad("expected an unsigned integer, decimal or 0x hex");
        }
        if (size < 8 && *v >> (8 * size) != 0) {
            return bad(fmt::format("out of range for {} bytes", size));
        }
        put_le_n(out.data(), *v, size);
        return out;
    }
    if (is_signed(t)) {
        const auto v = parse_int(text);
        if (!v) {
            return bad("expected an integer");
        }
        if (size < 8) {
            const std::int64_t lo = -(std::int64_t{1} << (8 * size - 1));
            const std::int64_t hi = (std::int64_t{1} << (8 * size - 1)) - 1;
            if (*v < lo || *v > hi) {
                return bad(fmt::format("out of range {}..{}", lo, hi));
            }
        }
        put_le_n(out.data(), static_cast<std::uint64_t>(*v), size);
        return out;
    }
    if (t == SdoValueType::F32 || t == SdoValueType::F64) {
        double d = 0;
        const auto* end = text.data() + text.size();
        const auto [ptr, ec] = std::from_chars(text.data(), end, d);
        if (text.empty() || ec != std::errc() || ptr != end) {
            return bad("expected a number");
        }
        if (t == SdoValueType::F32) {
            put_le<float>(out.data(), static_cast<float>(d));
        } else {
            put_le<double>(out.data(), d);
        }
        return out;
    }
    if (t == SdoValueType::Str) {
        return std::vector<std::uint8_t>(text.begin(), text.end());
    }
    auto bytes = parse_hex_bytes(text);
    if (!bytes) {
        return bad("expected hex bytes such as '01 02 AB' or '0102AB'");
    }
    return std::move(*bytes);
}

tl::expected<std::string, std::string> format_value(SdoValueType t,
                                                    std::span<const std::uint8_t> bytes) {
    const std::size_t size = value_type_size(t);
    if (size != 0 && bytes.size() != size) {
        return tl::unexpected(fmt::format("the object has {} bytes, not the {} of type {}",
                                          bytes.size(), size, to_string(t)));
    }
    if (is_unsigned(t)) {
        return fmt::format("{}", get_le_n(bytes.data(), size));
    }
    if (is_signed(t)) {
        return fmt::format("{}", sign_extend(get_le_n(bytes.data(), size), size));
    }
    if (t == SdoValueType::F32) {
        return fmt::format("{}", get_le<float>(bytes.data()));
    }
    if (t == SdoValueType::F64) {
        return fmt::format("{}", get_le<double>(bytes.data()));
    }
    if (t == SdoValueType::Str) {
        std::string s(bytes.begin(), bytes.end());
        while (!s.empty() && s.back() == '\0') {
            s.pop_back();
        }
        return s;
    }
    if (t == SdoValueType::Hex) {
        return hex_bytes(bytes);
    }
    return std::string(bytes.begin(), bytes.end());
}

std::string format_untyped(std::span<const std::uint8_t> bytes) {
    if (bytes.empty()) {
        return "(0 bytes)";
    }
    std::string out = hex_bytes(bytes);
    if (bytes.size() <= 8) {
        const std::uint64_t v = get_le_n(bytes.data(), bytes.size());
        out += fmt::format(" (0x{:0{}X} = {})", v, bytes.size() * 2, v);
    }
    return out;
}

} // namespace codrive::cli
