// SPDX-License-Identifier: Apache-2.0
// Parsers for candump text: the log format (`candump -l`/`-L`) and the default screen format.
#pragma once

#include <codrive/dump/input.hpp>
#include <codrive/dump/record.hpp>

#include <cstdint>
#include <memory>
#include <string>
#include <string_view>

namespace codrive::dump {

/// The outcome of parsing one line.
enum class LineStatus : std::uint8_t { Frame, Skip, Error };

/// Parses one line of candump output into `out` (its `iface` views `line`):
///  - log format:    `(1700000000.123456) can0 181#11223344` (also `123#R`, `123##1AABB`,
///                   8-digit ids for 29-bit frames, trailing tokens such as `T`/`R` ignored);
///  - screen format: `  vcan0  123   [4]  11 22 33 44`, optionally after a `(sec.usec)` or
///                   `(YYYY-MM-DD HH:MM:SS.usec)` timestamp, `remote request` for RTR frames.
/// Blank lines and lines starting with '#' are Skip. On Error, `error` names the problem
/// ("bad data byte 'G1'"). Hand-written: no allocation, no locale.
[[nodiscard]] LineStatus parse_log_line(std::string_view line, TraceRecord& out,
                                        std::string_view& error);

/// Reads candump text line by line from a BufferedInput.
class LogReader final : public ITraceSource {
public:
    explicit LogReader(BufferedInput& input) : input_(input) {}
    ReadStatus next(TraceRecord& record) override;
    [[nodiscard]] std::string_view error() const override { return error_; }
    [[nodiscard]] std::uint64_t line_number() const { return line_no_; }

private:
    BufferedInput& input_;
    std::uint64_t line_no_ = 0;
    std::string error_;
};

} // namespace codrive::dump
