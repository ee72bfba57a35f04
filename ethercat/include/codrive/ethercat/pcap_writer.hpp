// SPDX-License-Identifier: Apache-2.0
// A minimal pcap file writer (LINKTYPE_ETHERNET) for captures tshark/Wireshark can dissect.
#pragma once

#include <codrive/core/error.hpp>

#include <cstdint>
#include <cstdio>
#include <span>
#include <string>

namespace codrive::ethercat {

/// Writes classic pcap (magic a1b2c3d4, microsecond timestamps, link type 1).
class PcapWriter {
public:
    PcapWriter() = default;
    ~PcapWriter();
    PcapWriter(const PcapWriter&) = delete;
    PcapWriter& operator=(const PcapWriter&) = delete;

    /// Creates the file and writes the global header. Errors: errno of fopen/fwrite.
    VoidResult open(const std::string& path);
    /// Appends one frame stamped with the current wall-clock time.
    void write(std::span<const std::uint8_t> frame);
    void close();
    [[nodiscard]] std::size_t frames() const { return frames_; }

private:
    std::FILE* file_ = nullptr;
    std::size_t frames_ = 0;
};

} // namespace codrive::ethercat
