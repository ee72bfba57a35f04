// SPDX-License-Identifier: Apache-2.0
// Output lines: candump-like frame text followed by the decode, in colour or as JSON.
#pragma once

#include <codrive/dump/decoder.hpp>
#include <codrive/dump/record.hpp>

#include <fmt/format.h>

#include <cstdint>

namespace codrive::dump {

/// Timestamp modes, as candump's `-t`: absolute, delta to the previous frame, zero-based; none.
enum class TimeMode : std::uint8_t { Absolute, Delta, Zero, None };

struct LineOptions {
    TimeMode time = TimeMode::Absolute;
    bool color = false;
    bool json = false;
};

/// Formats records and notes. Keeps the previous and first timestamps for delta/zero modes.
class LineFormatter {
public:
    explicit LineFormatter(LineOptions options) : options_(options) {}
    /// `(1700000000.123456)  can0  181   [4]  11 22 33 44               node 1 TPDO1 ...`
    void frame(fmt::memory_buffer& out, const TraceRecord& r, const Decoded& d);
    /// `(1700000001.123456)  ----                                       node 4 SDO … (timeout)`
    void note(fmt::memory_buffer& out, const Note& n);

private:
    void timestamp(fmt::memory_buffer& out, bool has_ts, std::int64_t ts, bool advance);
    LineOptions options_;
    bool have_first_ = false;
    std::int64_t first_ns_ = 0;
    std::int64_t prev_ns_ = 0;
};

/// Appends `s` as a JSON string literal (quotes, escapes).
void append_json_string(fmt::memory_buffer& out, std::string_view s);

} // namespace codrive::dump
