// SPDX-License-Identifier: Apache-2.0
// Hand-written candump text parsers (log and screen formats).
#include <codrive/dump/log_parser.hpp>

#include <codrive/dump/text_scan.hpp>

#include <fmt/format.h>

namespace codrive::dump {
namespace {

using scan::Cursor;
using scan::hexval;
using scan::parse_date_time;
using scan::parse_digits;
using scan::parse_seconds;

// Sets id and flags from an id token: 3 digits (or fewer) 11-bit, 8 digits 29-bit; an 8-digit id
// with CAN_ERR_FLAG (bit 29) is an error frame as candump logs it.
bool set_id(std::string_view tok, Frame& f, std::string_view& error) {
    std::uint32_t id = 0;
    if (!scan::parse_hex_u32(tok, id)) {
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
    const auto fd_flags = static_cast<std::uint8_t>(f.flags & (Frame::kFd | Frame::kBrs));
    if (!set_id(id_tok, f, error)) {
        return LineStatus::Error;
    }
    f.flags = static_cast<std::uint8_t>(f.flags | fd_flags);
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
    if (len > 8 || len_tok.size() == 4) {
        // candump prints CAN FD lengths with two digits ("[08]", "[12]"), classic ones as "[8]".
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
    Cursor c(line);
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
    auto tok = c.token();
    if (tok == "RX" || tok == "TX") {
        // candump -x: direction, then BRS ('B' or '-') and ESI ('E' or '-') of CAN FD frames.
        const auto brs = c.token();
        const auto esi = c.token();
        if ((brs != "B" && brs != "-") || (esi != "E" && esi != "-")) {
            error = "expected candump -x flags such as 'RX B -'";
            return LineStatus::Error;
        }
        if (brs == "B") {
            out.frame.flags = Frame::kFd | Frame::kBrs;
        }
        tok = c.token();
    }
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

namespace {
// candump -t d/z screen stamps count from zero; a -t a stamp is seconds since the epoch. Anything
// before 1973 is taken as relative.
constexpr std::int64_t kRelativeBelowNs = 100'000'000LL * 1'000'000'000LL;

bool is_screen_line(std::string_view line) {
    return line.find('#') == std::string_view::npos && line.find('[') != std::string_view::npos;
}
} // namespace

bool LogReader::looks_like_deltas() const {
    // The bytes after the current line are still in the buffer: look ahead at up to 1000 lines.
    std::string_view rest(reinterpret_cast<const char*>(input_.data()), input_.available());
    std::int64_t prev = -1;
    std::int64_t first = -1;
    bool all_equal = true;
    int seen = 0;
    TraceRecord r;
    for (int i = 0; i < 1000 && !rest.empty(); ++i) {
        const auto nl = rest.find('\n');
        auto line = rest.substr(0, nl);
        rest = nl == std::string_view::npos ? std::string_view() : rest.substr(nl + 1);
        if (!line.empty() && line.back() == '\r') {
            line.remove_suffix(1); // as next_line() does: CRLF files
        }
        std::string_view why;
        if (!is_screen_line(line) || parse_log_line(line, r, why) != LineStatus::Frame ||
            !r.has_ts || r.ts_ns >= kRelativeBelowNs) {
            continue;
        }
        if (prev >= 0 && r.ts_ns < prev) {
            return true; // a -t z stamp never goes back; deltas do
        }
        if (seen == 1) {
            first = r.ts_ns;
        } else if (seen > 1 && r.ts_ns != first) {
            all_equal = false;
        }
        prev = r.ts_ns;
        ++seen;
    }
    return seen >= 3 && all_equal; // 0, p, p, p...: a constant period printed as deltas
}

LineStatus LogReader::parse_line(std::string_view line, TraceRecord& out, std::string& why) {
    std::string_view w;
    const auto status = parse_log_line(line, out, w);
    if (status == LineStatus::Error) {
        why = w;
        return status;
    }
    if (status == LineStatus::Frame && out.has_ts && out.ts_ns < kRelativeBelowNs &&
        is_screen_line(line)) {
        if (relative_ == Relative::Unknown) {
            relative_ = looks_like_deltas() ? Relative::Delta : Relative::FromZero;
        }
        if (relative_ == Relative::Delta) {
            if (!add_trace_time(delta_sum_ns_, out.ts_ns, delta_sum_ns_)) {
                why = "the time deltas add up past the year 2255";
                return LineStatus::Error;
            }
            out.ts_ns = delta_sum_ns_;
        }
    }
    return status;
}

} // namespace codrive::dump
