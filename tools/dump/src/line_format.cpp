// SPDX-License-Identifier: Apache-2.0
// candump-like output lines with the decode, colours and JSON.
#include <codrive/dump/line_format.hpp>

#include <codrive/dump/text_append.hpp>
#include <codrive/dump/value_format.hpp>

#include <iterator>

namespace codrive::dump {
namespace {

constexpr char kHex[] = "0123456789ABCDEF";
constexpr std::string_view kReset = "\033[0m";
constexpr std::string_view kDim = "\033[2m";

std::string_view color_of(const Decoded& d) {
    switch (d.severity) {
    case Severity::Error:
        return "\033[1;31m";
    case Severity::Warning:
        return "\033[33m";
    default:
        break;
    }
    switch (d.service) {
    case Service::Nmt:
    case Service::Lss:
        return "\033[35m";
    case Service::Sync:
    case Service::Time:
        return "\033[34m";
    case Service::Emcy:
        return "\033[31m";
    case Service::Heartbeat:
        return "\033[32m";
    case Service::Sdo:
        return d.severity == Severity::Notice ? "\033[1;36m" : "\033[36m";
    case Service::Pdo:
        return "\033[0m";
    default:
        return "\033[2m";
    }
}

// |ns|, also of INT64_MIN.
std::uint64_t magnitude(std::int64_t ns) {
    return ns < 0 ? static_cast<std::uint64_t>(-(ns + 1)) + 1U : static_cast<std::uint64_t>(ns);
}

// A JSON number of seconds with microseconds: "12.000345", "-0.200000" (a time given by a library
// user, or a note's, may be negative; readers never give one).
void json_seconds(fmt::memory_buffer& out, std::int64_t ns) {
    const bool neg = ns < 0;
    const std::uint64_t a = magnitude(ns);
    fmt::format_to(std::back_inserter(out), "{}{}.{:06}", neg ? "-" : "", a / 1'000'000'000U,
                   (a % 1'000'000'000U) / 1000U);
}

// Seconds and microseconds, with a sign for negative deltas (out-of-order merged traces).
void seconds(fmt::memory_buffer& out, std::int64_t ns, int width) {
    const bool neg = ns < 0;
    const std::uint64_t a = magnitude(ns);
    const std::uint64_t us = a / 1000;
    text::Cursor c(out, 32);
    c.put('(');
    if (neg) {
        c.put('-');
    }
    c.uint(us / 1000000, static_cast<unsigned>(width));
    c.put('.');
    c.uint(us % 1000000, 6);
    c.put(')');
}

} // namespace

void append_json_string(fmt::memory_buffer& out, std::string_view s) {
    out.push_back('"');
    for (char c : s) {
        const auto u = static_cast<unsigned char>(c);
        if (c == '"' || c == '\\') {
            out.push_back('\\');
            out.push_back(c);
        } else if (u < 0x20) {
            const char esc[6] = {'\\', 'u', '0', '0', kHex[u >> 4], kHex[u & 0xF]};
            out.append(esc, esc + 6);
        } else {
            out.push_back(c);
        }
    }
    out.push_back('"');
}

void LineFormatter::timestamp(fmt::memory_buffer& out, bool has_ts, std::int64_t ts, bool advance) {
    if (has_ts && !have_first_) {
        have_first_ = true;
        first_ns_ = ts;
        prev_ns_ = ts;
    }
    switch (options_.time) {
    case TimeMode::None:
        return;
    case TimeMode::Absolute:
        if (has_ts) {
            seconds(out, ts, 1);
        } else {
            text::put(out, "(no timestamp)");
        }
        break;
    case TimeMode::Delta:
        if (has_ts) {
            seconds(out, ts - prev_ns_, 3);
        } else {
            text::put(out, "(-)");
        }
        break;
    case TimeMode::Zero:
        if (has_ts) {
            seconds(out, ts - first_ns_, 3);
        } else {
            text::put(out, "(-)");
        }
        break;
    }
    if (has_ts && advance) {
        prev_ns_ = ts;
    }
    text::put(out, "  ");
}

void LineFormatter::frame(fmt::memory_buffer& out, const TraceRecord& r, const Decoded& d) {
    const Frame& f = r.frame;
    if (options_.json) {
        auto it = std::back_inserter(out);
        text::put(out, "{");
        if (r.has_ts) {
            text::put(out, "\"ts\":");
            json_seconds(out, r.ts_ns);
            out.push_back(',');
        }
        text::put(out, "\"iface\":");
        append_json_string(out, r.iface);
        fmt::format_to(it, ",\"id\":{},\"ext\":{},\"rtr\":{},\"fd\":{},\"len\":{},\"data\":\"",
                       f.id, f.extended(), f.rtr(), f.fd(), f.len);
        if (!f.rtr()) {
            for (std::size_t i = 0; i < f.len; ++i) {
                out.push_back(kHex[f.data[i] >> 4]);
                out.push_back(kHex[f.data[i] & 0xF]);
            }
        }
        fmt::format_to(it, "\",\"service\":\"{}\"", to_string(d.service));
        if (d.node != 0) {
            fmt::format_to(it, ",\"node\":{}", d.node);
        }
        fmt::format_to(it, ",\"severity\":\"{}\",\"text\":", to_string(d.severity));
        append_json_string(out, std::string_view(d.text.data(), d.text.size()));
        text::put(out, "}\n");
        return;
    }
    if (options_.color && options_.time != TimeMode::None) {
        text::put(out, kDim);
    }
    timestamp(out, r.has_ts, r.ts_ns, true);
    if (options_.color && options_.time != TimeMode::None) {
        text::put(out, kReset);
    }
    {
        // Frame columns, written in one reserved region (this is the hot path).
        text::Cursor c(out, r.iface.size() + 32 + 3 * Frame::kMaxFdLen + 16);
        c.put(r.iface);
        if (r.iface.size() < 5) {
            c.spaces(5 - r.iface.size());
        }
        c.put("  ", 2);
        char* const start = c.pos();
        if (f.extended() || f.error()) {
            c.hex(f.id | (f.error() ? 0x20000000U : 0U), 8);
        } else {
            c.hex(f.id, 3);
        }
        c.put(f.len >= 10 ? std::string_view("  [") : std::string_view("   ["));
        c.uint(f.len);
        c.put("]  ", 3);
        if (f.rtr()) {
            c.put("remote request");
        } else {
            for (std::size_t i = 0; i < f.len; ++i) {
                if (i != 0) {
                    c.put(' ');
                }
                c.byte_hex(f.data[i]);
            }
        }
        if (d.text.size() == 0) {
            c.put('\n');
            return;
        }
        // Pad to the width of an 8-byte frame so decodes line up.
        constexpr std::size_t kColumn = 3 + 3 + 5 + 23 + 3;
        const auto used = static_cast<std::size_t>(c.pos() - start);
        c.spaces(used < kColumn ? kColumn - used : 2);
    }
    if (options_.color) {
        text::put(out, color_of(d));
    }
    out.append(d.text.data(), d.text.data() + d.text.size());
    if (options_.color) {
        text::put(out, kReset);
    }
    out.push_back('\n');
}

void LineFormatter::note(fmt::memory_buffer& out, const Note& n) {
    if (options_.json) {
        auto it = std::back_inserter(out);
        text::put(out, "{");
        if (n.timed) { // as a frame without a timestamp, a note without one has no "ts"
            text::put(out, "\"ts\":");
            json_seconds(out, n.ts_ns);
            out.push_back(',');
        }
        fmt::format_to(it, "\"service\":\"{}\",\"node\":{},\"event\":", to_string(n.service),
                       n.node);
        append_json_string(out, n.event);
        fmt::format_to(it, ",\"severity\":\"{}\",\"text\":", to_string(n.severity));
        append_json_string(out, n.text);
        text::put(out, "}\n");
        return;
    }
    timestamp(out, n.timed, n.ts_ns, false);
    // Notes have no frame: the frame columns are left blank.
    constexpr std::size_t kBlank = 5 + 2 + 3 + 3 + 5 + 23 + 3;
    out.push_back('-');
    for (std::size_t i = 1; i < kBlank; ++i) {
        out.push_back(' ');
    }
    if (options_.color) {
        text::put(out, n.severity == Severity::Error ? "\033[1;31m" : "\033[33m");
    }
    text::put(out, n.text);
    if (options_.color) {
        text::put(out, kReset);
    }
    out.push_back('\n');
}

} // namespace codrive::dump
