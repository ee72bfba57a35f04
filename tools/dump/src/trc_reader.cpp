// SPDX-License-Identifier: Apache-2.0
// PEAK .trc trace reader (PEAK-System "PEAK CAN TRC File Format", versions 1.0-2.1).
#include <codrive/dump/trc_reader.hpp>

#include <codrive/dump/error_frame_build.hpp>
#include <codrive/dump/text_scan.hpp>

#include <fmt/format.h>
#include <linux/can/error.h>

namespace codrive::dump {
namespace {

using scan::Cursor;

// Column letters of the TRC format description: N message number, O time offset (ms), T type,
// B bus, I id, d direction (Rx/Tx), R reserved, L data length code, l data length, D data.
constexpr const char* kColumns10 = "NOILD";
constexpr const char* kColumns11 = "NOTILD";
constexpr const char* kColumns12 = "NOBTILD";
constexpr const char* kColumns13 = "NOBTIRLD";
constexpr const char* kColumns20 = "NOTIdlD";
constexpr const char* kColumns21 = "NOTBIdRLD";

// STARTTIME counts days from 1899-12-30 (the OLE automation date PCAN-View writes); the Unix
// epoch is day 25569.
constexpr std::int64_t kEpochDay = 25569;
constexpr std::int64_t kDayNs = 86'400'000'000'000LL;
// Trace times end at kMaxTraceTimeNs (the year 2255): a later start is refused.
constexpr std::int64_t kLastStartDay = kEpochDay + kMaxTraceTimeNs / kDayNs - 1;

bool parse_start_time(std::string_view s, std::int64_t& ns) {
    const auto dot = s.find('.');
    std::int64_t days = 0;
    if (!scan::parse_digits(s.substr(0, dot), days) || days < kEpochDay || days > kLastStartDay) {
        return false;
    }
    double frac = 0;
    if (dot != std::string_view::npos) {
        double scale = 0.1;
        for (char c : s.substr(dot + 1)) {
            if (!scan::is_digit(c)) {
                return false;
            }
            frac += (c - '0') * scale;
            scale /= 10;
        }
    }
    ns =
        (days - kEpochDay) * kDayNs + static_cast<std::int64_t>(frac * static_cast<double>(kDayNs));
    return true;
}

bool is_fd_type(std::string_view t) {
    return t == "FD" || t == "FB" || t == "FE" || t == "BI";
}

// PEAK error types (the id of a 1.x error frame, the first byte of a 2.x ER line).
std::uint8_t prot_type(std::uint32_t peak_type) {
    switch (peak_type) {
    case 1:
        return CAN_ERR_PROT_BIT;
    case 2:
        return CAN_ERR_PROT_FORM;
    case 4:
        return CAN_ERR_PROT_STUFF;
    default:
        return CAN_ERR_PROT_UNSPEC; // 8: "other error" (CRC, acknowledge, ...)
    }
}

// A PCAN status word (PCAN-Basic PCAN_ERROR_* bits) as a controller state.
TraceBusState status_state(std::uint32_t v) {
    if ((v & 0x10U) != 0) {
        return TraceBusState::BusOff;
    }
    if ((v & 0x40008U) != 0) { // BUSHEAVY / BUSPASSIVE
        return TraceBusState::Passive;
    }
    if ((v & 0x04U) != 0) { // BUSLIGHT: an error counter reached the warning limit
        return TraceBusState::Warning;
    }
    if ((v & 0x42U) != 0) { // OVERRUN / QOVERRUN
        return TraceBusState::RxOverflow;
    }
    return v == 0 ? TraceBusState::Active : TraceBusState::Unknown;
}

} // namespace

bool TrcReader::add_start(std::int64_t& ts_ns, std::string& why) const {
    if (!add_trace_time(ts_ns, start_ns_, ts_ns)) {
        why = "time offset too large: with STARTTIME it is past the year 2255";
        return false;
    }
    return true;
}

TrcReader::TrcReader(BufferedInput& input)
    : TextTraceReader(input), columns_(kColumns10), iface_("pcan") {}

void TrcReader::set_version(unsigned major, unsigned minor) {
    version_ = major * 100 + minor;
    switch (version_) {
    case 100:
        columns_ = kColumns10;
        break;
    case 101:
        columns_ = kColumns11;
        break;
    case 102:
        columns_ = kColumns12;
        break;
    case 103:
        columns_ = kColumns13;
        break;
    case 200:
        columns_ = kColumns20;
        break;
    default:
        columns_ = kColumns21;
        break;
    }
}

LineStatus TrcReader::parse_header(std::string_view line, std::string& why) {
    // ";$KEY=VALUE" lines carry the header; every other ';' line is a comment.
    if (line.size() < 2 || line[1] != '$') {
        return LineStatus::Skip;
    }
    const auto eq = line.find('=');
    if (eq == std::string_view::npos) {
        return LineStatus::Skip;
    }
    const auto key = line.substr(2, eq - 2);
    auto value = line.substr(eq + 1);
    while (!value.empty() && scan::is_space(value.back())) {
        value.remove_suffix(1);
    }
    if (key == "FILEVERSION") {
        std::int64_t major = 0;
        std::int64_t minor = 0;
        const auto dot = value.find('.');
        if (dot == std::string_view::npos || !scan::parse_digits(value.substr(0, dot), major) ||
            !scan::parse_digits(value.substr(dot + 1), minor) || major < 1 || major > 2 ||
            minor > 9 || (major == 1 && minor > 3) || (major == 2 && minor > 1)) {
            why = "unknown TRC file version (this reader knows 1.0 to 2.1)";
            return LineStatus::Error;
        }
        set_version(static_cast<unsigned>(major), static_cast<unsigned>(minor));
    } else if (key == "STARTTIME") {
        if (!parse_start_time(value, start_ns_)) {
            why = "bad STARTTIME (expected days since 1899-12-30, e.g. 45254.5)";
            return LineStatus::Error;
        }
        has_start_ = true;
    } else if (key == "COLUMNS") {
        std::string cols;
        for (char c : value) {
            if (c == ',') {
                continue;
            }
            if (std::string_view("NOTBIdRLlD").find(c) == std::string_view::npos) {
                why = fmt::format("unknown column '{}' in $COLUMNS", c);
                return LineStatus::Error;
            }
            cols += c;
        }
        if (cols.find('O') == std::string::npos || cols.find('I') == std::string::npos ||
            cols.empty() || cols.back() != 'D') {
            why = "$COLUMNS needs O, I and D (last)";
            return LineStatus::Error;
        }
        columns_ = cols;
    }
    return LineStatus::Skip;
}

LineStatus TrcReader::parse_status(std::string_view type, std::uint32_t id, const std::uint8_t* b,
                                   std::size_t n, Frame& f, std::string& why) {
    if (type == "ER" || type == "Error" || type == "ERROR") {
        // 2.x ER: type, direction (0 Tx, 1 Rx), ECC, Rx and Tx error counters. 1.x: the id is
        // the type and the four bytes are direction, ECC, Rx and Tx error counters.
        if (n == 4) {
            f = protocol_error_frame(prot_type(id), b[0] == 0, b[1] & 0x1FU, b[3], b[2]);
        } else if (n == 5) {
            f = protocol_error_frame(prot_type(b[0]), b[1] == 0, b[2] & 0x1FU, b[4], b[3]);
        } else {
            why = "an error frame line carries 4 or 5 bytes";
            return LineStatus::Error;
        }
        return LineStatus::Frame;
    }
    if (type == "EC") {
        if (n != 2) {
            why = "an error counter line carries 2 bytes (Rx and Tx counter)";
            return LineStatus::Error;
        }
        f = state_error_frame(state_from_counters(b[1], b[0]), b[1], b[0]);
        return LineStatus::Frame;
    }
    // ST (2.x) or Warng / id FFFFFFFF (1.x): a 32-bit PCAN status, big-endian.
    if (n != 4) {
        why = "a status line carries 4 bytes";
        return LineStatus::Error;
    }
    const std::uint32_t v = (static_cast<std::uint32_t>(b[0]) << 24) |
                            (static_cast<std::uint32_t>(b[1]) << 16) |
                            (static_cast<std::uint32_t>(b[2]) << 8) | b[3];
    f = state_error_frame(status_state(v));
    return LineStatus::Frame;
}

LineStatus TrcReader::parse_line(std::string_view line, TraceRecord& out, std::string& why) {
    Cursor c(line);
    c.skip_space();
    if (c.done()) {
        return LineStatus::Skip;
    }
    if (*c.p == ';') {
        return parse_header(c.rest(), why);
    }
    Frame& f = out.frame;
    f.flags = 0;
    f.len = 0;
    f.id = 0;
    std::string_view type = version_ < 101 ? "Rx" : "";
    std::uint32_t id = 0;
    bool have_id = false;
    std::int64_t length = -1;
    bool length_is_dlc = false;
    unsigned bus = 0;
    bool have_offset = false;
    for (char col : columns_) {
        if (col == 'D') {
            break;
        }
        const auto tok = c.token();
        if (tok.empty()) {
            why = "line ends before the data";
            return LineStatus::Error;
        }
        switch (col) {
        case 'N': {
            auto n = tok;
            if (n.back() == ')') {
                n.remove_suffix(1);
            }
            std::int64_t v = 0;
            if (!scan::parse_digits(n, v)) {
                why = "bad message number";
                return LineStatus::Error;
            }
            break;
        }
        case 'O':
            if (!scan::parse_scaled(tok, 1'000'000, out.ts_ns)) {
                why = "bad time offset";
                return LineStatus::Error;
            }
            have_offset = true;
            break;
        case 'T':
            type = tok;
            if (type == "EV") {
                return LineStatus::Skip; // a user event: text, no CAN data
            }
            if (type == "ST" || type == "ER" || type == "EC") {
                if (!have_offset) { // the time would be the previous line's
                    why = "a status line whose $COLUMNS puts the type before the time offset";
                    return LineStatus::Error;
                }
                // Status lines leave out columns in some writers: the bytes are what counts.
                std::uint8_t bytes[8];
                std::size_t n = 0;
                for (auto t = c.token(); !t.empty(); t = c.token()) {
                    std::uint8_t b = 0;
                    if (t == "-" || t == "Rx" || t == "Tx" || t.size() != 2) {
                        n = 0; // columns before the data
                        continue;
                    }
                    if (n == sizeof bytes) {
                        why = "more than 8 status bytes";
                        return LineStatus::Error;
                    }
                    if (!scan::parse_hex_byte(t, b)) {
                        why = "bad data byte";
                        return LineStatus::Error;
                    }
                    bytes[n++] = b;
                }
                const auto st = parse_status(type, 0, bytes, n, f, why);
                if (st == LineStatus::Frame) {
                    if (!add_start(out.ts_ns, why)) {
                        return LineStatus::Error;
                    }
                    out.has_ts = true;
                    out.iface = iface_;
                }
                return st;
            }
            if (type != "Rx" && type != "Tx" && type != "DT" && type != "RR" && type != "Warng" &&
                type != "Error" && !is_fd_type(type)) {
                why = "unknown message type";
                return LineStatus::Error;
            }
            break;
        case 'B': {
            std::int64_t v = 0;
            if (!scan::parse_digits(tok, v) || v > 255) {
                why = "bad bus number";
                return LineStatus::Error;
            }
            bus = static_cast<unsigned>(v);
            break;
        }
        case 'I':
            if (!scan::parse_hex_u32(tok, id) ||
                (tok.size() == 8 && id > Frame::kExtMask && id != 0xFFFFFFFFU)) {
                why = "bad CAN identifier";
                return LineStatus::Error;
            }
            if (tok.size() <= 4 && id > Frame::kStdMask) {
                why = "11-bit identifier out of range";
                return LineStatus::Error;
            }
            have_id = true;
            if (tok.size() > 4) {
                f.flags = Frame::kExtended;
            }
            break;
        case 'd':
            if (tok != "Rx" && tok != "Tx") {
                why = "expected Rx or Tx";
                return LineStatus::Error;
            }
            break;
        case 'R':
            break;
        case 'L':
        case 'l':
            if (!scan::parse_digits(tok, length) || length > 64) {
                why = "bad data length";
                return LineStatus::Error;
            }
            length_is_dlc = col == 'L';
            break;
        default:
            break;
        }
    }
    if (!have_id || length < 0) {
        why = "missing id or length column";
        return LineStatus::Error;
    }
    if (!add_start(out.ts_ns, why)) {
        return LineStatus::Error;
    }
    out.has_ts = true;
    iface_ = bus == 0 ? std::string("pcan") : fmt::format("pcan{}", bus);
    out.iface = iface_;
    // The data column: bytes, or RTR (1.x), or ERROR then bytes (1.0 error frames).
    auto first = c.token();
    bool error_frame = type == "Error" || type == "Warng" || id == 0xFFFFFFFFU;
    if (first == "RTR" || type == "RR") {
        f.flags = static_cast<std::uint8_t>(f.flags | Frame::kRtr);
        f.id = id;
        f.len = static_cast<std::uint8_t>(length > 8 ? 8 : length);
        return LineStatus::Frame;
    }
    if (first == "ERROR") {
        error_frame = true;
        first = c.token();
    }
    const bool fd = is_fd_type(type);
    std::size_t want = static_cast<std::size_t>(length);
    if (fd && (length_is_dlc || fd_dlc_to_len(fd_len_to_dlc(want)) != want)) {
        // An `L` column is the DLC (9..15 mean 12..64 bytes); a length no CAN FD frame can have
        // (9, 10, 11, 13, 14, 15) in an `l` column is a DLC too.
        if (length > 15) {
            why = "bad CAN FD DLC";
            return LineStatus::Error;
        }
        want = fd_dlc_to_len(static_cast<std::uint8_t>(length));
    } else if (!fd && want > 8) {
        why = "a classic CAN frame carries at most 8 bytes";
        return LineStatus::Error;
    } else if (fd && fd_dlc_to_len(fd_len_to_dlc(want)) != want) {
        why = "CAN FD length not a valid DLC length";
        return LineStatus::Error;
    }
    std::size_t n = 0;
    for (auto t = first; n < want; t = c.token()) {
        if (t.empty()) {
            why = "fewer data bytes than the length says";
            return LineStatus::Error;
        }
        if (!scan::parse_hex_byte(t, f.data[n])) {
            why = "bad data byte";
            return LineStatus::Error;
        }
        ++n;
    }
    if (error_frame) {
        std::uint8_t b[8] = {};
        std::copy_n(f.data.begin(), std::min<std::size_t>(n, 8), b);
        return parse_status(type == "Warng" || id == 0xFFFFFFFFU ? "ST" : "Error", id, b, n, f,
                            why);
    }
    if (fd) {
        f.flags = static_cast<std::uint8_t>(f.flags | Frame::kFd);
        if (type == "FB" || type == "BI") {
            f.flags = static_cast<std::uint8_t>(f.flags | Frame::kBrs);
        }
    }
    f.id = id;
    f.len = static_cast<std::uint8_t>(n);
    return LineStatus::Frame; // trailing text (1.0 "------BUSLIGHT" notes) is ignored
}

} // namespace codrive::dump
