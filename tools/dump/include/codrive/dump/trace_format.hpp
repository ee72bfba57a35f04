// SPDX-License-Identifier: Apache-2.0
// Trace file formats: recognised from their content, each read by its own ITraceSource.
#pragma once

#include <codrive/dump/input.hpp>
#include <codrive/dump/record.hpp>

#include <cstdint>
#include <memory>
#include <string_view>

namespace codrive::dump {

enum class TraceFormat : std::uint8_t {
    Candump, ///< candump -l/-L log or candump screen output (the fallback)
    Pcap,    ///< classic pcap or pcapng, link type SocketCAN
    PeakTrc, ///< PEAK PCAN-View/PCAN-Explorer .trc
    VectorAsc,
    Csv,
    VectorBlf, ///< Vector binary logging format (.blf)
};

/// "candump", "pcap", "PEAK trc", "Vector asc", "CSV", "Vector blf".
[[nodiscard]] std::string_view to_string(TraceFormat f);

/// Recognises the format from the first bytes of a file (never from its name): a pcap/pcapng
/// magic number; the BLF file header (`LOGG`); a first non-blank line starting with ';' (PEAK
/// header, e.g.
/// `;$FILEVERSION=2.1`); `date `, `base hex|dec`, `// version` or `Begin Triggerblock` (Vector
/// ASC header), or an ASC event line; a CSV header with id and data columns; else candump text.
[[nodiscard]] TraceFormat detect_trace_format(const std::uint8_t* p, std::size_t n);

/// The reader for `format` (whatever the content).
[[nodiscard]] std::unique_ptr<ITraceSource> make_trace_reader(TraceFormat format,
                                                              BufferedInput& input);

/// Detects the format of `input` (reading until the first line that tells, at most 64 KiB) and
/// returns its reader.
[[nodiscard]] std::unique_ptr<ITraceSource> open_trace_reader(BufferedInput& input,
                                                              TraceFormat* detected = nullptr);

} // namespace codrive::dump
