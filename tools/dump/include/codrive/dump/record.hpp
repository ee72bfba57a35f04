// SPDX-License-Identifier: Apache-2.0
// One captured frame as every reader yields it: frame, wall-clock timestamp, interface name.
#pragma once

#include <codrive/core/frame.hpp>

#include <cstdint>
#include <string_view>

namespace codrive::dump {

/// The latest time a trace may carry: 9e18 ns after 1970 (the year 2255). Every reader gives
/// times in 0..kMaxTraceTimeNs and names a later one, so whoever uses a time may add intervals
/// (SDO timeouts, statistics windows) to it or subtract two without overflow.
inline constexpr std::int64_t kMaxTraceTimeNs = 9'000'000'000'000'000'000LL;
/// kMaxTraceTimeNs in whole seconds, for readers that parse seconds first.
inline constexpr std::int64_t kMaxTraceTimeS = kMaxTraceTimeNs / 1'000'000'000LL;

/// `a + b` into `sum` when both are times or intervals of 0..kMaxTraceTimeNs and the sum is one
/// too; false (and `sum` untouched) otherwise.
[[nodiscard]] inline bool add_trace_time(std::int64_t a, std::int64_t b, std::int64_t& sum) {
    if (a < 0 || b < 0 || a > kMaxTraceTimeNs || b > kMaxTraceTimeNs - a) {
        return false;
    }
    sum = a + b;
    return true;
}

/// A frame with where and when it was seen. `iface` views the reader's storage and is valid until
/// the reader's next call.
struct TraceRecord {
    Frame frame;
    std::int64_t ts_ns = 0; ///< wall-clock nanoseconds since the epoch (or since trace start)
    bool has_ts = false;    ///< false for screen-format lines without a timestamp
    std::string_view iface;
};

/// What a reader returns for one step.
enum class ReadStatus : std::uint8_t {
    Frame,     ///< `record` holds a frame
    Malformed, ///< one entry could not be parsed; `error()` names it; reading may continue
    End,       ///< end of input
    Fatal,     ///< input cannot be read further (truncated or corrupt container); `error()`
};

/// A source of records: a log file, a pcap/pcapng file, or live interfaces.
class ITraceSource {
public:
    virtual ~ITraceSource() = default;
    virtual ReadStatus next(TraceRecord& record) = 0;
    /// The message for the last Malformed or Fatal status: "line 12: bad data byte 'G1'".
    [[nodiscard]] virtual std::string_view error() const = 0;
    /// True if error() starts with a line number ("12: ..."), so the caller writes
    /// "file:12: ..." (text formats); false for container formats ("pcap record 3: ...").
    [[nodiscard]] virtual bool line_numbered() const { return false; }
};

} // namespace codrive::dump
