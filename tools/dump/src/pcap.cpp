// SPDX-License-Identifier: Apache-2.0
// pcap / pcapng SocketCAN reader and pcap writer.
#include <codrive/dump/pcap.hpp>

#include "pcap_format.hpp"

#include <codrive/core/endian.hpp>

#include <fmt/format.h>

#include <cerrno>
#include <cstring>

namespace codrive::dump {
namespace {

using namespace pcap_format;

constexpr std::size_t kMaxBlock = 1U << 18; // larger blocks cannot hold CAN and mean corruption

std::uint32_t bswap32(std::uint32_t v) {
    return __builtin_bswap32(v);
}

// floor(a * b / c), exact through a 128-bit product (a < c keeps the result below b).
std::uint64_t mul_div_below(std::uint64_t a, std::uint64_t b, std::uint64_t c) {
    __extension__ typedef unsigned __int128 Wide;
    return static_cast<std::uint64_t>(static_cast<Wide>(a) * b / c);
}

} // namespace

bool looks_like_pcap(const std::uint8_t* p, std::size_t n) {
    if (n < 4) {
        return false;
    }
    const auto m = get_le<std::uint32_t>(p);
    return m == kPcapMagicUs || m == kPcapMagicNs || bswap32(m) == kPcapMagicUs ||
           bswap32(m) == kPcapMagicNs || m == kNgShb;
}

SocketCanDecode decode_socketcan_record(const std::uint8_t* p, std::size_t n, std::size_t wire_len,
                                        Frame& f) {
    if (n < 8) {
        return SocketCanDecode::TooShort;
    }
    const std::uint32_t raw = (static_cast<std::uint32_t>(p[0]) << 24) |
                              (static_cast<std::uint32_t>(p[1]) << 16) |
                              (static_cast<std::uint32_t>(p[2]) << 8) | p[3];
    f.flags = 0;
    if ((raw & kCanErr) != 0) {
        f.flags = Frame::kError;
        f.id = raw & Frame::kExtMask;
    } else if ((raw & kCanEff) != 0) {
        f.flags = Frame::kExtended;
        f.id = raw & Frame::kExtMask;
    } else {
        f.id = raw & Frame::kStdMask;
    }
    if ((raw & kCanRtr) != 0) {
        f.flags = static_cast<std::uint8_t>(f.flags | Frame::kRtr);
    }
    // The record length is the reliable FD marker: SocketCAN writes struct canfd_frame (72 bytes,
    // CANFD_MTU) for FD and struct can_frame (16 bytes, CAN_MTU) for classic frames. The byte
    // after the length is can_frame.__pad on classic frames and was left uninitialised by older
    // kernels (e.g. `7f 00 00`), so - as Wireshark does - the FDF bit is believed only when no
    // undefined flag bit is set and both reserved bytes are zero.
    // A bit outside kCanFdDefinedFlags means the byte is not an FD flags byte (old kernels left
    // it uninitialised).
    const bool flags_clean = (p[5] & ~kCanFdDefinedFlags) == 0 && p[6] == 0 && p[7] == 0;
    const bool fd = wire_len == kCanFdMtu || (flags_clean && (p[5] & kCanFdFdf) != 0);
    std::size_t len = p[4];
    if (fd) {
        f.flags = static_cast<std::uint8_t>(f.flags | Frame::kFd);
        if ((p[5] & kCanFdBrs) != 0) {
            f.flags = static_cast<std::uint8_t>(f.flags | Frame::kBrs);
        }
        len = std::min<std::size_t>(len, Frame::kMaxFdLen);
    } else if (len > Frame::kMaxClassicLen) {
        // A classic frame carries at most 8 bytes (ISO 11898-1; SocketCAN keeps a DLC of 9..15 in
        // len8_dlc with len = 8). Not taken for FD: the record cannot hold FD data.
        f.len = static_cast<std::uint8_t>(len);
        return SocketCanDecode::ClassicLenOver8;
    }
    if (f.rtr()) {
        f.len = static_cast<std::uint8_t>(len);
        return SocketCanDecode::Ok;
    }
    len = std::min(len, n - 8); // a short snaplen keeps only what was captured
    std::memcpy(f.data.data(), p + 8, len);
    f.len = static_cast<std::uint8_t>(len);
    return SocketCanDecode::Ok;
}

std::string socketcan_decode_error(SocketCanDecode result, std::string_view where, std::size_t n,
                                   const Frame& f) {
    if (result == SocketCanDecode::TooShort) {
        return fmt::format("{}: {} bytes is too short for a CAN frame", where, n);
    }
    return fmt::format("{}: CAN id 0x{:X} claims {} data bytes in a classic CAN record (at most 8, "
                       "and the record is not CAN FD), skipped",
                       where, f.id, f.len);
}

std::uint32_t PcapReader::u32(const std::uint8_t* p) const {
    const auto v = get_le<std::uint32_t>(p);
    return swapped_ ? bswap32(v) : v;
}
std::uint16_t PcapReader::u16(const std::uint8_t* p) const {
    const auto v = get_le<std::uint16_t>(p);
    return swapped_ ? static_cast<std::uint16_t>((v >> 8) | (v << 8)) : v;
}

ReadStatus PcapReader::truncated(std::string_view what) {
    error_ = fmt::format("pcap truncated after {} records (byte offset {}): {}", records_, offset_,
                         what);
    return ReadStatus::Fatal;
}

ReadStatus PcapReader::read_header() {
    started_ = true;
    if (input_.ensure(4) < 4) {
        return truncated("no file header");
    }
    const auto magic = get_le<std::uint32_t>(input_.data());
    if (magic == kNgShb) {
        ng_ = true;
        return ReadStatus::Frame; // the SHB is read as a block
    }
    if (input_.ensure(24) < 24) {
        return truncated("incomplete file header");
    }
    if (magic == kPcapMagicUs || magic == kPcapMagicNs) {
        swapped_ = false;
    } else if (bswap32(magic) == kPcapMagicUs || bswap32(magic) == kPcapMagicNs) {
        swapped_ = true;
    } else {
        error_ = "not a pcap file (unknown magic number)";
        return ReadStatus::Fatal;
    }
    nanos_ = (swapped_ ? bswap32(magic) : magic) == kPcapMagicNs;
    link_type_ = u32(input_.data() + 20) & 0xFFFF;
    if (link_type_ != kLinkTypeSocketCan) {
        error_ =
            fmt::format("pcap link type {} is not SocketCAN ({})", link_type_, kLinkTypeSocketCan);
        return ReadStatus::Fatal;
    }
    input_.consume(24);
    offset_ = 24;
    return ReadStatus::Frame;
}

ReadStatus PcapReader::next(TraceRecord& record) {
    if (!started_) {
        if (auto s = read_header(); s != ReadStatus::Frame) {
            return s;
        }
    }
    return ng_ ? next_ng(record) : next_classic(record);
}

ReadStatus PcapReader::next_classic(TraceRecord& record) {
    const auto have = input_.ensure(16);
    if (have == 0) {
        return ReadStatus::End;
    }
    if (have < 16) {
        return truncated("incomplete record header");
    }
    const auto* h = input_.data();
    const std::uint32_t sec = u32(h);
    const std::uint32_t frac = u32(h + 4);
    const std::uint32_t incl = u32(h + 8);
    if (incl > kMaxBlock) {
        error_ =
            fmt::format("pcap record {} claims {} bytes: the file is corrupt", records_ + 1, incl);
        return ReadStatus::Fatal;
    }
    if (input_.ensure(16 + incl) < 16 + incl) {
        return truncated("incomplete record");
    }
    const auto* body = input_.data() + 16;
    record.ts_ns = static_cast<std::int64_t>(sec) * 1'000'000'000LL +
                   static_cast<std::int64_t>(frac) * (nanos_ ? 1 : 1000);
    record.has_ts = true;
    record.iface = "pcap";
    const std::uint32_t orig = u32(h + 12);
    const auto result = decode_socketcan_record(body, incl, orig, record.frame);
    input_.consume(16 + incl);
    offset_ += 16 + incl;
    ++records_;
    if (result != SocketCanDecode::Ok) {
        error_ = socketcan_decode_error(result, fmt::format("pcap record {}", records_), incl,
                                        record.frame);
        return ReadStatus::Malformed;
    }
    return ReadStatus::Frame;
}

// An IDB: link type (2 bytes), reserved (2), snap length (4), then options of code (2), length
// (2) and a value padded to 4 bytes (pcapng, draft-ietf-opsawg-pcapng §4.2).
PcapReader::Interface PcapReader::read_interface(const std::uint8_t* body,
                                                 std::uint32_t body_len) const {
    Interface itf;
    itf.link_type = u16(body);
    std::size_t o = 8;
    while (o + 4 <= body_len) {
        const std::uint16_t code = u16(body + o);
        const std::uint16_t olen = u16(body + o + 2);
        if (code == 0 || o + 4 + olen > body_len) {
            break;
        }
        const auto* v = body + o + 4;
        if (code == 9 && olen >= 1) {
            // if_tsresol: 10^-n s, or 2^-n s with the top bit set. Units finer than 10^-19 or
            // 2^-63 s do not fit a 64-bit count of units per second.
            const unsigned exp = v[0] & 0x7FU;
            const bool binary = (v[0] & 0x80U) != 0;
            if (binary ? exp > 63 : exp > 19) {
                itf.bad_resolution = fmt::format(
                    "if_tsresol of {}^-{} s is too fine: a second holds more than 2^64 such units",
                    binary ? 2 : 10, exp);
            } else {
                std::uint64_t per = 1;
                for (unsigned i = 0; i < exp; ++i) {
                    per *= binary ? 2U : 10U;
                }
                itf.ts_per_second = per;
                itf.bad_resolution.clear();
            }
        } else if (code == 14 && olen == 8) {
            // if_tsoffset: signed seconds added to every timestamp, one 64-bit value in the
            // section's byte order.
            const std::uint64_t lo = u32(swapped_ ? v + 4 : v);
            const std::uint64_t hi = u32(swapped_ ? v : v + 4);
            itf.ts_offset_s = static_cast<std::int64_t>((hi << 32) | lo);
        } else if (code == 2 && olen > 0) { // if_name
            itf.name.assign(reinterpret_cast<const char*>(v),
                            strnlen(reinterpret_cast<const char*>(v), olen));
        }
        o += 4 + ((olen + 3U) & ~3U);
    }
    if (itf.name.empty()) {
        itf.name = fmt::format("if{}", interfaces_.size());
    }
    return itf;
}

bool PcapReader::packet_time(const Interface& itf, std::uint64_t ts, std::int64_t& ns) {
    if (!itf.bad_resolution.empty()) {
        error_ = fmt::format("pcapng packet {}: its interface's {}, skipped", records_,
                             itf.bad_resolution);
        return false;
    }
    const std::uint64_t per = itf.ts_per_second;
    const std::uint64_t whole = ts / per;
    const std::uint64_t frac_ns = mul_div_below(ts % per, 1'000'000'000U, per);
    const bool in_range = whole <= static_cast<std::uint64_t>(kMaxTraceTimeS) &&
                          itf.ts_offset_s >= -kMaxTraceTimeS && itf.ts_offset_s <= kMaxTraceTimeS;
    const std::int64_t sec = in_range ? static_cast<std::int64_t>(whole) + itf.ts_offset_s : -1;
    if (sec >= 0 && sec <= kMaxTraceTimeS &&
        add_trace_time(sec * 1'000'000'000LL, static_cast<std::int64_t>(frac_ns), ns)) {
        return true;
    }
    if (itf.ts_offset_s == 0) {
        error_ = fmt::format("pcapng packet {}: timestamp {} ({} per second) is past the year "
                             "2255, skipped",
                             records_, ts, per);
    } else {
        error_ = fmt::format("pcapng packet {}: timestamp {} ({} per second) with the "
                             "interface's offset of {} s is before 1970 or past the year 2255, "
                             "skipped",
                             records_, ts, per, itf.ts_offset_s);
    }
    return false;
}

ReadStatus PcapReader::next_ng(TraceRecord& record) {
    for (;;) {
        const auto have = input_.ensure(12);
        if (have == 0) {
            return ReadStatus::End;
        }
        if (have < 12) {
            return truncated("incomplete block header");
        }
        const auto* b = input_.data();
        const auto raw_type = get_le<std::uint32_t>(b);
        if (raw_type == kNgShb) {
            const auto bom = get_le<std::uint32_t>(b + 8);
            if (bom == kNgByteOrder) {
                swapped_ = false;
            } else if (bswap32(bom) == kNgByteOrder) {
                swapped_ = true;
            } else {
                error_ = "pcapng section header with a bad byte-order magic";
                return ReadStatus::Fatal;
            }
            interfaces_.clear();
        }
        const std::uint32_t type = u32(b);
        const std::uint32_t len = u32(b + 4);
        if (len < 12 || len > kMaxBlock || len % 4 != 0) {
            error_ = fmt::format("pcapng block at byte offset {} has bad length {}", offset_, len);
            return ReadStatus::Fatal;
        }
        if (input_.ensure(len) < len) {
            return truncated("incomplete block");
        }
        b = input_.data();
        const std::uint32_t body_len = len - 12;
        const auto* body = b + 8;
        ReadStatus status = ReadStatus::End; // End here means "no record from this block"
        if (type == kNgIdb && body_len >= 8) {
            auto itf = read_interface(body, body_len);
            if (interfaces_.size() < 256) {
                interfaces_.push_back(std::move(itf));
            }
        } else if ((type == kNgEpb && body_len >= 20) || (type == kNgSpb && body_len >= 4)) {
            const bool epb = type == kNgEpb;
            const std::uint32_t if_id = epb ? u32(body) : 0;
            const std::uint32_t cap = epb ? u32(body + 12) : std::min(u32(body), body_len - 4);
            const std::size_t data_off = epb ? 20 : 4;
            ++records_;
            if (if_id >= interfaces_.size() || cap > body_len - data_off) {
                error_ = fmt::format("pcapng packet {} refers to unknown interface {} or is "
                                     "longer than its block",
                                     records_, if_id);
                status = ReadStatus::Malformed;
            } else if (interfaces_[if_id].link_type != kLinkTypeSocketCan) {
                error_ = fmt::format("pcapng packet {}: link type {} is not SocketCAN, skipped",
                                     records_, interfaces_[if_id].link_type);
                status = ReadStatus::Malformed;
            } else {
                const auto& itf = interfaces_[if_id];
                record.iface = itf.name;
                bool ts_ok = true;
                if (epb) {
                    const std::uint64_t ts =
                        (static_cast<std::uint64_t>(u32(body + 4)) << 32) | u32(body + 8);
                    ts_ok = packet_time(itf, ts, record.ts_ns);
                    record.has_ts = true;
                } else {
                    record.has_ts = false;
                }
                const std::uint32_t wire = epb ? u32(body + 16) : u32(body);
                if (!ts_ok) {
                    status = ReadStatus::Malformed;
                } else if (const auto result =
                               decode_socketcan_record(body + data_off, cap, wire, record.frame);
                           result == SocketCanDecode::Ok) {
                    status = ReadStatus::Frame;
                } else {
                    error_ = socketcan_decode_error(
                        result, fmt::format("pcapng packet {}", records_), cap, record.frame);
                    status = ReadStatus::Malformed;
                }
            }
        }
        input_.consume(len);
        offset_ += len;
        if (status != ReadStatus::End) {
            return status;
        }
    }
}

} // namespace codrive::dump
