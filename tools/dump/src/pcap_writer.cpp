// SPDX-License-Identifier: Apache-2.0
// pcap and pcapng writer for SocketCAN frames (what `codrive-dump -w` writes).
#include <codrive/dump/pcap.hpp>

#include "pcap_format.hpp"

#include <codrive/core/endian.hpp>

#include <cerrno>
#include <cstring>

namespace codrive::dump {
namespace {

using namespace pcap_format;

constexpr std::uint16_t kOptEnd = 0;
constexpr std::uint16_t kOptIfName = 2;
constexpr std::uint16_t kOptIfTsresol = 9;
constexpr std::size_t kMaxInterfaces = 64; // more names than this share the last description

void append(std::vector<std::uint8_t>& b, const void* p, std::size_t n) {
    const auto* c = static_cast<const std::uint8_t*>(p);
    b.insert(b.end(), c, c + n);
}
void append_u32(std::vector<std::uint8_t>& b, std::uint32_t v) {
    std::uint8_t t[4];
    put_le<std::uint32_t>(t, v);
    append(b, t, 4);
}
void append_u16(std::vector<std::uint8_t>& b, std::uint16_t v) {
    std::uint8_t t[2];
    put_le<std::uint16_t>(t, v);
    append(b, t, 2);
}
void pad4(std::vector<std::uint8_t>& b) {
    while (b.size() % 4 != 0) {
        b.push_back(0);
    }
}
// Closes a pcapng block started at `start`: total length at both ends.
void close_block(std::vector<std::uint8_t>& b, std::size_t start) {
    pad4(b);
    const auto len = static_cast<std::uint32_t>(b.size() - start + 4);
    put_le<std::uint32_t>(b.data() + start + 4, len);
    append_u32(b, len);
}

} // namespace

std::size_t encode_socketcan_record(const Frame& f, std::uint8_t* c) {
    const std::size_t body = f.fd() ? kCanFdMtu : kCanMtu;
    std::memset(c, 0, body);
    std::uint32_t id = f.id;
    if (f.error()) {
        id |= kCanErr;
    } else if (f.extended()) {
        id |= kCanEff;
    }
    if (f.rtr()) {
        id |= kCanRtr;
    }
    c[0] = static_cast<std::uint8_t>(id >> 24);
    c[1] = static_cast<std::uint8_t>(id >> 16);
    c[2] = static_cast<std::uint8_t>(id >> 8);
    c[3] = static_cast<std::uint8_t>(id);
    c[4] = f.len;
    if (f.fd()) {
        c[5] =
            static_cast<std::uint8_t>(kCanFdFdf | ((f.flags & Frame::kBrs) != 0 ? kCanFdBrs : 0));
    }
    if (!f.rtr()) {
        std::memcpy(c + 8, f.data.data(), std::min<std::size_t>(f.len, body - 8));
    }
    return body;
}

Result<std::unique_ptr<PcapWriter>> PcapWriter::open(const std::string& path) {
    const bool ng = path.size() >= 7 && path.compare(path.size() - 7, 7, ".pcapng") == 0;
    return open(path, ng ? Format::Pcapng : Format::Pcap);
}

Result<std::unique_ptr<PcapWriter>> PcapWriter::open(const std::string& path, Format format) {
    std::unique_ptr<PcapWriter> w(new PcapWriter());
    w->format_ = format;
    if (path == "-") {
        w->file_ = stdout;
    } else {
        w->file_ = std::fopen(path.c_str(), "wb");
        if (w->file_ == nullptr) {
            return fail_errno(errno);
        }
        w->own_ = true;
    }
    auto& b = w->buf_;
    if (format == Format::Pcap) {
        std::uint8_t h[24] = {};
        put_le<std::uint32_t>(h, kPcapMagicUs);
        put_le<std::uint16_t>(h + 4, 2);
        put_le<std::uint16_t>(h + 6, 4);
        put_le<std::uint32_t>(h + 16, kCanFdMtu);
        put_le<std::uint32_t>(h + 20, kLinkTypeSocketCan);
        b.assign(h, h + sizeof h);
    } else {
        append_u32(b, kNgShb);
        append_u32(b, 0); // length, set by close_block
        append_u32(b, kNgByteOrder);
        append_u16(b, 1); // version 1.0
        append_u16(b, 0);
        append_u32(b, 0xFFFFFFFFU); // section length unknown (streamed)
        append_u32(b, 0xFFFFFFFFU);
        close_block(b, 0);
    }
    return w;
}

PcapWriter::~PcapWriter() {
    (void)flush();
    if (own_) {
        std::fclose(file_);
    }
}

std::uint32_t PcapWriter::interface_for(std::string_view name) {
    for (std::size_t i = 0; i < interfaces_.size(); ++i) {
        if (interfaces_[i] == name) {
            return static_cast<std::uint32_t>(i);
        }
    }
    if (interfaces_.size() == kMaxInterfaces) {
        return static_cast<std::uint32_t>(kMaxInterfaces - 1);
    }
    interfaces_.emplace_back(name);
    const auto start = buf_.size();
    append_u32(buf_, kNgIdb);
    append_u32(buf_, 0);
    append_u16(buf_, static_cast<std::uint16_t>(kLinkTypeSocketCan));
    append_u16(buf_, 0);
    append_u32(buf_, kCanFdMtu); // snaplen
    const auto shown = name.substr(0, 64);
    if (!shown.empty()) {
        append_u16(buf_, kOptIfName);
        append_u16(buf_, static_cast<std::uint16_t>(shown.size()));
        append(buf_, shown.data(), shown.size());
        pad4(buf_);
    }
    append_u16(buf_, kOptIfTsresol);
    append_u16(buf_, 1);
    buf_.push_back(9); // 10^-9 s: nanoseconds, as every reader keeps them
    pad4(buf_);
    append_u16(buf_, kOptEnd);
    append_u16(buf_, 0);
    close_block(buf_, start);
    return static_cast<std::uint32_t>(interfaces_.size() - 1);
}

void PcapWriter::write(const TraceRecord& r) {
    std::uint8_t rec[kCanFdMtu];
    const std::size_t body = encode_socketcan_record(r.frame, rec);
    const std::int64_t ts = r.ts_ns < 0 ? 0 : r.ts_ns;
    if (format_ == Format::Pcap) {
        std::uint8_t h[16];
        put_le<std::uint32_t>(h, static_cast<std::uint32_t>(ts / 1'000'000'000LL));
        put_le<std::uint32_t>(h + 4, static_cast<std::uint32_t>((ts % 1'000'000'000LL) / 1000));
        put_le<std::uint32_t>(h + 8, static_cast<std::uint32_t>(body));
        put_le<std::uint32_t>(h + 12, static_cast<std::uint32_t>(body));
        append(buf_, h, sizeof h);
        append(buf_, rec, body);
    } else {
        const auto if_id = interface_for(r.iface);
        const auto start = buf_.size();
        const auto t = static_cast<std::uint64_t>(ts);
        append_u32(buf_, kNgEpb);
        append_u32(buf_, 0);
        append_u32(buf_, if_id);
        append_u32(buf_, static_cast<std::uint32_t>(t >> 32));
        append_u32(buf_, static_cast<std::uint32_t>(t));
        append_u32(buf_, static_cast<std::uint32_t>(body));
        append_u32(buf_, static_cast<std::uint32_t>(body));
        append(buf_, rec, body);
        close_block(buf_, start);
    }
    if (buf_.size() >= (1U << 16)) {
        (void)flush();
    }
}

VoidResult PcapWriter::flush() {
    if (!buf_.empty() && file_ != nullptr) {
        if (std::fwrite(buf_.data(), 1, buf_.size(), file_) != buf_.size()) {
            buf_.clear();
            return fail_errno(errno);
        }
        buf_.clear();
        std::fflush(file_);
    }
    return {};
}

} // namespace codrive::dump
