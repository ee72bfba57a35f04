// SPDX-License-Identifier: Apache-2.0
// PEAK PCAN-View / PCAN-Explorer trace files (.trc), file versions 1.0 to 2.1.
#pragma once

#include <codrive/dump/text_reader.hpp>

#include <array>
#include <cstdint>
#include <string>

namespace codrive::dump {

/// Reads a PEAK `.trc` trace. The header's `;$FILEVERSION=` picks the column layout (1.0 when
/// missing; 2.1 files may name their columns in `;$COLUMNS=`), `;$STARTTIME=` (days since
/// 1899-12-30, as PCAN-View writes it; taken as UTC) plus each line's time offset in ms gives the
/// timestamp; without a start time the timestamps count from the start of the trace.
///
/// Message types: data frames (1.x `Rx`/`Tx`, 2.x `DT`, and CAN FD `FD`, `FB` bit-rate switch,
/// `FE` error-state indicator, `BI` both) are decoded; remote requests (`RTR` in 1.x data, `RR`
/// in 2.x) are marked; error frames (1.0 `ERROR`, 1.x `Error`, 2.x `ER`), hardware status lines
/// (1.x `Warng` with id FFFFFFFF, 2.x `ST`) and error-counter changes (2.x `EC`) become SocketCAN
/// error frames, so they are reported (and written by `-w`) like a live bus's error frames.
/// User events (`EV`) carry no CAN data and are skipped.
class TrcReader final : public TextTraceReader {
public:
    explicit TrcReader(BufferedInput& input);

protected:
    LineStatus parse_line(std::string_view line, TraceRecord& out, std::string& why) override;

private:
    LineStatus parse_header(std::string_view line, std::string& why);
    /// Adds STARTTIME to a line's time offset; false (with `why`) past the 64-bit range.
    bool add_start(std::int64_t& ts_ns, std::string& why) const;
    LineStatus parse_status(std::string_view type, std::uint32_t id, const std::uint8_t* bytes,
                            std::size_t n, Frame& f, std::string& why);
    void set_version(unsigned major, unsigned minor);

    unsigned version_ = 100; ///< major * 100 + minor
    std::string columns_;    ///< one letter per column: N O T B I d R L l D
    std::int64_t start_ns_ = 0;
    bool has_start_ = false;
    std::string iface_;
};

} // namespace codrive::dump
