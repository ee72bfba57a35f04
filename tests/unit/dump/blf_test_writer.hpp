// SPDX-License-Identifier: Apache-2.0
// Test-only Vector BLF writer: makes BLF files (zlib or stored containers) for the reader tests.
#pragma once

#include <codrive/core/frame.hpp>
#include <codrive/dump/blf_reader.hpp>

#include <cstdint>
#include <string>
#include <vector>

namespace codrive::dump::testing {

/// One frame to write, as the object type `type` (CAN_MESSAGE, CAN_MESSAGE2, CAN_FD_MESSAGE,
/// CAN_FD_MESSAGE_64; for an error frame CAN_ERROR_EXT, CAN_FD_ERROR_64, CAN_OVERLOAD, or
/// CAN_DRIVER_ERROR(_EXT) with the frame's error counters).
struct BlfEvent {
    Frame frame;
    std::int64_t ts_ns = 0;
    std::uint16_t channel = 1;
    BlfObjectType type = BlfObjectType::CanMessage;
};

struct BlfWriteOptions {
    bool compress = true;                       ///< zlib containers (method 2), else stored (0)
    std::size_t container_bytes = 128U * 1024U; ///< object-stream bytes per container
    std::uint16_t header_version = 1;           ///< object header version 1 (32 bytes) or 2 (40)
    bool ten_micros = false;                    ///< timestamps in 10 µs units, else 1 ns
};

/// One object: base header, header version 1 or 2 with `flags` and `timestamp`, then `payload`.
std::string blf_object(BlfObjectType type, const std::string& payload, std::uint64_t timestamp,
                       std::uint32_t flags = 2, std::uint16_t header_version = 1);
/// An object of a raw type number (for types the reader skips).
std::string blf_object(std::uint32_t type, const std::string& payload, std::uint64_t timestamp,
                       std::uint32_t flags = 2, std::uint16_t header_version = 1);

/// The object for one event; timestamps count from `start_ns`.
std::string blf_event_object(const BlfEvent& e, std::int64_t start_ns, const BlfWriteOptions& o);

/// A whole file: header with the measurement start (`start_ns`, kept to the millisecond), then
/// `stream` (concatenated objects, each padded to 4 bytes) cut into containers.
std::string blf_file(std::int64_t start_ns, const std::string& stream, const BlfWriteOptions& o);

/// A whole file of events; the start is the first event's time cut to the millisecond.
std::string blf_file(const std::vector<BlfEvent>& events, const BlfWriteOptions& o = {});

} // namespace codrive::dump::testing
