// SPDX-License-Identifier: Apache-2.0
// Hand-written candump text parsers (log and screen formats).
#include <codrive/dump/log_parser.hpp>

#include <fmt/format.h>

#include <array>

namespace codrive::dump {
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

inline int hexval(char c) {
    return kHex[static_cast<unsigned char>(c)];
}
inline bool is_space(char c) {
    return c == ' ' || c == '\t';
}
inline bool is_digit(char c) {
    return c >= '0' && c <= '9';
}

struct Cursor {
    const char* p;
    const char* end;
    [[nodiscard]] bool done() const { return p == end; }
    void skip_space() {
        while (p != end && is_space(*p)) {
            ++p;
        }
    }
    std::string_view token() {
        const char* s = p;
        while (p != end && !is_space(*p)) {
            ++p;
        }
        return {s, static_cast<std::size_t>(p - s)};
    }
};

// Days from 1970-01-01 to y-m-d (proleptic Gregorian), for `-t A` screen timestamps.
std::int64_t days_from_civil(std::int64_t y, unsigned m, unsigned d) {
    y -= m <= 2 ? 1 : 0;
    const std::int64_t era = (y >= 0 ? y : y - 399) / 400;
    const auto yoe = static_cast<unsigned>(y - era * 400);
    const unsigned doy = (153 * (m + (m > 2 ? static_cast<unsigned>(-3) : 9)) + 2) / 5 + d - 1;
    const unsigned doe = yoe * 365 + yoe / 4 - yoe / 100 + doy;
    return era * 146097 + static_cast<std::int64_t>(doe) - 719468;
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

// "1700000000.123456" (1..9 fraction digits) → ns.
bool parse_seconds(std::string_view s, std::int64_t& ns) {
    const auto dot = s.find('.');
    std::int64_t sec = 0;
    if (!parse_digits(s.substr(0, dot), sec) || sec > 9'000'000'000LL) {
        return false;
    }
    std::int64_t frac = 0;
    if (dot != std::string_view::npos) {
        const auto f = s.substr(dot + 1);
        if (f.empty() || f.size() > 9 || !parse_digits(f, frac)) {
            return false;
        }
        for (std::size_t i = f.size(); i < 9; ++i) {
            frac *= 10;
        }
    }
    ns = sec * 1'000'000'000LL + frac;
    return true;
}

// "2023-11-14 22:13:20.123456" → ns (read as UTC).
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
        !parse_digits(s.substr(14, 2), mi) || !parse_seconds(s.substr(17), sec_ns) || y < 1970 ||
        y > 2200 || mo < 1 || mo > 12 || d < 1 || d > 31 || h > 23 || mi > 59 ||
        sec_ns >= 61'000'000'000LL) {
        return false;
    }
    const auto days = days_from_civil(y, static_cast<unsigned>(mo), static_cast<unsigned>(d));
    ns = ((days * 24 + h) * 60 + mi) * 60 * 1'000'000'000LL + sec_ns;
    return true;
}

bool parse_hex_id(std::string_view s, std::uint32_t& id) {
    if (s.empty() || s.size() > 8) {
        return false;
    }
    std::uint32_t v = 0;
    for (char c : s) {
        const int h = hexval(c);
        if (h < 0) {
            return false;
        }
        v = (v << 4) | static_cast<std::uint32_t>(h);
    }
    id = v;
    return true;
}

// Sets id and flags from an id token: 3 digits (or fewer) 11-bit, 8 digits 29-bit; an 8-digit id
// with CAN_ERR_FLAG (bit 29) is an error frame as candump logs it.
bool set_id(std::string_view tok, Frame& f, std::string_view& error) {
    std::uint32_t id = 0;
    if (!parse_hex_id(tok, id)) {
        error = "bad CAN identifier";
        return false;
    }
    if (tok.size() == 8) {
        if ((id & 0x20000000U) != 0) {
            f.flags = Frame::kError;
            f.id = id & Frame::kExtMask;
            return true;
        }
        if (id > Frame::kExtMask) {
            error = "29-bit identifier out of range";
            return false;
        }
        f.flags = Frame::kExtended;
    } else if (id > Frame::kStdMask) {
        error = "11-bit identifier out of range";
        return false;
    }
    f.id = id;
    return true;
}

// The log-format frame text after the id: "11223344", "11.22.33", "R", "R3", "#1AABB".
bool parse_log_payload(std::string_view s, Frame& f, std::string_view& error) {
    std::size_t i = 0;
    std::size_t max = Frame::kMaxClassicLen;
    if (!s.empty() && s[0] == '#') {
        // CAN FD: one hex digit of flags, then data.
        if (s.size() < 2 || hexval(s[1]) < 0) {
            error = "bad CAN FD flags";
            return false;
        }
        f.flags = static_cast<std::uint8_t>(f.flags | Frame::kFd);
        if ((hexval(s[1]) & 1) != 0) {
            f.flags = static_cast<std::uint8_t>(f.flags | Frame::kBrs);
        }
        i = 2;
        max = Frame::kMaxFdLen;
    } else if (!s.empty() && (s[0] == 'R' || s[0] == 'r')) {
        f.flags = static_cast<std::uint8_t>(f.flags | Frame::kRtr);
        f.len = 0;
        if (s.size() >= 2) {
            const int d = hexval(s[1]);
            if (d < 0 || d > 8 || s.size() > 2) {
                error = "bad remote frame length";
                return false;
            }
            f.len = static_cast<std::uint8_t>(d);
        }
        return true;
    }
    std::size_t n = 0;
    while (i < s.size()) {
        if (s[i] == '.') {
            ++i;
            continue;
        }
        if (i + 1 >= s.size()) {
            error = "odd number of data digits";
            return false;
        }
        const int hi = hexval(s[i]);
        const int lo = hexval(s[i + 1]);
        if (hi < 0 || lo < 0) {
            error = "bad data byte";
            return false;
        }
        if (n == max) {
            error = "too many data bytes";
            return false;
        }
        f.data[n++] = static_cast<std::uint8_t>((hi << 4) | lo);
        i += 2;
    }
    if (f.fd() && fd_dlc_to_len(fd_len_to_dlc(n)) != n) {
        error = "CAN FD length not a valid DLC length";
        return false;
    }
    f.len = static_cast<std::uint8_t>(n);
    return true;
}

// Screen format after the interface: "123   [4]  11 22 33 44" or "123   [4]  remote request".
LineStatus parse_screen_rest(Cursor& c, std::string_view id_tok, TraceRecord& out,
                             std::string_view& error) {
    Frame& f = out.frame;
    if (!set_id(id_tok, f, error)) {
        return LineStatus::Error;
    }
    c.skip_space();
    auto len_tok = c.token();
    if (len_tok.size() < 3 || len_tok.front() != '[' || len_tok.back() != ']') {
        error = "expected a length such as [8]";
        return LineStatus::Error;
    }
    std::int64_t len = 0;
    if (!parse_digits(len_tok.substr(1, len_tok.size() - 2), len) || len > 64) {
        error = "bad length";
        return LineStatus::Error;
    }
    if (len > 8) {
        f.flags = static_cast<std::uint8_t>(f.flags | Frame::kFd);
    }
    c.skip_space();
    if (c.end - c.p >= 6 && std::string_view(c.p, 6) == "remote") {
        f.flags = static_cast<std::uint8_t>(f.flags | Frame::kRtr);
        f.len = static_cast<std::uint8_t>(len > 8 ? 8 : len);
        return LineStatus::Frame;
    }
    std::size_t n = 0;
    while (n < static_cast<std::size_t>(len)) {
        c.skip_space();
        auto b = c.token();
        if (b.size() != 2 || hexval(b[0]) < 0 || hexval(b[1]) < 0) {
            error = b.empty() ? std::string_view("fewer data bytes than the length says")
                              : std::string_view("bad data byte");
            return LineStatus::Error;
        }
        f.data[n++] = static_cast<std::uint8_t>((hexval(b[0]) << 4) | hexval(b[1]));
    }
    if (f.fd() && fd_dlc_to_len(fd_len_to_dlc(n)) != n) {
        error = "CAN FD length not a valid DLC length";
        return LineStatus::Error;
    }
    f.len = static_cast<std::uint8_t>(n);
    return LineStatus::Frame; // trailing text (candump -a ASCII) is ignored
}

} // namespace

LineStatus parse_log_line(std::string_view line, TraceRecord& out, std::string_view& error) {
    Cursor c{line.data(), line.data() + line.size()};
    c.skip_space();
    if (c.done() || *c.p == '#') {
        return LineStatus::Skip;
    }
    out.frame.flags = 0;
    out.frame.len = 0;
    out.has_ts = false;
    if (*c.p == '(') {
        const char* s = c.p + 1;
        const char* e = s;
        while (e != c.end && *e != ')') {
            ++e;
        }
        if (e == c.end) {
            error = "unterminated timestamp";
            return LineStatus::Error;
        }
        const std::string_view ts(s, static_cast<std::size_t>(e - s));
        if (!parse_seconds(ts, out.ts_ns) && !parse_date_time(ts, out.ts_ns)) {
            error = "bad timestamp";
            return LineStatus::Error;
        }
        out.has_ts = true;
        c.p = e + 1;
        c.skip_space();
    }
    out.iface = c.token();
    if (out.iface.empty()) {
        error = "missing interface name";
        return LineStatus::Error;
    }
    c.skip_space();
    const auto tok = c.token();
    const auto hash = tok.find('#');
    if (hash == std::string_view::npos) {
        if (tok.empty()) {
            error = "missing frame";
            return LineStatus::Error;
        }
        return parse_screen_rest(c, tok, out, error);
    }
    if (!set_id(tok.substr(0, hash), out.frame, error)) {
        return LineStatus::Error;
    }
    if (!parse_log_payload(tok.substr(hash + 1), out.frame, error)) {
        return LineStatus::Error;
    }
    return LineStatus::Frame;
}

ReadStatus LogReader::next(TraceRecord& record) {
    std::string_view line;
    bool too_long = false;
    while (input_.next_line(line, too_long)) {
        ++line_no_;
        if (too_long) {
            error_ =
                fmt::format("line {}: longer than {} bytes, skipped", line_no_, input_.capacity());
            return ReadStatus::Malformed;
        }
        std::string_view why;
        switch (parse_log_line(line, record, why)) {
        case LineStatus::Frame:
            return ReadStatus::Frame;
        case LineStatus::Skip:
            continue;
        case LineStatus::Error: {
            const auto shown = line.substr(0, 80);
            error_ = fmt::format("line {}: {}: '{}'", line_no_, why, shown);
            return ReadStatus::Malformed;
        }
        }
    }
    if (!input_.read_error().empty()) {
        error_ = fmt::format("read error after line {}: {}", line_no_, input_.read_error());
        return ReadStatus::Fatal;
    }
    return ReadStatus::End;
}

} // namespace codrive::dump
