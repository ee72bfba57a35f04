// SPDX-License-Identifier: Apache-2.0
// Scanners shared by the text trace readers.
#include <codrive/dump/text_scan.hpp>

#include <codrive/dump/record.hpp>

#include <array>

namespace codrive::dump::scan {
namespace {

constexpr std::array<std::int8_t, 256> make_hex_table() {
    std::array<std::int8_t, 256> t{};
    for (auto& v : t) {
        v = -1;
    }
    for (int c = '0'; c <= '9'; ++c) {
        t[static_cast<std::size_t>(c)] = static_cast<std::int8_t>(c - '0');
    }
    for (int c = 'a'; c <= 'f'; ++c) {
        t[static_cast<std::size_t>(c)] = static_cast<std::int8_t>(c - 'a' + 10);
    }
    for (int c = 'A'; c <= 'F'; ++c) {
        t[static_cast<std::size_t>(c)] = static_cast<std::int8_t>(c - 'A' + 10);
    }
    return t;
}
constexpr auto kHex = make_hex_table();

char lower(char c) {
    return (c >= 'A' && c <= 'Z') ? static_cast<char>(c - 'A' + 'a') : c;
}

// Days from 1970-01-01 by 400-year eras of 146097 days, with March as the first month so the
// leap day falls at the end of the year.
std::int64_t days_from_civil(std::int64_t y, unsigned m, unsigned d) {
    y -= m <= 2 ? 1 : 0;
    const std::int64_t era = (y >= 0 ? y : y - 399) / 400;
    const auto yoe = static_cast<unsigned>(y - era * 400);
    const unsigned doy = (153 * (m + (m > 2 ? static_cast<unsigned>(-3) : 9)) + 2) / 5 + d - 1;
    const unsigned doe = yoe * 365 + yoe / 4 - yoe / 100 + doy;
    return era * 146097 + static_cast<std::int64_t>(doe) - 719468;
}

} // namespace

int hexval(char c) {
    return kHex[static_cast<unsigned char>(c)];
}

bool days_since_epoch(std::int64_t y, std::int64_t m, std::int64_t d, std::int64_t& days) {
    if (y < 1970 || y > 2200 || m < 1 || m > 12 || d < 1) {
        return false;
    }
    static constexpr std::array<std::int64_t, 12> kMonthDays{31, 28, 31, 30, 31, 30,
                                                             31, 31, 30, 31, 30, 31};
    const bool leap = (y % 4 == 0 && y % 100 != 0) || y % 400 == 0;
    if (d > kMonthDays[static_cast<std::size_t>(m - 1)] + (m == 2 && leap ? 1 : 0)) {
        return false;
    }
    days = days_from_civil(y, static_cast<unsigned>(m), static_cast<unsigned>(d));
    return true;
}

bool parse_digits(std::string_view s, std::int64_t& v) {
    if (s.empty() || s.size() > 18) {
        return false;
    }
    v = 0;
    for (char c : s) {
        if (!is_digit(c)) {
            return false;
        }
        v = v * 10 + (c - '0');
    }
    return true;
}

bool parse_scaled(std::string_view s, std::int64_t unit_ns, std::int64_t& ns) {
    const auto dot = s.find('.');
    std::int64_t whole = 0;
    if (!parse_digits(s.substr(0, dot), whole) || whole > kMaxTraceTimeNs / unit_ns) {
        return false;
    }
    std::int64_t frac_ns = 0;
    if (dot != std::string_view::npos) {
        const auto f = s.substr(dot + 1);
        std::int64_t frac = 0;
        if (f.size() > 9 || (!f.empty() && !parse_digits(f, frac))) {
            return false;
        }
        std::int64_t scale = 1;
        for (std::size_t i = 0; i < f.size(); ++i) {
            scale *= 10;
        }
        frac_ns = frac * unit_ns / scale;
    }
    return add_trace_time(whole * unit_ns, frac_ns, ns); // the fraction may pass the bound
}

bool parse_seconds(std::string_view s, std::int64_t& ns) {
    const auto dot = s.find('.');
    std::int64_t sec = 0;
    if (!parse_digits(s.substr(0, dot), sec) || sec > kMaxTraceTimeS) {
        return false;
    }
    if (dot != std::string_view::npos && s.size() == dot + 1) {
        return false; // "12." has no fraction digits
    }
    return parse_scaled(s, 1'000'000'000LL, ns);
}

bool parse_date_time(std::string_view s, std::int64_t& ns) {
    if (s.size() < 19 || s[4] != '-' || s[7] != '-' || s[10] != ' ' || s[13] != ':' ||
        s[16] != ':') {
        return false;
    }
    std::int64_t y = 0;
    std::int64_t mo = 0;
    std::int64_t d = 0;
    std::int64_t h = 0;
    std::int64_t mi = 0;
    std::int64_t sec_ns = 0;
    if (!parse_digits(s.substr(0, 4), y) || !parse_digits(s.substr(5, 2), mo) ||
        !parse_digits(s.substr(8, 2), d) || !parse_digits(s.substr(11, 2), h) ||
        !parse_digits(s.substr(14, 2), mi) || !parse_seconds(s.substr(17), sec_ns) || h > 23 ||
        mi > 59 || sec_ns >= 61'000'000'000LL) {
        return false;
    }
    std::int64_t days = 0;
    if (!days_since_epoch(y, mo, d, days)) {
        return false;
    }
    ns = ((days * 24 + h) * 60 + mi) * 60 * 1'000'000'000LL + sec_ns;
    return true;
}

bool parse_hex_u32(std::string_view s, std::uint32_t& v, bool allow_prefix) {
    if (allow_prefix && s.size() > 2 && s[0] == '0' && (s[1] == 'x' || s[1] == 'X')) {
        s.remove_prefix(2);
    }
    if (s.empty() || s.size() > 8) {
        return false;
    }
    std::uint32_t r = 0;
    for (char c : s) {
        const int h = hexval(c);
        if (h < 0) {
            return false;
        }
        r = (r << 4) | static_cast<std::uint32_t>(h);
    }
    v = r;
    return true;
}

bool parse_hex_byte(std::string_view s, std::uint8_t& b) {
    if (s.size() != 2 || hexval(s[0]) < 0 || hexval(s[1]) < 0) {
        return false;
    }
    b = static_cast<std::uint8_t>((hexval(s[0]) << 4) | hexval(s[1]));
    return true;
}

bool iequals(std::string_view a, std::string_view b) {
    if (a.size() != b.size()) {
        return false;
    }
    for (std::size_t i = 0; i < a.size(); ++i) {
        if (lower(a[i]) != lower(b[i])) {
            return false;
        }
    }
    return true;
}

bool istarts_with(std::string_view s, std::string_view prefix) {
    return s.size() >= prefix.size() && iequals(s.substr(0, prefix.size()), prefix);
}

bool contains_ci(std::string_view s, std::string_view part) {
    for (std::size_t i = 0; i + part.size() <= s.size(); ++i) {
        if (iequals(s.substr(i, part.size()), part)) {
            return true;
        }
    }
    return false;
}

} // namespace codrive::dump::scan
