// SPDX-License-Identifier: Apache-2.0
// pcap and pcapng files with link type SocketCAN (227): reader and writer.
#pragma once

#include <codrive/core/error.hpp>
#include <codrive/dump/input.hpp>
#include <codrive/dump/record.hpp>

#include <cstdint>
#include <cstdio>
#include <string>
#include <string_view>
#include <vector>

namespace codrive::dump {

inline constexpr std::uint32_t kLinkTypeSocketCan = 227;

/// True if the first bytes are a pcap or pcapng magic number.
[[nodiscard]] bool looks_like_pcap(const std::uint8_t* p, std::size_t n);

/// Outcome of decode_socketcan_record().
enum class SocketCanDecode : std::uint8_t {
    Ok,              ///< `f` holds the frame
    TooShort,        ///< fewer than 8 bytes captured
    ClassicLenOver8, ///< a classic (non-FD) record claims more than 8 data bytes; `f.len` holds it
};

/// Decodes a SocketCAN pcap record body (the CAN id is big-endian with the EFF/RTR/ERR flags in
/// the top bits, as Linux's SLL-less capture writes it). `n` is the captured length, `wire_len`
/// the record's original length: 72 (CANFD_MTU) means CAN FD. Otherwise the frame is FD only if
/// the flags byte has CANFD_FDF, no undefined bit, and both reserved bytes are zero (older kernels
/// left junk there on classic frames).
[[nodiscard]] SocketCanDecode decode_socketcan_record(const std::uint8_t* p, std::size_t n,
                                                      std::size_t wire_len, Frame& f);

/// The sentence for a failed decode_socketcan_record(); `where` names the record.
[[nodiscard]] std::string socketcan_decode_error(SocketCanDecode result, std::string_view where,
                                                 std::size_t n, const Frame& f);

/// Reads classic pcap (either byte order, micro- or nanosecond) and pcapng (SHB/IDB/EPB/SPB, any
/// if_tsresol). Records of other link types are skipped with a Malformed status; a file that
/// ends in the middle of a record gives Fatal ("truncated").
class PcapReader final : public ITraceSource {
public:
    explicit PcapReader(BufferedInput& input) : input_(input) {}
    ReadStatus next(TraceRecord& record) override;
    [[nodiscard]] std::string_view error() const override { return error_; }

private:
    struct Interface {
        std::uint16_t link_type = 0;
        std::uint64_t ts_per_second = 1'000'000; ///< if_tsresol (default: microseconds)
        std::int64_t ts_offset_s = 0;            ///< if_tsoffset, added to every timestamp
        std::string bad_resolution; ///< an if_tsresol no timestamp can be read with, named
        std::string name;
    };
    /// The interface an IDB body describes (link type, if_name, if_tsresol, if_tsoffset).
    [[nodiscard]] Interface read_interface(const std::uint8_t* body, std::uint32_t body_len) const;
    /// An EPB timestamp of `itf` into `ns`; false with error_ set when it cannot be a trace time.
    bool packet_time(const Interface& itf, std::uint64_t ts, std::int64_t& ns);
    ReadStatus read_header();
    ReadStatus next_classic(TraceRecord& record);
    ReadStatus next_ng(TraceRecord& record);
    ReadStatus truncated(std::string_view what);
    [[nodiscard]] std::uint32_t u32(const std::uint8_t* p) const;
    [[nodiscard]] std::uint16_t u16(const std::uint8_t* p) const;

    BufferedInput& input_;
    bool started_ = false;
    bool ng_ = false;
    bool swapped_ = false;
    bool nanos_ = false;
    std::uint32_t link_type_ = 0;
    std::uint64_t records_ = 0;
    std::uint64_t offset_ = 0;
    std::vector<Interface> interfaces_;
    std::string error_;
};

/// Writes the SocketCAN record body of `f` (the layout decode_socketcan_record() reads: 16 bytes
/// for a classic frame, 72 for CAN FD) into `out`, which holds at least 72 bytes. Returns the size.
std::size_t encode_socketcan_record(const Frame& f, std::uint8_t* out);

/// Writes what was read to a file Wireshark and tshark open: classic pcap (microsecond
/// timestamps) or pcapng (nanosecond timestamps, `if_tsresol` 9, one interface description per
/// interface name seen, so the names survive the conversion). Link type SocketCAN (227).
class PcapWriter {
public:
    enum class Format : std::uint8_t { Pcap, Pcapng };
    /// Opens `path` ("-" is stdout) and writes the file header; a path ending in ".pcapng" gets
    /// pcapng, any other classic pcap. Errors: the open/write errno.
    static Result<std::unique_ptr<PcapWriter>> open(const std::string& path);
    static Result<std::unique_ptr<PcapWriter>> open(const std::string& path, Format format);
    ~PcapWriter();
    PcapWriter(const PcapWriter&) = delete;
    PcapWriter& operator=(const PcapWriter&) = delete;
    /// Buffers one record.
    void write(const TraceRecord& record);
    /// Writes buffered records. Errors: the write errno.
    VoidResult flush();

private:
    PcapWriter() = default;
    std::uint32_t interface_for(std::string_view name);
    std::FILE* file_ = nullptr;
    bool own_ = false;
    Format format_ = Format::Pcap;
    std::vector<std::string> interfaces_;
    std::vector<std::uint8_t> buf_;
};

} // namespace codrive::dump
