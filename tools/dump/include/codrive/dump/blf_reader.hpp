// SPDX-License-Identifier: Apache-2.0
// Vector BLF (binary logging format) files: CAN and CAN FD objects in zlib-compressed containers.
#pragma once

#include <codrive/dump/input.hpp>
#include <codrive/dump/record.hpp>

#include <cstdint>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

namespace codrive::dump {

/// True if the first bytes are a BLF file header: "LOGG" and a header size of 72 to 65536.
[[nodiscard]] bool looks_like_blf(const std::uint8_t* p, std::size_t n);

/// BLF object types codrive-dump reads (the values of Vector's binlog object type list).
enum class BlfObjectType : std::uint32_t {
    CanMessage = 1,         ///< CAN_MESSAGE: classic frame
    CanError = 2,           ///< CAN_ERROR: error frame without details
    CanOverload = 3,        ///< CAN_OVERLOAD: overload frame
    CanDriverError = 31,    ///< CAN_DRIVER_ERROR: the controller's error counters
    LogContainer = 10,      ///< LOG_CONTAINER: further objects, zlib-compressed or stored
    CanErrorExt = 73,       ///< CAN_ERROR_EXT: error frame with controller details
    CanDriverErrorExt = 74, ///< CAN_DRIVER_ERROR_EXT: error counters with controller state
    CanMessage2 = 86,       ///< CAN_MESSAGE2: classic frame with its bit length
    CanFdMessage = 100,     ///< CAN_FD_MESSAGE: CAN FD or classic frame (channel 16-bit)
    CanFdMessage64 = 101,   ///< CAN_FD_MESSAGE_64: CAN FD or classic frame (channel 8-bit)
    CanFdError64 = 104,     ///< CAN_FD_ERROR_64: error frame on a CAN FD channel (8-bit)
};

/// Reads a Vector BLF file as a stream: the file header ("LOGG": the measurement start, a
/// SYSTEMTIME taken as UTC), then objects ("LOBJ"), normally inside LOG_CONTAINER objects whose
/// data is zlib-compressed (method 2) or stored (method 0). The objects inside the containers
/// form one byte stream, so an object may start in one container and end in the next. Each
/// object's timestamp counts from the measurement start in 10 µs (object flag 1) or 1 ns units
/// (flag 2). Frames come from CAN_MESSAGE, CAN_MESSAGE2, CAN_FD_MESSAGE and CAN_FD_MESSAGE_64
/// (11/29-bit ids, remote frames, CAN FD with BRS, classic frames on FD channels); CAN_ERROR and
/// CAN_ERROR_EXT give an unspecified protocol error frame. The interface is `can<channel>` (BLF
/// channels count from 1, as in ASC files). Other objects (statistics, comments, other buses) are
/// skipped.
///
/// Memory is 64 KiB of decompressed object bytes and the BufferedInput buffer, whatever the file
/// or container size. An object that cannot be decoded gives Malformed ("BLF object 12 at byte
/// 345 of the object stream (reading the container at file offset 6789) (CAN_MESSAGE):
/// identifier 0x800 out of range") and reading goes on; a broken file (bad signature, truncated
/// file, bad zlib stream, absurd size) gives Fatal, one sentence with the byte offset.
class BlfReader final : public ITraceSource {
public:
    explicit BlfReader(BufferedInput& input);
    ~BlfReader() override;
    BlfReader(const BlfReader&) = delete;
    BlfReader& operator=(const BlfReader&) = delete;
    ReadStatus next(TraceRecord& record) override;
    [[nodiscard]] std::string_view error() const override { return error_; }

private:
    struct Inflater; // the zlib stream, kept out of this header
    enum class Source : std::uint8_t { None, Stored, Zlib };
    enum class Fill : std::uint8_t { Ok, End, Fatal };

    ReadStatus read_file_header();
    Fill next_source();
    Fill fill();
    Fill ensure_inner(std::size_t n);
    bool skip_input(std::size_t n);
    ReadStatus fatal(std::string message);
    ReadStatus decode(const std::uint8_t* obj, std::uint32_t size, std::uint32_t type,
                      TraceRecord& record);
    [[nodiscard]] std::string where() const;
    [[nodiscard]] std::size_t inner_available() const { return inner_end_ - inner_pos_; }

    BufferedInput& input_;
    std::unique_ptr<Inflater> z_;
    bool started_ = false;
    std::int64_t start_ns_ = 0;
    std::uint64_t offset_ = 0; ///< file offset of input_.data()

    Source source_ = Source::None;
    std::uint64_t source_left_ = 0;    ///< bytes of the current container still in the file
    std::uint64_t container_at_ = 0;   ///< file offset of the current container
    std::uint32_t container_size_ = 0; ///< uncompressed size its header gives
    std::uint64_t produced_ = 0;       ///< bytes the current container has given so far
    bool stream_end_ = false;

    std::vector<std::uint8_t> inner_; ///< object bytes taken from the containers, not yet read
    std::size_t inner_pos_ = 0;
    std::size_t inner_end_ = 0;
    std::uint64_t inner_offset_ = 0; ///< position of inner_pos_ in the container data stream
    std::uint64_t skip_left_ = 0;    ///< bytes of a skipped object still to drop
    std::uint64_t objects_ = 0;
    std::string iface_;
    std::string error_;
};

} // namespace codrive::dump
