// SPDX-License-Identifier: Apache-2.0
// Fixed-size histogram of timing errors (send time minus ideal time): min/mean/percentiles/max.
#pragma once

#include <codrive/core/time.hpp>

#include <cstdint>
#include <string>
#include <vector>

namespace codrive::sync {

/// Records signed durations into a log-linear histogram allocated once at construction (about
/// 30 KB); add() never allocates, so it can run on the cyclic path. Values below
/// 128 × resolution are kept exactly to the resolution, larger ones to 1/64 of their magnitude
/// (like HdrHistogram), so no range has to be chosen up front. min and max are exact.
class PeriodStats {
public:
    explicit PeriodStats(Duration resolution = microseconds(1));

    void add(Duration value);
    void reset();

    [[nodiscard]] std::uint64_t count() const { return count_; }
    [[nodiscard]] Duration min() const { return count_ != 0 ? min_ : Duration{0}; }
    [[nodiscard]] Duration max() const { return count_ != 0 ? max_ : Duration{0}; }
    [[nodiscard]] Duration mean() const;
    /// The value below which a fraction `p` (0..1) of the samples lie, to bucket resolution
    /// (clamped to the exact min/max). 0 when empty.
    [[nodiscard]] Duration percentile(double p) const;
    [[nodiscard]] Duration p50() const { return percentile(0.50); }
    [[nodiscard]] Duration p99() const { return percentile(0.99); }

    /// "n=10000 min 2 us mean 14.2 us p50 12 us p99 61 us max 240 us".
    [[nodiscard]] std::string summary() const;

private:
    [[nodiscard]] static std::size_t bucket_of(std::uint64_t units);
    [[nodiscard]] static std::uint64_t bucket_floor(std::size_t index);

    Duration resolution_;
    std::vector<std::uint32_t> positive_; ///< value >= 0, by magnitude
    std::vector<std::uint32_t> negative_; ///< value < 0, by magnitude
    std::uint64_t count_ = 0;
    Duration min_{0};
    Duration max_{0};
    long double sum_ns_ = 0;
};

/// Microseconds as a double, for messages.
inline double to_us(Duration d) {
    return std::chrono::duration<double, std::micro>(d).count();
}

} // namespace codrive::sync
