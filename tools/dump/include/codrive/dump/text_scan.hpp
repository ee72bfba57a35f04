// SPDX-License-Identifier: Apache-2.0
// Small hand-written scanners the text trace readers share (no locale, no allocation).
#pragma once

#include <cstdint>
#include <string_view>

namespace codrive::dump::scan {

/// Value of a hex digit, or -1.
[[nodiscard]] int hexval(char c);
[[nodiscard]] inline bool is_space(char c) {
    return c == ' ' || c == '\t';
}
[[nodiscard]] inline bool is_digit(char c) {
    return c >= '0' && c <= '9';
}

/// Splits a line into whitespace-separated tokens (or `sep`-separated fields, see field()).
struct Cursor {
    const char* p;
    const char* end;
    explicit Cursor(std::string_view s) : p(s.data()), end(s.data() + s.size()) {}
    [[nodiscard]] bool done() const { return p == end; }
    void skip_space() {
        while (p != end && is_space(*p)) {
            ++p;
        }
    }
    /// The next whitespace-separated token ("" at the end).
    std::string_view token() {
        skip_space();
        const char* s = p;
        while (p != end && !is_space(*p)) {
            ++p;
        }
        return {s, static_cast<std::size_t>(p - s)};
    }
    /// The rest of the line from here.
    [[nodiscard]] std::string_view rest() const { return {p, static_cast<std::size_t>(end - p)}; }
};

/// Decimal digits only (1..18 of them).
[[nodiscard]] bool parse_digits(std::string_view s, std::int64_t& v);
/// "1700000000.123456" (0..9 fraction digits) into nanoseconds.
[[nodiscard]] bool parse_seconds(std::string_view s, std::int64_t& ns);
/// Like parse_seconds but scaled: "1841.5" with `unit_ns` 1'000'000 (milliseconds) is
/// 1'841'500'000 ns. A leading '-' is refused.
[[nodiscard]] bool parse_scaled(std::string_view s, std::int64_t unit_ns, std::int64_t& ns);
/// "2023-11-14 22:13:20.123456" (read as UTC) into nanoseconds since the epoch.
[[nodiscard]] bool parse_date_time(std::string_view s, std::int64_t& ns);
/// Days from 1970-01-01 to y-m-d (proleptic Gregorian) when the date exists and lies in
/// 1970..2200, the years a trace timestamp can carry; false for 2023-02-29, 2023-04-31 or a
/// month 13, so no reader turns an impossible date into the next month's.
[[nodiscard]] bool days_since_epoch(std::int64_t y, std::int64_t m, std::int64_t d,
                                    std::int64_t& days);
/// 1..8 hex digits (an optional "0x" prefix is accepted when `allow_prefix`).
[[nodiscard]] bool parse_hex_u32(std::string_view s, std::uint32_t& v, bool allow_prefix = false);
/// Exactly two hex digits.
[[nodiscard]] bool parse_hex_byte(std::string_view s, std::uint8_t& b);
/// Case-insensitive ASCII comparison.
[[nodiscard]] bool iequals(std::string_view a, std::string_view b);
/// Case-insensitive prefix test.
[[nodiscard]] bool istarts_with(std::string_view s, std::string_view prefix);
/// Case-insensitive substring test.
[[nodiscard]] bool contains_ci(std::string_view s, std::string_view part);

} // namespace codrive::dump::scan
