// SPDX-License-Identifier: Apache-2.0
// Parsers for candump text: the log format (`candump -l`/`-L`) and the default screen format.
#pragma once

#include <codrive/dump/input.hpp>
#include <codrive/dump/record.hpp>
#include <codrive/dump/text_reader.hpp>

#include <cstdint>
#include <memory>
#include <string>
#include <string_view>

namespace codrive::dump {

/// Parses one line of candump output into `out` (its `iface` views `line`):
///  - log format:    `(1700000000.123456) can0 181#11223344` (also `123#R`, `123##1AABB`,
///                   8-digit ids for 29-bit frames, trailing tokens such as `T`/`R` ignored);
///  - screen format: `  vcan0  123   [4]  11 22 33 44`, optionally after a `(sec.usec)` or
///                   `(YYYY-MM-DD HH:MM:SS.usec)` timestamp, `remote request` for RTR frames,
///                   `candump -x` extras after the interface (`RX B -`), CAN FD lengths as
///                   two digits (`[08]`).
/// Blank lines and lines starting with '#' are Skip. On Error, `error` names the problem
/// ("bad data byte 'G1'"). Hand-written: no allocation, no locale.
[[nodiscard]] LineStatus parse_log_line(std::string_view line, TraceRecord& out,
                                        std::string_view& error);

/// Reads candump text line by line from a BufferedInput. Screen-format timestamps printed with
/// `candump -t d` (deltas) or `-t z` (from zero) are recognised (stamps before 1973) and turned
/// into time since the first frame: deltas are summed (a stamp smaller than the one before it, or
/// a constant non-zero stamp, in the first 1000 lines means deltas).
class LogReader final : public TextTraceReader {
public:
    explicit LogReader(BufferedInput& input) : TextTraceReader(input) {}

protected:
    LineStatus parse_line(std::string_view line, TraceRecord& out, std::string& why) override;

private:
    enum class Relative : std::uint8_t { Unknown, FromZero, Delta };
    [[nodiscard]] bool looks_like_deltas() const;
    Relative relative_ = Relative::Unknown;
    std::int64_t delta_sum_ns_ = 0;
};

} // namespace codrive::dump
