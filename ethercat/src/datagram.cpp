// SPDX-License-Identifier: Apache-2.0
// EtherCAT frame and datagram codec (ETG.1000.4 §5.3 frame structure, §5.4 datagrams).
#include <codrive/ethercat/datagram.hpp>
#include <codrive/ethercat/error.hpp>

#include <codrive/core/endian.hpp>

#include <algorithm>
#include <cstring>

namespace codrive::ethercat {
namespace {

constexpr std::uint16_t kLengthMask = 0x07FF;
constexpr std::uint16_t kCirculatingBit = 0x4000;
constexpr std::uint16_t kMoreBit = 0x8000;
constexpr std::uint16_t kEcatTypeDlpdu = 1; // EtherCAT header type 1: DLPDU (datagrams)
constexpr std::size_t kDatagramHeaderSize = 10;

struct RawDatagram {
    std::size_t header_offset;
    std::uint8_t cmd;
    std::uint16_t len;
    bool circulated;
};

// Validates the frame and hands each datagram's position to `visit` (a RawDatagram, in order);
// nothing else reads unchecked bytes. Returns the number of datagrams. Allocates nothing: the
// cyclic LRW path decodes through it every cycle.
template <typename Visit>
Result<std::size_t> scan_frame_each(std::span<const std::uint8_t> frame, Visit&& visit) {
    if (frame.size() < kEthernetHeaderSize + kEcatHeaderSize) {
        return fail(EcatErrc::InvalidFrame);
    }
    const std::uint16_t ethertype =
        static_cast<std::uint16_t>((frame[12] << 8) | frame[13]); // network byte order
    if (ethertype != kEthertype) {
        return fail(EcatErrc::InvalidFrame);
    }
    const auto ecat_header = get_le<std::uint16_t>(frame.data() + kEthernetHeaderSize);
    const std::size_t ecat_len = ecat_header & kLengthMask;
    if ((ecat_header >> 12) != kEcatTypeDlpdu) {
        return fail(EcatErrc::InvalidFrame);
    }
    const std::size_t begin = kEthernetHeaderSize + kEcatHeaderSize;
    if (begin + ecat_len > frame.size()) {
        return fail(EcatErrc::InvalidFrame);
    }
    const std::size_t end = begin + ecat_len;
    std::size_t count = 0;
    std::size_t pos = begin;
    while (true) {
        if (pos + kDatagramHeaderSize > end) {
            return fail(EcatErrc::InvalidFrame);
        }
        const std::uint8_t cmd = frame[pos];
        const auto len_field = get_le<std::uint16_t>(frame.data() + pos + 6);
        const auto len = static_cast<std::uint16_t>(len_field & kLengthMask);
        if (!is_valid_command(cmd) || pos + kDatagramHeaderSize + len + 2 > end) {
            return fail(EcatErrc::InvalidFrame);
        }
        visit(RawDatagram{pos, cmd, len, (len_field & kCirculatingBit) != 0});
        ++count;
        pos += kDatagramHeaderSize + len + 2;
        if ((len_field & kMoreBit) == 0) {
            break;
        }
    }
    return count;
}

// The datagram positions as a list (decoding paths outside the cycle).
Result<std::vector<RawDatagram>> scan_frame(std::span<const std::uint8_t> frame) {
    std::vector<RawDatagram> out;
    auto n = scan_frame_each(frame, [&out](const RawDatagram& r) { out.push_back(r); });
    if (!n) {
        return fail(n.error());
    }
    return out;
}

} // namespace

std::string_view to_string(Command c) {
    switch (c) {
    case Command::Nop:
        return "NOP";
    case Command::Aprd:
        return "APRD";
    case Command::Apwr:
        return "APWR";
    case Command::Aprw:
        return "APRW";
    case Command::Fprd:
        return "FPRD";
    case Command::Fpwr:
        return "FPWR";
    case Command::Fprw:
        return "FPRW";
    case Command::Brd:
        return "BRD";
    case Command::Bwr:
        return "BWR";
    case Command::Brw:
        return "BRW";
    case Command::Lrd:
        return "LRD";
    case Command::Lwr:
        return "LWR";
    case Command::Lrw:
        return "LRW";
    case Command::Armw:
        return "ARMW";
    case Command::Frmw:
        return "FRMW";
    }
    return "?";
}

bool is_valid_command(std::uint8_t raw) {
    return raw <= static_cast<std::uint8_t>(Command::Frmw);
}

Addressing addressing_of(Command c) {
    switch (c) {
    case Command::Aprd:
    case Command::Apwr:
    case Command::Aprw:
    case Command::Armw:
        return Addressing::AutoIncrement;
    case Command::Fprd:
    case Command::Fpwr:
    case Command::Fprw:
    case Command::Frmw:
        return Addressing::Configured;
    case Command::Brd:
    case Command::Bwr:
    case Command::Brw:
        return Addressing::Broadcast;
    case Command::Lrd:
    case Command::Lwr:
    case Command::Lrw:
        return Addressing::Logical;
    case Command::Nop:
        break;
    }
    return Addressing::None;
}

bool command_reads(Command c) {
    switch (c) {
    case Command::Aprd:
    case Command::Aprw:
    case Command::Fprd:
    case Command::Fprw:
    case Command::Brd:
    case Command::Brw:
    case Command::Lrd:
    case Command::Lrw:
    case Command::Armw:
    case Command::Frmw:
        return true;
    default:
        return false;
    }
}

bool command_writes(Command c) {
    switch (c) {
    case Command::Apwr:
    case Command::Aprw:
    case Command::Fpwr:
    case Command::Fprw:
    case Command::Bwr:
    case Command::Brw:
    case Command::Lwr:
    case Command::Lrw:
    case Command::Armw:
    case Command::Frmw:
        return true;
    default:
        return false;
    }
}

std::uint16_t wkc_increment(Command c, bool read_done, bool write_done) {
    switch (c) {
    case Command::Nop:
        return 0;
    case Command::Armw:
    case Command::Frmw:
        return (read_done || write_done) ? 1 : 0;
    case Command::Aprw:
    case Command::Fprw:
    case Command::Brw:
    case Command::Lrw:
        return static_cast<std::uint16_t>((read_done ? 1 : 0) + (write_done ? 2 : 0));
    default:
        break;
    }
    if (command_reads(c)) {
        return read_done ? 1 : 0;
    }
    return write_done ? 1 : 0;
}

std::uint16_t expected_wkc(Command c, std::uint16_t slaves) {
    return static_cast<std::uint16_t>(slaves *
                                      wkc_increment(c, command_reads(c), command_writes(c)));
}

Datagram Datagram::physical(Command c, std::uint16_t adp, std::uint16_t ado, std::size_t size) {
    Datagram d;
    d.command = c;
    d.address = static_cast<std::uint32_t>(adp) | (static_cast<std::uint32_t>(ado) << 16);
    d.data.assign(size, 0);
    return d;
}

Datagram Datagram::physical(Command c, std::uint16_t adp, std::uint16_t ado,
                            std::span<const std::uint8_t> payload) {
    Datagram d = physical(c, adp, ado, 0);
    d.data.assign(payload.begin(), payload.end());
    return d;
}

Datagram Datagram::logical(Command c, std::uint32_t logical_address, std::size_t size) {
    Datagram d;
    d.command = c;
    d.address = logical_address;
    d.data.assign(size, 0);
    return d;
}

std::size_t frame_size(std::span<const Datagram> datagrams) {
    std::size_t n = kEthernetHeaderSize + kEcatHeaderSize;
    for (const auto& d : datagrams) {
        n += d.wire_size();
    }
    return n;
}

Result<std::size_t> encode_frame(std::span<const Datagram> datagrams, std::span<std::uint8_t> out,
                                 const MacAddress& source) {
    if (datagrams.empty()) {
        return fail(CoreErrc::InvalidArgument);
    }
    const std::size_t size = frame_size(datagrams);
    if (size > kMaxFrameSize) {
        return fail(EcatErrc::FrameTooLarge);
    }
    const std::size_t padded = std::max(size, kMinFrameSize);
    if (out.size() < padded) {
        return fail(CoreErrc::InvalidArgument);
    }
    std::uint8_t* p = out.data();
    std::memcpy(p, kBroadcastMac.data(), 6);
    std::memcpy(p + 6, source.data(), 6);
    p[12] = static_cast<std::uint8_t>(kEthertype >> 8);
    p[13] = static_cast<std::uint8_t>(kEthertype & 0xFF);
    const auto ecat_len = static_cast<std::uint16_t>(size - kEthernetHeaderSize - kEcatHeaderSize);
    put_le<std::uint16_t>(p + kEthernetHeaderSize,
                          static_cast<std::uint16_t>(ecat_len | (kEcatTypeDlpdu << 12)));
    std::size_t pos = kEthernetHeaderSize + kEcatHeaderSize;
    for (std::size_t i = 0; i < datagrams.size(); ++i) {
        const Datagram& d = datagrams[i];
        p[pos] = static_cast<std::uint8_t>(d.command);
        p[pos + 1] = d.index;
        put_le<std::uint32_t>(p + pos + 2, d.address);
        auto len_field = static_cast<std::uint16_t>(d.data.size());
        if (d.circulated) {
            len_field = static_cast<std::uint16_t>(len_field | kCirculatingBit);
        }
        if (i + 1 < datagrams.size()) {
            len_field = static_cast<std::uint16_t>(len_field | kMoreBit);
        }
        put_le<std::uint16_t>(p + pos + 6, len_field);
        put_le<std::uint16_t>(p + pos + 8, d.irq);
        if (!d.data.empty()) {
            std::memcpy(p + pos + kDatagramHeaderSize, d.data.data(), d.data.size());
        }
        put_le<std::uint16_t>(p + pos + kDatagramHeaderSize + d.data.size(), d.wkc);
        pos += d.wire_size();
    }
    std::fill(p + pos, p + padded, std::uint8_t{0});
    return padded;
}

Result<std::vector<std::uint8_t>> encode_frame(std::span<const Datagram> datagrams,
                                               const MacAddress& source) {
    std::vector<std::uint8_t> out(std::max(frame_size(datagrams), kMinFrameSize));
    auto n = encode_frame(datagrams, out, source);
    if (!n) {
        return fail(n.error());
    }
    out.resize(*n);
    return out;
}

Result<std::vector<Datagram>> decode_frame(std::span<const std::uint8_t> frame) {
    auto raw = scan_frame(frame);
    if (!raw) {
        return fail(raw.error());
    }
    std::vector<Datagram> out;
    out.reserve(raw->size());
    for (const auto& r : *raw) {
        const std::uint8_t* h = frame.data() + r.header_offset;
        Datagram d;
        d.command = static_cast<Command>(r.cmd);
        d.index = h[1];
        d.address = get_le<std::uint32_t>(h + 2);
        d.irq = get_le<std::uint16_t>(h + 8);
        d.data.assign(h + kDatagramHeaderSize, h + kDatagramHeaderSize + r.len);
        d.wkc = get_le<std::uint16_t>(h + kDatagramHeaderSize + r.len);
        d.circulated = r.circulated;
        out.push_back(std::move(d));
    }
    return out;
}

VoidResult decode_frame_into(std::span<const std::uint8_t> frame, std::span<Datagram> datagrams) {
    // Two passes over the frame, no list: first check that it answers `datagrams` one for one
    // (nothing is written unless all match), then copy.
    std::size_t i = 0;
    bool matches = true;
    auto n = scan_frame_each(frame, [&](const RawDatagram& r) {
        const std::uint8_t* h = frame.data() + r.header_offset;
        if (i >= datagrams.size() || r.cmd != static_cast<std::uint8_t>(datagrams[i].command) ||
            h[1] != datagrams[i].index || r.len != datagrams[i].data.size()) {
            matches = false;
        }
        ++i;
    });
    if (!n) {
        return fail(n.error());
    }
    if (*n != datagrams.size() || !matches) {
        return fail(EcatErrc::ProtocolError);
    }
    i = 0;
    (void)scan_frame_each(frame, [&](const RawDatagram& r) {
        const std::uint8_t* h = frame.data() + r.header_offset;
        Datagram& d = datagrams[i++];
        if (!d.data.empty()) {
            std::memcpy(d.data.data(), h + kDatagramHeaderSize, d.data.size());
        }
        d.irq = get_le<std::uint16_t>(h + 8);
        d.address = get_le<std::uint32_t>(h + 2);
        d.wkc = get_le<std::uint16_t>(h + kDatagramHeaderSize + d.data.size());
    });
    return {};
}

std::uint32_t DatagramRef::address() const {
    return get_le<std::uint32_t>(header + 2);
}

void DatagramRef::set_address(std::uint32_t a) const {
    put_le<std::uint32_t>(header + 2, a);
}

void DatagramRef::set_adp(std::uint16_t adp) const {
    put_le<std::uint16_t>(header + 2, adp);
}

std::uint16_t DatagramRef::wkc() const {
    return get_le<std::uint16_t>(data.data() + data.size());
}

void DatagramRef::set_wkc(std::uint16_t wkc) const {
    put_le<std::uint16_t>(data.data() + data.size(), wkc);
}

VoidResult for_each_datagram(std::span<std::uint8_t> frame,
                             const std::function<void(DatagramRef&)>& visit) {
    auto raw = scan_frame(frame);
    if (!raw) {
        return fail(raw.error());
    }
    for (const auto& r : *raw) {
        DatagramRef ref;
        ref.command = static_cast<Command>(r.cmd);
        ref.header = frame.data() + r.header_offset;
        ref.index = ref.header[1];
        ref.data = std::span<std::uint8_t>(ref.header + kDatagramHeaderSize, r.len);
        visit(ref);
    }
    return {};
}

std::optional<std::uint8_t> frame_index(std::span<const std::uint8_t> frame) {
    if (frame.size() < kEthernetHeaderSize + kEcatHeaderSize + kDatagramHeaderSize ||
        frame[12] != 0x88 || frame[13] != 0xA4) {
        return std::nullopt;
    }
    return frame[kEthernetHeaderSize + kEcatHeaderSize + 1];
}

} // namespace codrive::ethercat
