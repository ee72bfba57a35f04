// SPDX-License-Identifier: Apache-2.0
// Vector ASC log reader (Vector "CAN, Log & Trigger ASC Logging Format", CAN and CAN FD events).
#include <codrive/dump/asc_reader.hpp>

#include <codrive/dump/error_frame_build.hpp>
#include <codrive/dump/text_scan.hpp>

#include <fmt/format.h>
#include <linux/can/error.h>

#include <array>

namespace codrive::dump {
namespace {

using scan::Cursor;

// English month abbreviations, then the German ones CANoe writes on German Windows.
constexpr std::array<std::string_view, 12> kMonthsEn = {"jan", "feb", "mar", "apr", "may", "jun",
                                                        "jul", "aug", "sep", "oct", "nov", "dec"};
constexpr std::array<std::string_view, 12> kMonthsDe = {"jan", "feb", "mär", "apr", "mai", "jun",
                                                        "jul", "aug", "sep", "okt", "nov", "dez"};

int month_number(std::string_view m) {
    for (std::size_t i = 0; i < 12; ++i) {
        if (scan::istarts_with(m, kMonthsEn[i]) || scan::istarts_with(m, kMonthsDe[i]) ||
            (i == 2 && scan::istarts_with(m, "mrz"))) {
            return static_cast<int>(i) + 1;
        }
    }
    return 0;
}

// The details CANoe writes after "ErrorFrame": "ECC: 10100010" (an SJA1000 error code capture
// register in binary), "Flags = 0xe CodeExt = 0x20a2 Code = 0x82 ..." (flag 2: Code is the
// CAN-Core error register, flag 1: an SJA1000 ECC), or in CANFD events a text ("Not Acknowledge
// error, dominant error flag ..."). Without details: an unspecified protocol error.
Frame error_frame_details(std::string_view rest, bool tx) {
    Cursor c(rest);
    const auto first = c.token();
    if (first == "ECC:") {
        const auto bits = c.token();
        std::uint8_t ecc = 0;
        bool ok = bits.size() == 8;
        for (std::size_t i = 0; ok && i < 8; ++i) {
            ok = bits[i] == '0' || bits[i] == '1';
            ecc = static_cast<std::uint8_t>((ecc << 1) | (bits[i] == '1' ? 1 : 0));
        }
        return ok ? sja1000_ecc_error_frame(ecc) : protocol_error_frame(0, tx, 0);
    }
    if (first == "Flags") {
        std::uint32_t flags = 0;
        std::uint32_t code = 0;
        bool have_flags = c.token() == "=" && scan::parse_hex_u32(c.token(), flags, true);
        bool have_code = false;
        for (auto t = c.token(); have_flags && !t.empty() && !have_code; t = c.token()) {
            have_code =
                t == "Code" && c.token() == "=" && scan::parse_hex_u32(c.token(), code, true);
        }
        if (have_code && code <= 0xFF && (flags & 2U) != 0) {
            return can_core_error_frame(static_cast<std::uint8_t>(code));
        }
        if (have_code && code <= 0xFF && (flags & 1U) != 0) {
            return sja1000_ecc_error_frame(static_cast<std::uint8_t>(code));
        }
        return protocol_error_frame(0, tx, 0);
    }
    if (scan::contains_ci(rest, "acknowledge")) {
        return no_ack_error_frame(CAN_ERR_PROT_UNSPEC, tx, CAN_ERR_PROT_LOC_UNSPEC);
    }
    static constexpr struct {
        std::string_view word;
        std::uint8_t prot;
        std::uint8_t location;
    } kWords[] = {{"stuff", CAN_ERR_PROT_STUFF, 0},
                  {"form", CAN_ERR_PROT_FORM, 0},
                  {"crc", CAN_ERR_PROT_UNSPEC, CAN_ERR_PROT_LOC_CRC_SEQ},
                  {"bit error", CAN_ERR_PROT_BIT, 0}};
    for (const auto& w : kWords) {
        if (scan::contains_ci(rest, w.word)) {
            return protocol_error_frame(w.prot, tx, w.location);
        }
    }
    return protocol_error_frame(0, tx, 0);
}

bool is_time_token(std::string_view t) {
    return !t.empty() && scan::is_digit(t[0]) && t.find('.') != std::string_view::npos;
}

bool parse_decimal(std::string_view t, std::uint32_t& v) {
    std::int64_t x = 0;
    if (!scan::parse_digits(t, x) || x > 0xFFFFFFFFLL) {
        return false;
    }
    v = static_cast<std::uint32_t>(x);
    return true;
}

} // namespace

LineStatus AscReader::stamp(std::int64_t t_ns, TraceRecord& out, std::string& why) {
    if (relative_) {
        if (!add_trace_time(last_ns_, t_ns, last_ns_)) {
            why = "the relative times add up past the year 2255";
            return LineStatus::Error;
        }
        t_ns = last_ns_;
    }
    if (!add_trace_time(start_ns_, t_ns, out.ts_ns)) {
        why = "the date plus this time is past the year 2255";
        return LineStatus::Error;
    }
    out.has_ts = true;
    return LineStatus::Frame;
}

LineStatus AscReader::parse_date(std::string_view rest, std::string& why) {
    // "Thu Nov 24 01:02:03.456 pm 2022" (also without milliseconds or am/pm).
    Cursor c(rest);
    (void)c.token(); // weekday
    const int month = month_number(c.token());
    std::int64_t day = 0;
    const bool day_ok = scan::parse_digits(c.token(), day);
    const auto time = c.token();
    auto next = c.token();
    std::int64_t hour_shift = 0;
    const bool twelve_hour = scan::iequals(next, "pm") || scan::iequals(next, "am");
    if (twelve_hour) {
        hour_shift = scan::iequals(next, "pm") ? 12 : 0;
        next = c.token();
    }
    std::int64_t year = 0;
    std::int64_t h = 0;
    std::int64_t m = 0;
    std::int64_t sec_ns = 0;
    std::int64_t days = 0;
    if (!day_ok || time.size() < 8 || time[2] != ':' || time[5] != ':' ||
        !scan::parse_digits(time.substr(0, 2), h) || !scan::parse_digits(time.substr(3, 2), m) ||
        !scan::parse_scaled(time.substr(6), 1'000'000'000LL, sec_ns) ||
        !scan::parse_digits(next, year) || h > 23 || m > 59 ||
        !scan::days_since_epoch(year, month, day, days)) {
        why = "unreadable date (expected e.g. 'date Thu Nov 24 01:02:03.456 pm 2022'); "
              "timestamps count from the start of the measurement";
        return LineStatus::Error;
    }
    if (twelve_hour) {
        h = h % 12 + hour_shift; // 12:xx am is just after midnight, 12:xx pm just after noon
    }
    start_ns_ = ((days * 24 + h) * 60 + m) * 60 * 1'000'000'000LL + sec_ns;
    return LineStatus::Skip;
}

bool AscReader::parse_id(std::string_view tok, Frame& f) const {
    f.flags = 0;
    if (!tok.empty() && (tok.back() == 'x' || tok.back() == 'X')) {
        tok.remove_suffix(1);
        f.flags = Frame::kExtended;
    }
    std::uint32_t id = 0;
    if (!(hex_ ? scan::parse_hex_u32(tok, id) : parse_decimal(tok, id))) {
        return false;
    }
    f.id = id;
    return id <= (f.extended() ? Frame::kExtMask : Frame::kStdMask);
}

bool AscReader::parse_byte(std::string_view tok, std::uint8_t& b) const {
    if (hex_) {
        std::uint32_t v = 0;
        if (tok.empty() || tok.size() > 2 || !scan::parse_hex_u32(tok, v)) {
            return false;
        }
        b = static_cast<std::uint8_t>(v);
        return true;
    }
    std::uint32_t v = 0;
    if (!parse_decimal(tok, v) || v > 255) {
        return false;
    }
    b = static_cast<std::uint8_t>(v);
    return true;
}

LineStatus AscReader::parse_fd(std::string_view rest, TraceRecord& out, std::string& why) {
    Cursor c(rest);
    Frame& f = out.frame;
    const auto ch = c.token();
    const auto dir = c.token();
    const auto id_tok = c.token();
    iface_ = fmt::format("can{}", ch);
    out.iface = iface_;
    if (dir != "Rx" && dir != "Tx") {
        return LineStatus::Skip; // e.g. "CANFD 1 Statistic:"
    }
    if (id_tok == "ErrorFrame") {
        f = error_frame_details(c.rest(), dir == "Tx");
        return LineStatus::Frame;
    }
    if (!parse_id(id_tok, f)) {
        why = "bad CAN identifier";
        return LineStatus::Error;
    }
    auto brs = c.token();
    if (brs != "0" && brs != "1") {
        brs = c.token(); // the optional symbolic name came first
    }
    const auto esi = c.token();
    const auto dlc_tok = c.token();
    const auto len_tok = c.token();
    std::uint32_t dlc = 0;
    std::int64_t len = 0;
    if ((brs != "0" && brs != "1") || (esi != "0" && esi != "1") ||
        !scan::parse_hex_u32(dlc_tok, dlc) || dlc > 15 || !scan::parse_digits(len_tok, len) ||
        len > 64) {
        why = "expected <brs> <esi> <dlc> <data length> after the id of a CANFD event";
        return LineStatus::Error;
    }
    // A classic frame may have a DLC of 9..15 with 8 bytes; a remote frame has no data.
    const bool len_fits =
        static_cast<std::size_t>(len) == fd_dlc_to_len(static_cast<std::uint8_t>(dlc)) ||
        (dlc > 8 && len == 8) || len == 0;
    if (!len_fits) {
        why = "data length does not match the DLC";
        return LineStatus::Error;
    }
    for (std::int64_t i = 0; i < len; ++i) {
        if (!parse_byte(c.token(), f.data[static_cast<std::size_t>(i)])) {
            why = "bad or missing data byte";
            return LineStatus::Error;
        }
    }
    f.len = static_cast<std::uint8_t>(len);
    // <duration> <bit count> <flags>: EDL (0x1000) says CAN FD, 0x10 a remote frame.
    (void)c.token();
    (void)c.token();
    std::uint32_t flags = 0x1000;
    if (const auto flags_tok = c.token(); !flags_tok.empty()) {
        if (!scan::parse_hex_u32(flags_tok, flags)) {
            why = "bad message flags";
            return LineStatus::Error;
        }
    }
    // More than 8 data bytes can only be CAN FD, whatever the flags say (python-can's test
    // files have such lines with flags 0): the frame is kept, not dropped.
    if ((flags & 0x1000U) != 0 || len > 8) {
        f.flags = static_cast<std::uint8_t>(f.flags | Frame::kFd | (brs == "1" ? Frame::kBrs : 0));
    } else if ((flags & 0x10U) != 0) {
        f.flags = static_cast<std::uint8_t>(f.flags | Frame::kRtr);
        f.len = static_cast<std::uint8_t>(dlc > 8 ? 8 : dlc);
        return LineStatus::Frame;
    }
    if (len == 0 && dlc != 0) {
        why = "data length does not match the DLC";
        return LineStatus::Error;
    }
    return LineStatus::Frame;
}

LineStatus AscReader::parse_line(std::string_view line, TraceRecord& out, std::string& why) {
    Cursor c(line);
    const auto first = c.token();
    if (first.empty() || first.substr(0, 2) == "//") {
        return LineStatus::Skip;
    }
    if (first == "date") {
        return parse_date(c.rest(), why);
    }
    if (first == "base") {
        const auto base = c.token();
        (void)c.token(); // "timestamps"
        const auto mode = c.token();
        if ((base != "hex" && base != "dec") || (mode != "absolute" && mode != "relative")) {
            why = "expected 'base hex|dec timestamps absolute|relative'";
            return LineStatus::Error;
        }
        hex_ = base == "hex";
        relative_ = mode == "relative";
        return LineStatus::Skip;
    }
    if (first == "internal" || first == "no" || first == "Begin" || first == "End") {
        return LineStatus::Skip;
    }
    std::int64_t t_ns = 0;
    if (!is_time_token(first) || !scan::parse_seconds(first, t_ns)) {
        why = "not an ASC header or event line";
        return LineStatus::Error;
    }
    const auto ch = c.token();
    if (ch == "CANFD") {
        const auto s = parse_fd(c.rest(), out, why);
        return s == LineStatus::Frame ? stamp(t_ns, out, why) : s;
    }
    std::int64_t channel = 0;
    if (!scan::parse_digits(ch, channel)) {
        return LineStatus::Skip; // "Start of measurement", "CAN 1 Status:...", system variables
    }
    const auto id_tok = c.token();
    Frame& f = out.frame;
    iface_ = fmt::format("can{}", channel);
    out.iface = iface_;
    if (id_tok == "ErrorFrame") {
        f = error_frame_details(c.rest(), false);
        return stamp(t_ns, out, why);
    }
    const auto dir = c.token();
    if (dir != "Rx" && dir != "Tx") {
        return LineStatus::Skip; // "1 Statistic: ..." and other channel events
    }
    if (!parse_id(id_tok, f)) {
        why = "bad CAN identifier";
        return LineStatus::Error;
    }
    const auto kind = c.token();
    const auto dlc_tok = c.token();
    std::uint32_t dlc = 0;
    if (kind == "r") {
        f.flags = static_cast<std::uint8_t>(f.flags | Frame::kRtr);
        f.len = 0;
        if (!dlc_tok.empty() && scan::parse_hex_u32(dlc_tok, dlc) && dlc <= 15) {
            f.len = static_cast<std::uint8_t>(dlc > 8 ? 8 : dlc);
        }
        return stamp(t_ns, out, why);
    }
    if (kind != "d" || !scan::parse_hex_u32(dlc_tok, dlc)) {
        why = "expected 'd <dlc>' or 'r' after the direction";
        return LineStatus::Error;
    }
    if (dlc > 15) {
        // python-can writes a 64-byte frame not marked CAN FD as "d 40": not a CAN frame.
        why = fmt::format("DLC 0x{:X} is not a CAN DLC (0 to F); a classic CAN frame carries at "
                          "most 8 bytes, and CAN FD frames are CANFD events",
                          dlc);
        return LineStatus::Error;
    }
    const std::size_t n = dlc > 8 ? 8 : dlc; // a DLC of 9..15 still carries 8 bytes
    for (std::size_t i = 0; i < n; ++i) {
        const auto b = c.token();
        if (b.empty()) {
            why = "fewer data bytes than the DLC says";
            return LineStatus::Error;
        }
        if (!parse_byte(b, f.data[i])) {
            why = "bad data byte";
            return LineStatus::Error;
        }
    }
    f.len = static_cast<std::uint8_t>(n);
    // "Length = ... BitCount = ... ID = ..." after the data is ignored.
    return stamp(t_ns, out, why);
}

} // namespace codrive::dump
