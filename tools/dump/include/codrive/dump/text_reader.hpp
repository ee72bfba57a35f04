// SPDX-License-Identifier: Apache-2.0
// The line loop every text trace reader shares: line numbers, over-long lines, error sentences.
#pragma once

#include <codrive/dump/input.hpp>
#include <codrive/dump/record.hpp>

#include <cstdint>
#include <string>
#include <string_view>

namespace codrive::dump {

/// The outcome of parsing one line.
enum class LineStatus : std::uint8_t { Frame, Skip, Error };

/// Base of the line-oriented readers (candump, PEAK .trc, Vector .asc, CSV): reads lines from a
/// BufferedInput and hands each to parse_line(). A line that cannot be parsed gives Malformed
/// with error() = "12: <cause>: '<the line>'" (the caller puts the file name and ':' in front,
/// so the user reads `trace.trc:12: bad data byte: '...'`); reading goes on with the next line.
/// A file whose first kUnreadableLinesToStop lines that are not comments all fail, before any
/// frame, is no trace of this format (another tool's log): reading stops there with Fatal and one
/// sentence saying so, instead of one error per line of the whole file.
class TextTraceReader : public ITraceSource {
public:
    explicit TextTraceReader(BufferedInput& input) : input_(input) {}
    ReadStatus next(TraceRecord& record) final;
    [[nodiscard]] std::string_view error() const final { return error_; }
    [[nodiscard]] bool line_numbered() const final { return true; }
    [[nodiscard]] std::uint64_t line_number() const { return line_no_; }

protected:
    /// Parses one line (without its line end) into `out`; on Error sets `why` to the cause.
    virtual LineStatus parse_line(std::string_view line, TraceRecord& out, std::string& why) = 0;
    BufferedInput& input_;

public:
    static constexpr std::uint64_t kUnreadableLinesToStop = 20;

private:
    std::uint64_t line_no_ = 0;
    std::uint64_t frames_ = 0;
    std::uint64_t failed_before_frames_ = 0;
    std::string error_;
};

} // namespace codrive::dump
