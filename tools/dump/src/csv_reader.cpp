// SPDX-License-Identifier: Apache-2.0
// CSV trace reader: columns found by their header names.
#include <codrive/dump/csv_reader.hpp>

#include <codrive/dump/error_frame_build.hpp>
#include <codrive/dump/text_scan.hpp>

#include <fmt/format.h>

#include <array>

namespace codrive::dump {
namespace {

std::string_view trim(std::string_view s) {
    while (!s.empty() && (scan::is_space(s.front()) || s.front() == '"')) {
        s.remove_prefix(1);
    }
    while (!s.empty() && (scan::is_space(s.back()) || s.back() == '"')) {
        s.remove_suffix(1);
    }
    return s;
}

// Splits on `sep` (quotes only trimmed: CAN exports do not put separators inside fields).
template <typename F>
void for_each_field(std::string_view line, char sep, F&& f) {
    std::size_t i = 0;
    for (;;) {
        const auto e = line.find(sep, i);
        f(trim(line.substr(i, e == std::string_view::npos ? std::string_view::npos : e - i)));
        if (e == std::string_view::npos) {
            return;
        }
        i = e + 1;
    }
}

bool any_of(std::string_view name, std::initializer_list<std::string_view> names) {
    for (auto n : names) {
        if (scan::iequals(name, n)) {
            return true;
        }
    }
    return false;
}

using scan::contains_ci;

// "D1", "d0", "Byte 3", "Data7", "B2", "data[4]" - one column per data byte.
bool is_byte_column(std::string_view name) {
    std::size_t i = 0;
    while (i < name.size() &&
           ((name[i] >= 'a' && name[i] <= 'z') || (name[i] >= 'A' && name[i] <= 'Z'))) {
        ++i;
    }
    const auto letters = name.substr(0, i);
    auto rest = name.substr(i);
    while (!rest.empty() && (rest.front() == ' ' || rest.front() == '[')) {
        rest.remove_prefix(1);
    }
    if (!rest.empty() && rest.back() == ']') {
        rest.remove_suffix(1);
    }
    std::int64_t n = 0;
    return any_of(letters, {"d", "b", "db", "byte", "data"}) && scan::parse_digits(rest, n) &&
           n <= 64;
}

bool truthy(std::string_view v) {
    return any_of(v, {"1", "true", "yes", "x", "ext", "rtr", "y"});
}

int base64_value(char c) {
    if (c >= 'A' && c <= 'Z') {
        return c - 'A';
    }
    if (c >= 'a' && c <= 'z') {
        return c - 'a' + 26;
    }
    if (c >= '0' && c <= '9') {
        return c - '0' + 52;
    }
    return c == '+' ? 62 : (c == '/' ? 63 : -1);
}

bool decode_base64(std::string_view s, Frame& f, std::size_t& n) {
    std::uint32_t acc = 0;
    int bits = 0;
    n = 0;
    for (char c : s) {
        if (c == '=') {
            break;
        }
        const int v = base64_value(c);
        if (v < 0) {
            return false;
        }
        acc = (acc << 6) | static_cast<std::uint32_t>(v);
        bits += 6;
        if (bits >= 8) {
            bits -= 8;
            if (n == Frame::kMaxFdLen) {
                return false;
            }
            f.data[n++] = static_cast<std::uint8_t>(acc >> bits);
        }
    }
    return true;
}

bool decode_hex_data(std::string_view s, Frame& f, std::size_t& n) {
    n = 0;
    std::size_t i = 0;
    while (i < s.size()) {
        if (scan::is_space(s[i]) || s[i] == '-' || s[i] == ':') {
            ++i;
            continue;
        }
        std::uint8_t b = 0;
        if (i + 1 >= s.size() || !scan::parse_hex_byte(s.substr(i, 2), b) ||
            n == Frame::kMaxFdLen) {
            return false;
        }
        f.data[n++] = b;
        i += 2;
    }
    return true;
}

// "12.345.678.901": seconds, then groups of three digits for ms, µs and ns, as HMS/IXXAT
// exports write "Time (abs)" (CANnector Log user manual 4.01.0091.21000, section 6.1: "format:
// s.ms.µs.ns"). False if `v` has fewer than two dots, so plain decimals go the usual way.
bool parse_dotted_time(std::string_view v, std::int64_t& ns) {
    const auto dot = v.find('.');
    if (dot == std::string_view::npos || v.find('.', dot + 1) == std::string_view::npos) {
        return false;
    }
    std::int64_t secs = 0;
    if (!scan::parse_digits(v.substr(0, dot), secs) || secs > kMaxTraceTimeS) {
        return false;
    }
    std::int64_t total = secs;
    auto rest = v.substr(dot + 1);
    int groups = 0;
    for (; !rest.empty() && groups < 3; ++groups) {
        const auto end = rest.find('.');
        const auto g = rest.substr(0, end);
        std::int64_t x = 0;
        if (g.size() != 3 || !scan::parse_digits(g, x)) {
            return false;
        }
        total = total * 1000 + x;
        rest = end == std::string_view::npos ? std::string_view() : rest.substr(end + 1);
    }
    if (!rest.empty()) {
        return false;
    }
    for (; groups < 3; ++groups) {
        total *= 1000;
    }
    if (total > kMaxTraceTimeNs) {
        return false; // 9000000000.999.999.999: the groups pass the bound
    }
    ns = total;
    return true;
}

} // namespace

bool looks_like_csv_header(std::string_view line) {
    const char sep = line.find(',') != std::string_view::npos ? ',' : ';';
    bool id = false;
    bool data = false;
    int fields = 0;
    for_each_field(line, sep, [&](std::string_view name) {
        ++fields;
        id = id || any_of(name, {"id", "arbitration_id", "can id", "can-id", "canid", "identifier",
                                 "id (hex)", "id(hex)", "message id", "msg id"});
        data = data || any_of(name, {"data", "data (hex)", "payload", "data bytes"}) ||
               is_byte_column(name);
    });
    return fields >= 2 && id && data;
}

LineStatus CsvReader::parse_header(std::string_view line, std::string& why) {
    if (!looks_like_csv_header(line)) {
        why = "not a CSV header with an id and a data column";
        return LineStatus::Error;
    }
    sep_ = line.find(',') != std::string_view::npos ? ',' : ';';
    ids_padded_to_8_ = scan::iequals(trim(line), "ID,Data Bytes"); // SavvyCAN "Generic ID/Data CSV"
    bool have_time = false;
    for_each_field(line, sep_, [&](std::string_view name) {
        Role r = Role::Ignore;
        if (contains_ci(name, "time")) {
            // One time column is read: the first that is not an interval ("Time Delta",
            // "Time (rel)"); with "Timestamp,Time Delta" the delta would otherwise overwrite
            // the timestamp, and its unit the timestamp's.
            if (have_time || contains_ci(name, "delta") || contains_ci(name, "diff") ||
                contains_ci(name, "rel") || contains_ci(name, "interval")) {
                roles_.push_back(Role::Ignore);
                return;
            }
            have_time = true;
            r = Role::Time;
            if (contains_ci(name, "ms")) {
                time_unit_ns_ = 1'000'000;
            } else if (contains_ci(name, "us") || contains_ci(name, "\xC2\xB5s") ||
                       scan::iequals(name, "time stamp")) {
                time_unit_ns_ = 1'000;
            }
        } else if (any_of(name, {"id", "arbitration_id", "can id", "can-id", "canid", "identifier",
                                 "id (hex)", "id(hex)", "message id", "msg id"})) {
            r = Role::Id;
            base64_ = base64_ || scan::iequals(name, "arbitration_id");
        } else if (any_of(name, {"extended", "ext", "ide", "is_extended_id"})) {
            r = Role::Extended;
        } else if (any_of(name, {"remote", "rtr", "is_remote_frame"})) {
            r = Role::Remote;
        } else if (any_of(name, {"error", "is_error_frame", "errorframe"})) {
            r = Role::Error;
        } else if (any_of(name, {"dlc", "len", "length", "data length", "datalength"})) {
            r = Role::Length;
        } else if (any_of(name, {"data", "data (hex)", "payload", "data bytes"})) {
            r = Role::Data;
        } else if (is_byte_column(name)) {
            r = Role::Byte;
        } else if (any_of(name, {"bus", "channel", "chn", "ch"})) {
            r = Role::Bus;
        }
        roles_.push_back(r);
    });
    header_done_ = true;
    return LineStatus::Skip;
}

LineStatus CsvReader::parse_line(std::string_view line, TraceRecord& out, std::string& why) {
    if (trim(line).empty()) {
        return LineStatus::Skip;
    }
    if (!header_done_) {
        return parse_header(line, why);
    }
    Frame& f = out.frame;
    f.flags = 0;
    f.len = 0;
    out.has_ts = false;
    out.iface = "csv";
    std::int64_t length = -1;
    std::size_t n = 0;
    std::size_t bytes_seen = 0;
    bool have_id = false;
    bool have_ext_column = false;
    bool ext = false;
    bool rtr = false;
    bool err = false;
    std::size_t id_digits = 0;
    std::uint32_t id = 0;
    std::size_t col = 0;
    bool ok = true;
    for_each_field(line, sep_, [&](std::string_view v) {
        if (!ok || col >= roles_.size()) {
            ++col;
            return;
        }
        switch (roles_[col++]) {
        case Role::Time:
            if (!scan::parse_scaled(v, time_unit_ns_, out.ts_ns) &&
                (time_unit_ns_ != 1'000'000'000 || !parse_dotted_time(v, out.ts_ns))) {
                why = "bad timestamp";
                ok = false;
            }
            out.has_ts = true;
            break;
        case Role::Id: {
            auto t = v;
            if (!t.empty() && (t.back() == 'h' || t.back() == 'H')) {
                t.remove_suffix(1);
            }
            if (!scan::parse_hex_u32(t, id, true)) {
                why = "bad CAN identifier";
                ok = false;
            }
            id_digits = t.size() > 2 && t[1] == 'x' ? t.size() - 2 : t.size();
            have_id = true;
            break;
        }
        case Role::Extended:
            have_ext_column = true;
            ext = truthy(v);
            break;
        case Role::Remote:
            rtr = truthy(v);
            break;
        case Role::Error:
            err = truthy(v);
            break;
        case Role::Length:
            if (!scan::parse_digits(v, length) || length > 64) {
                why = "bad length";
                ok = false;
            }
            break;
        case Role::Data:
            if (!(base64_ ? decode_base64(v, f, n) : decode_hex_data(v, f, n))) {
                why = "bad data";
                ok = false;
            }
            bytes_seen = n;
            break;
        case Role::Byte:
            if (!v.empty()) {
                std::uint32_t b = 0;
                if (n == Frame::kMaxFdLen || v.size() > 2 || !scan::parse_hex_u32(v, b)) {
                    why = "bad data byte";
                    ok = false;
                    break;
                }
                f.data[n++] = static_cast<std::uint8_t>(b);
            }
            bytes_seen = n;
            break;
        case Role::Bus:
            iface_ = fmt::format("can{}", v);
            out.iface = iface_;
            break;
        case Role::Ignore:
            break;
        }
    });
    if (!ok) {
        return LineStatus::Error;
    }
    if (!have_id) {
        why = "no id";
        return LineStatus::Error;
    }
    if (err) {
        f = protocol_error_frame(0, false, 0);
        return LineStatus::Frame;
    }
    if (!have_ext_column) {
        // SavvyCAN's generic CSV writes every id with 8 digits and reads back > 7FF as 29-bit.
        ext = id > Frame::kStdMask || (id_digits == 8 && !ids_padded_to_8_);
    }
    if (id > (ext ? Frame::kExtMask : Frame::kStdMask)) {
        why = ext ? "29-bit identifier out of range" : "11-bit identifier out of range";
        return LineStatus::Error;
    }
    f.id = id;
    f.flags = ext ? Frame::kExtended : 0;
    if (length >= 0) {
        if (rtr) {
            bytes_seen = static_cast<std::size_t>(length);
        } else if (static_cast<std::size_t>(length) > bytes_seen) {
            why = "fewer data bytes than the length says";
            return LineStatus::Error;
        }
        n = static_cast<std::size_t>(length); // per-byte columns past the length are padding
    } else {
        n = bytes_seen;
    }
    if (rtr) {
        f.flags = static_cast<std::uint8_t>(f.flags | Frame::kRtr);
        f.len = static_cast<std::uint8_t>(n > 8 ? 8 : n);
        return LineStatus::Frame;
    }
    if (n > 8) {
        if (fd_dlc_to_len(fd_len_to_dlc(n)) != n) {
            why = "CAN FD length not a valid DLC length";
            return LineStatus::Error;
        }
        f.flags = static_cast<std::uint8_t>(f.flags | Frame::kFd);
    }
    f.len = static_cast<std::uint8_t>(n);
    return LineStatus::Frame;
}

} // namespace codrive::dump
