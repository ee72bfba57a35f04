// SPDX-License-Identifier: Apache-2.0
// Vector BLF reader: file header, object headers, zlib containers streamed, CAN/CAN FD objects.
// Layout as Vector's binlog API (binlog_objects.h) defines it and python-can's blf.py reads it:
// all integers little-endian, objects start with the 16-byte base header
// {"LOBJ", u16 header size, u16 header version, u32 object size, u32 object type}.
#include <codrive/dump/blf_reader.hpp>

#include <codrive/dump/error_frame_build.hpp>
#include <codrive/dump/text_scan.hpp>

#include <fmt/format.h>
#include <linux/can/error.h>

#include <algorithm>
#include <cstring>
#include <limits>
#include <zlib.h>

namespace codrive::dump {
namespace {

constexpr std::size_t kFileHeaderMin = 72;       // signature .. stop SYSTEMTIME
constexpr std::size_t kFileHeaderMax = 1U << 16; // real files: 144
constexpr std::size_t kBaseHeader = 16;
constexpr std::size_t kContainerHeader = 16;   // u16 method, 6 reserved, u32 size, 4 reserved
constexpr std::uint32_t kMaxObject = 1U << 26; // 64 MiB: more is not a BLF object
constexpr std::size_t kMaxDecoded = 4096;      // a CAN object is about 100 bytes
constexpr std::size_t kInnerCapacity = 1U << 16;
constexpr std::uint16_t kMethodStored = 0;
constexpr std::uint16_t kMethodZlib = 2;
constexpr std::uint32_t kObjFlagTenMicros = 1; // BL_OBJ_FLAG_TIME_TEN_MICS
constexpr std::uint32_t kIdExtendedBit = 0x80000000U;
constexpr std::uint8_t kMsgFlagRemote = 0x80; // CAN_MESSAGE flags: bit 7 RTR, bit 0 Tx
constexpr std::uint8_t kFdFlagEdl = 0x01;     // CAN_FD_MESSAGE canFdFlags
constexpr std::uint8_t kFdFlagBrs = 0x02;
constexpr std::uint32_t kFd64Remote = 0x0010; // CAN_FD_MESSAGE_64 flags
constexpr std::uint32_t kFd64Edl = 0x1000;
constexpr std::uint32_t kFd64Brs = 0x2000;

std::uint16_t le16(const std::uint8_t* p) {
    return static_cast<std::uint16_t>(p[0] | (p[1] << 8));
}
std::uint32_t le32(const std::uint8_t* p) {
    return static_cast<std::uint32_t>(le16(p)) | (static_cast<std::uint32_t>(le16(p + 2)) << 16);
}
std::uint64_t le64(const std::uint8_t* p) {
    return static_cast<std::uint64_t>(le32(p)) | (static_cast<std::uint64_t>(le32(p + 4)) << 32);
}

std::string_view type_name(std::uint32_t type) {
    switch (static_cast<BlfObjectType>(type)) {
    case BlfObjectType::CanMessage:
        return "CAN_MESSAGE";
    case BlfObjectType::CanError:
        return "CAN_ERROR";
    case BlfObjectType::CanOverload:
        return "CAN_OVERLOAD";
    case BlfObjectType::CanDriverError:
        return "CAN_DRIVER_ERROR";
    case BlfObjectType::CanDriverErrorExt:
        return "CAN_DRIVER_ERROR_EXT";
    case BlfObjectType::CanFdError64:
        return "CAN_FD_ERROR_64";
    case BlfObjectType::LogContainer:
        return "LOG_CONTAINER";
    case BlfObjectType::CanErrorExt:
        return "CAN_ERROR_EXT";
    case BlfObjectType::CanMessage2:
        return "CAN_MESSAGE2";
    case BlfObjectType::CanFdMessage:
        return "CAN_FD_MESSAGE";
    case BlfObjectType::CanFdMessage64:
        return "CAN_FD_MESSAGE_64";
    }
    return "object";
}

bool decoded_type(std::uint32_t type) {
    return type != static_cast<std::uint32_t>(BlfObjectType::LogContainer) &&
           type_name(type) != "object";
}

// How many of the `n` bytes at `p` are zero before the first that is not (zero padding).
std::size_t leading_zeros(const std::uint8_t* p, std::size_t n) {
    return static_cast<std::size_t>(std::find_if(p, p + n, [](std::uint8_t b) { return b != 0; }) -
                                    p);
}

void add_flags(Frame& f, unsigned flags) {
    f.flags = static_cast<std::uint8_t>(f.flags | flags);
}

// Sets id and the 29-bit flag from a BLF id (bit 31: extended); false if an 11-bit id is > 7FF.
bool set_blf_id(std::uint32_t raw, Frame& f) {
    if ((raw & kIdExtendedBit) != 0) {
        f.flags = static_cast<std::uint8_t>(f.flags | Frame::kExtended);
        f.id = raw & Frame::kExtMask;
        return (raw & ~(kIdExtendedBit | Frame::kExtMask)) == 0;
    }
    f.id = raw;
    return raw <= Frame::kStdMask;
}

} // namespace

struct BlfReader::Inflater {
    z_stream s{};
    bool ready = false;
    Inflater() { ready = inflateInit(&s) == Z_OK; }
    ~Inflater() {
        if (ready) {
            inflateEnd(&s);
        }
    }
    Inflater(const Inflater&) = delete;
    Inflater& operator=(const Inflater&) = delete;
};

bool looks_like_blf(const std::uint8_t* p, std::size_t n) {
    // The signature and a plausible header size, so a text line "LOGGING ..." stays text.
    return n >= 8 && std::memcmp(p, "LOGG", 4) == 0 && le32(p + 4) >= kFileHeaderMin &&
           le32(p + 4) <= kFileHeaderMax;
}

BlfReader::BlfReader(BufferedInput& input)
    : input_(input), z_(std::make_unique<Inflater>()), inner_(kInnerCapacity) {}

BlfReader::~BlfReader() = default;

ReadStatus BlfReader::fatal(std::string message) {
    error_ = std::move(message);
    return ReadStatus::Fatal;
}

std::string BlfReader::where() const {
    return fmt::format(
        "BLF object {} at byte {} of the object stream (reading the container at file offset "
        "{})",
        objects_, inner_offset_, container_at_);
}

bool BlfReader::skip_input(std::size_t n) {
    while (n > 0) {
        const auto got = std::min(input_.ensure(std::min(n, input_.capacity())), n);
        if (got == 0) {
            return false;
        }
        input_.consume(got);
        offset_ += got;
        n -= got;
    }
    return true;
}

ReadStatus BlfReader::read_file_header() {
    started_ = true;
    if (!z_->ready) {
        return fatal("BLF: zlib could not be initialised");
    }
    const auto got = input_.ensure(kFileHeaderMin);
    if (got < 4 || std::memcmp(input_.data(), "LOGG", 4) != 0) {
        return fatal("not a BLF file (no 'LOGG' signature at byte offset 0)");
    }
    if (got < kFileHeaderMin) {
        return fatal(fmt::format("BLF file header truncated: {} of {} bytes", got, kFileHeaderMin));
    }
    const auto* h = input_.data();
    const std::uint32_t header_size = le32(h + 4);
    if (header_size < kFileHeaderMin || header_size > kFileHeaderMax) {
        return fatal(fmt::format("BLF file header size {} at byte offset 4 is absurd (expected "
                                 "{} to {}, normally 144)",
                                 header_size, kFileHeaderMin, kFileHeaderMax));
    }
    // Measurement start: SYSTEMTIME {year, month, day of week, day, hour, minute, second, ms}.
    const auto year = le16(h + 40);
    const auto month = le16(h + 42);
    const auto day = le16(h + 46);
    const auto hour = le16(h + 48);
    const auto minute = le16(h + 50);
    const auto second = le16(h + 52);
    const auto ms = le16(h + 54);
    std::int64_t days = 0;
    if (hour < 24 && minute < 60 && second < 61 && ms < 1000 &&
        scan::days_since_epoch(year, month, day, days)) {
        start_ns_ =
            (((days * 24 + hour) * 60 + minute) * 60 + second) * 1'000'000'000LL + ms * 1'000'000LL;
    } // else: no usable start, timestamps count from the start of the measurement
    if (!skip_input(header_size)) {
        return fatal(
            fmt::format("BLF file header truncated: the file ends before byte {}", header_size));
    }
    return ReadStatus::Frame;
}

// Starts the next top-level object as the source of object bytes.
BlfReader::Fill BlfReader::next_source() {
    // Objects are followed by up to 3 (object size % 4) zero padding bytes; a file may also end
    // in zeros. A zero byte never starts an object, so every one is skipped.
    for (;;) {
        const auto n = input_.ensure(1);
        if (n == 0) {
            return Fill::End;
        }
        const auto zeros = leading_zeros(input_.data(), n);
        input_.consume(zeros);
        offset_ += zeros;
        if (zeros < n) {
            break;
        }
    }
    const auto got = input_.ensure(kBaseHeader);
    const auto* h = input_.data();
    if (std::memcmp(h, "LOBJ", std::min<std::size_t>(got, 4)) != 0) {
        error_ = fmt::format("BLF: no object signature 'LOBJ' at file offset {}", offset_);
        return Fill::Fatal;
    }
    if (got < kBaseHeader) {
        error_ = fmt::format("BLF truncated: object header at file offset {} has {} of {} bytes",
                             offset_, got, kBaseHeader);
        return Fill::Fatal;
    }
    const std::uint32_t size = le32(h + 8);
    const std::uint32_t type = le32(h + 12);
    if (size < kBaseHeader || size > kMaxObject) {
        error_ = fmt::format("BLF object at file offset {} claims {} bytes (expected 16 to {}): "
                             "the file is corrupt",
                             offset_, size, kMaxObject);
        return Fill::Fatal;
    }
    container_at_ = offset_;
    produced_ = 0;
    stream_end_ = false;
    if (type != static_cast<std::uint32_t>(BlfObjectType::LogContainer)) {
        // An object outside any container (files of old loggers): its bytes are the stream.
        source_ = Source::Stored;
        source_left_ = size;
        container_size_ = size;
        return Fill::Ok;
    }
    if (input_.ensure(kBaseHeader + kContainerHeader) < kBaseHeader + kContainerHeader ||
        size < kBaseHeader + kContainerHeader) {
        error_ =
            fmt::format("BLF truncated: container header at file offset {} incomplete", offset_);
        return Fill::Fatal;
    }
    const std::uint16_t method = le16(h + kBaseHeader);
    container_size_ = le32(h + kBaseHeader + 8);
    if (method != kMethodStored && method != kMethodZlib) {
        error_ = fmt::format("BLF container at file offset {}: compression method {} is not "
                             "supported (0 stored, 2 zlib)",
                             offset_, method);
        return Fill::Fatal;
    }
    if (container_size_ > kMaxObject) {
        error_ = fmt::format("BLF container at file offset {} claims {} uncompressed bytes "
                             "(more than {}): the file is corrupt",
                             offset_, container_size_, kMaxObject);
        return Fill::Fatal;
    }
    input_.consume(kBaseHeader + kContainerHeader);
    offset_ += kBaseHeader + kContainerHeader;
    source_left_ = size - kBaseHeader - kContainerHeader;
    if (method == kMethodZlib) {
        source_ = Source::Zlib;
        inflateReset(&z_->s);
    } else {
        source_ = Source::Stored;
    }
    return Fill::Ok;
}

// Moves more container bytes into inner_ (at least one, or the end / an error).
BlfReader::Fill BlfReader::fill() {
    if (inner_pos_ > 0) {
        std::memmove(inner_.data(), inner_.data() + inner_pos_, inner_available());
        inner_end_ -= inner_pos_;
        inner_pos_ = 0;
    }
    for (;;) {
        if (inner_end_ == inner_.size()) {
            return Fill::Ok; // full; the caller reads before asking again
        }
        if (source_ == Source::None || (source_ == Source::Stored && source_left_ == 0) ||
            (source_ == Source::Zlib && stream_end_)) {
            if (source_ != Source::None) {
                if (source_ == Source::Zlib && produced_ != container_size_) {
                    error_ = fmt::format("BLF container at file offset {} gave {} bytes, its "
                                         "header says {}: the file is corrupt",
                                         container_at_, produced_, container_size_);
                    return Fill::Fatal;
                }
                if (!skip_input(static_cast<std::size_t>(source_left_))) {
                    error_ = fmt::format("BLF truncated in the container at file offset {}",
                                         container_at_);
                    return Fill::Fatal;
                }
                source_ = Source::None;
            }
            if (const auto s = next_source(); s != Fill::Ok) {
                return s;
            }
            continue;
        }
        const auto want = static_cast<std::size_t>(std::min<std::uint64_t>(source_left_, 1U << 16));
        const auto got = std::min(input_.ensure(want == 0 ? 1 : want), want);
        if (source_left_ > 0 && got == 0) {
            error_ = fmt::format("BLF truncated: the container at file offset {} misses its last "
                                 "{} bytes",
                                 container_at_, source_left_);
            return Fill::Fatal;
        }
        if (source_ == Source::Stored) {
            const auto n = std::min(got, inner_.size() - inner_end_);
            std::memcpy(inner_.data() + inner_end_, input_.data(), n);
            inner_end_ += n;
            input_.consume(n);
            offset_ += n;
            source_left_ -= n;
            produced_ += n;
            return Fill::Ok;
        }
        if (source_left_ == 0) {
            error_ = fmt::format("BLF container at file offset {}: the zlib stream is cut short",
                                 container_at_);
            return Fill::Fatal;
        }
        auto& s = z_->s;
        s.next_in = const_cast<Bytef*>(input_.data());
        s.avail_in = static_cast<uInt>(got);
        s.next_out = inner_.data() + inner_end_;
        s.avail_out = static_cast<uInt>(inner_.size() - inner_end_);
        const int rc = inflate(&s, Z_NO_FLUSH);
        const auto used = got - s.avail_in;
        const auto made = (inner_.size() - inner_end_) - s.avail_out;
        input_.consume(used);
        offset_ += used;
        source_left_ -= used;
        inner_end_ += made;
        produced_ += made;
        if (rc == Z_STREAM_END) {
            stream_end_ = true;
        } else if (rc != Z_OK || (used == 0 && made == 0)) {
            error_ = fmt::format("BLF container at file offset {}: bad zlib data ({})",
                                 container_at_, s.msg != nullptr ? s.msg : zError(rc));
            return Fill::Fatal;
        }
        if (made > 0) {
            return Fill::Ok;
        }
    }
}

BlfReader::Fill BlfReader::ensure_inner(std::size_t n) {
    while (inner_available() < n) {
        const auto before = inner_available();
        const auto s = fill();
        if (s != Fill::Ok) {
            return s;
        }
        if (inner_available() == before) {
            return Fill::End; // full buffer: cannot happen for n <= capacity
        }
    }
    return Fill::Ok;
}

ReadStatus BlfReader::next(TraceRecord& record) {
    if (!started_) {
        if (const auto s = read_file_header(); s != ReadStatus::Frame) {
            return s;
        }
    }
    for (;;) {
        while (skip_left_ > 0) {
            if (inner_available() == 0) {
                const auto s = fill();
                if (s == Fill::Fatal) {
                    return ReadStatus::Fatal;
                }
                if (s == Fill::End) {
                    return fatal(fmt::format("BLF truncated: the file ends inside {}", where()));
                }
            }
            const auto n =
                static_cast<std::size_t>(std::min<std::uint64_t>(skip_left_, inner_available()));
            inner_pos_ += n;
            inner_offset_ += n;
            skip_left_ -= n;
        }
        // Padding after the previous object: zero bytes up to the next "LOBJ". Vector's
        // converter fills the rest of a container with zeros (vector_blf's test_GlobalMarker.blf
        // from the converter: 27 after its last object), so there is no limit.
        for (;;) {
            const auto s = ensure_inner(1);
            if (s == Fill::Fatal) {
                return ReadStatus::Fatal;
            }
            if (s == Fill::End) {
                return ReadStatus::End;
            }
            const auto n = inner_available();
            const auto zeros = leading_zeros(inner_.data() + inner_pos_, n);
            inner_pos_ += zeros;
            inner_offset_ += zeros;
            if (zeros < n) {
                break;
            }
        }
        ++objects_;
        const auto s = ensure_inner(kBaseHeader);
        if (s == Fill::Fatal) {
            return ReadStatus::Fatal;
        }
        const auto* h = inner_.data() + inner_pos_;
        if (std::memcmp(h, "LOBJ", std::min<std::size_t>(4, inner_available())) != 0) {
            return fatal(fmt::format("{}: no object signature 'LOBJ'", where()));
        }
        if (s == Fill::End) {
            return fatal(
                fmt::format("BLF truncated: the file ends inside the header of {}", where()));
        }
        const std::uint16_t header_size = le16(h + 4);
        const std::uint32_t size = le32(h + 8);
        const std::uint32_t type = le32(h + 12);
        if (size < kBaseHeader || size > kMaxObject || header_size < kBaseHeader ||
            header_size > size) {
            return fatal(fmt::format("{}: object size {} with header size {} is absurd", where(),
                                     size, header_size));
        }
        if (!decoded_type(type) || size > kMaxDecoded) {
            if (decoded_type(type)) {
                error_ = fmt::format("{} ({}): {} bytes is too long for it, skipped", where(),
                                     type_name(type), size);
                skip_left_ = size;
                return ReadStatus::Malformed;
            }
            skip_left_ = size; // another bus, statistics, comments: not ours
            continue;
        }
        const auto e = ensure_inner(size);
        if (e == Fill::Fatal) {
            return ReadStatus::Fatal;
        }
        if (e == Fill::End) {
            return fatal(fmt::format("BLF truncated: the file ends inside {} ({}, {} bytes)",
                                     where(), type_name(type), size));
        }
        const auto status = decode(inner_.data() + inner_pos_, size, type, record);
        inner_pos_ += size;
        inner_offset_ += size;
        return status;
    }
}

ReadStatus BlfReader::decode(const std::uint8_t* obj, std::uint32_t size, std::uint32_t type,
                             TraceRecord& record) {
    const auto malformed = [&](std::string_view why) {
        error_ = fmt::format("{} ({}): {}", where(), type_name(type), why);
        return ReadStatus::Malformed;
    };
    const std::uint16_t header_size = le16(obj + 4);
    const std::uint16_t header_version = le16(obj + 6);
    // Header version 1: u32 flags, u16 client index, u16 object version, u64 timestamp (32
    // bytes); version 2: u32 flags, u8 timestamp status, u8, u16 object version, u64 timestamp,
    // u64 original timestamp (40 bytes). Both have flags at 16 and the timestamp at 24.
    if ((header_version != 1 && header_version != 2) ||
        header_size < (header_version == 1 ? 32 : 40)) {
        return malformed(fmt::format("object header version {} with {} bytes is unknown",
                                     header_version, header_size));
    }
    const std::uint32_t flags = le32(obj + 16);
    const std::uint64_t ts = le64(obj + 24);
    const std::uint64_t unit = flags == kObjFlagTenMicros ? 10'000 : 1;
    // Any time a trace may carry (to the year 2255) is taken: some writers leave the measurement
    // start empty and put times since 1970 here.
    std::int64_t ts_ns = 0;
    if (ts > static_cast<std::uint64_t>(kMaxTraceTimeNs) / unit ||
        !add_trace_time(start_ns_, static_cast<std::int64_t>(ts * unit), ts_ns)) {
        return malformed(fmt::format("timestamp {} ({}) is past the year 2255", ts,
                                     unit == 1 ? "ns" : "10 µs units"));
    }
    const auto* p = obj + header_size;
    const std::size_t n = size - header_size;
    Frame& f = record.frame;
    f = Frame{};
    std::uint32_t channel = 0;
    switch (static_cast<BlfObjectType>(type)) {
    case BlfObjectType::CanMessage:
    case BlfObjectType::CanMessage2: {
        // u16 channel, u8 flags, u8 dlc, u32 id, u8 data[8] (CAN_MESSAGE2 adds frame length,
        // bit count).
        if (n < 16) {
            return malformed(fmt::format("{} data bytes, at least 16 expected", n));
        }
        channel = le16(p);
        if (!set_blf_id(le32(p + 4), f)) {
            return malformed(fmt::format("identifier 0x{:X} out of range", le32(p + 4)));
        }
        f.len = std::min<std::uint8_t>(p[3], 8);
        if ((p[2] & kMsgFlagRemote) != 0) {
            add_flags(f, Frame::kRtr);
        } else {
            std::memcpy(f.data.data(), p + 8, f.len);
        }
        break;
    }
    case BlfObjectType::CanFdMessage: {
        // u16 channel, u8 flags, u8 dlc, u32 id, u32 frame length, u8 bit count, u8 FD flags,
        // u8 valid data bytes, 5 reserved, u8 data[64].
        if (n < 20) {
            return malformed(fmt::format("{} data bytes, at least 20 expected", n));
        }
        channel = le16(p);
        if (!set_blf_id(le32(p + 4), f)) {
            return malformed(fmt::format("identifier 0x{:X} out of range", le32(p + 4)));
        }
        const bool edl = (p[13] & kFdFlagEdl) != 0;
        const std::uint8_t dlc = p[3] & 0x0F;
        if (edl) {
            add_flags(f, Frame::kFd | ((p[13] & kFdFlagBrs) != 0 ? Frame::kBrs : 0));
            f.len = static_cast<std::uint8_t>(fd_dlc_to_len(dlc));
        } else {
            f.len = std::min<std::uint8_t>(dlc, 8);
            add_flags(f, (p[2] & kMsgFlagRemote) != 0 ? Frame::kRtr : 0);
        }
        if (!f.rtr()) {
            if (n < 20U + f.len || p[14] < f.len) {
                return malformed(fmt::format("DLC {} needs {} data bytes, the object has {}", dlc,
                                             f.len, std::min<std::size_t>(p[14], n - 20)));
            }
            std::memcpy(f.data.data(), p + 20, f.len);
        }
        break;
    }
    case BlfObjectType::CanFdMessage64: {
        // u8 channel, u8 dlc, u8 valid payload length, u8 tx count, u32 id, u32 frame length,
        // u32 flags, u32 btr arb, u32 btr data, u32 brs offset, u32 crc offset, u16 bit count,
        // u8 direction, u8 extended data offset, u32 crc, then the payload.
        if (n < 40) {
            return malformed(fmt::format("{} data bytes, at least 40 expected", n));
        }
        channel = p[0];
        if (!set_blf_id(le32(p + 4), f)) {
            return malformed(fmt::format("identifier 0x{:X} out of range", le32(p + 4)));
        }
        const std::uint32_t fd_flags = le32(p + 12);
        const std::uint8_t dlc = p[1] & 0x0F;
        if ((fd_flags & kFd64Edl) != 0) {
            add_flags(f, Frame::kFd | ((fd_flags & kFd64Brs) != 0 ? Frame::kBrs : 0));
            f.len = static_cast<std::uint8_t>(fd_dlc_to_len(dlc));
        } else {
            f.len = std::min<std::uint8_t>(dlc, 8);
            add_flags(f, (fd_flags & kFd64Remote) != 0 ? Frame::kRtr : 0);
        }
        if (!f.rtr()) {
            // The payload ends at the extended data (its offset counts from the object start)
            // or at the object's end. TSMaster writes 64-byte frames with 48 bytes stored and a
            // valid length of 64; CANoe shows the missing bytes as 00, and so does this reader.
            const std::size_t ext = p[35];
            const std::size_t end = ext >= header_size + 40U ? ext - header_size : n;
            const std::size_t stored = std::min<std::size_t>({end, n}) - 40;
            if (p[2] < f.len) { // the valid length contradicts the DLC
                return malformed(fmt::format("DLC {} needs {} data bytes, the object has {}", dlc,
                                             f.len, std::min<std::size_t>(p[2], stored)));
            }
            std::memcpy(f.data.data(), p + 40, std::min<std::size_t>(f.len, stored));
        }
        break;
    }
    case BlfObjectType::CanError:
        if (n < 2) {
            return malformed("no channel");
        }
        channel = le16(p);
        f = protocol_error_frame(0, false, 0);
        break;
    case BlfObjectType::CanErrorExt: {
        // u16 channel, u16 length, u32 flags (1: ecc is an SJA1000 ECC, 2: ecc is the CAN-Core
        // error register), u8 ecc, u8 position, u8 dlc, u8, u32 frame length (ns), u32 id,
        // u16 extended flags, u16, 8 data bytes.
        if (n < 2) {
            return malformed("no channel");
        }
        channel = le16(p);
        const std::uint32_t error_flags = n >= 9 ? le32(p + 4) : 0;
        if ((error_flags & 2U) != 0) {
            f = can_core_error_frame(p[8]);
        } else if ((error_flags & 1U) != 0) {
            f = sja1000_ecc_error_frame(p[8]);
        } else {
            f = protocol_error_frame(0, false, 0);
        }
        break;
    }
    case BlfObjectType::CanFdError64: // u8 channel, then the frame as CAN_FD_MESSAGE_64
        if (n < 1) {
            return malformed("no channel");
        }
        channel = p[0];
        f = protocol_error_frame(0, false, 0);
        break;
    case BlfObjectType::CanOverload: // u16 channel
        if (n < 2) {
            return malformed("no channel");
        }
        channel = le16(p);
        f = protocol_error_frame(CAN_ERR_PROT_OVERLOAD, false, 0);
        break;
    case BlfObjectType::CanDriverError:
    case BlfObjectType::CanDriverErrorExt: {
        // u16 channel, u8 transmit errors, u8 receive errors, u32 error code (EXT: more after):
        // the controller state the counters give, as for PEAK's error counter lines.
        if (n < 4) {
            return malformed(fmt::format("{} data bytes, at least 4 expected", n));
        }
        channel = le16(p);
        f = state_error_frame(state_from_counters(p[2], p[3]), p[2], p[3]);
        break;
    }
    case BlfObjectType::LogContainer:
        return malformed("a container inside a container");
    }
    record.ts_ns = ts_ns;
    record.has_ts = true;
    iface_ = fmt::format("can{}", channel);
    record.iface = iface_;
    return ReadStatus::Frame;
}

} // namespace codrive::dump
