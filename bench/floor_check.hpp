// SPDX-License-Identifier: Apache-2.0
// Shared by the benchmarks: the spread of interleaved samples and the check that a floor is one.
#pragma once

#include <fmt/format.h>

#include <algorithm>
#include <string>
#include <vector>

namespace codrive::bench {

/// Median and extremes of a set of interleaved samples (one per round).
struct Spread {
    double median = 0;
    double min = 0;
    double max = 0;
    std::size_t n = 0;
};

inline Spread spread_of(std::vector<double> v) {
    Spread s;
    if (v.empty()) {
        return s;
    }
    std::sort(v.begin(), v.end());
    const std::size_t m = v.size() / 2;
    s.median = v.size() % 2 == 1 ? v[m] : (v[m - 1] + v[m]) / 2;
    s.min = v.front();
    s.max = v.back();
    s.n = v.size();
    return s;
}

/// The q-quantile (0..1, nearest rank) of `v`; 0 when empty.
inline double percentile(std::vector<double> v, double q) {
    if (v.empty()) {
        return 0;
    }
    std::sort(v.begin(), v.end());
    const auto i = static_cast<std::size_t>(q * static_cast<double>(v.size() - 1) + 0.5);
    return v[std::min(i, v.size() - 1)];
}

/// "1.23 (0.98–1.40 over 8 rounds)" with `digits` decimals.
inline std::string describe(const Spread& s, int digits = 2) {
    return fmt::format("{:.{}f} (min {:.{}f}, max {:.{}f}, {} rounds)", s.median, digits, s.min,
                       digits, s.max, digits, s.n);
}

/// No code path beats its floor by more than measurement noise: a floor is the best the system
/// calls can do, so a median ratio (codrive figure / floor figure, oriented so that higher is
/// better for codrive) above this means the floor is not doing the best it can.
inline constexpr double kFloorTolerance = 1.05;

/// Prints the sentence and returns false when `ratio` (codrive/floor, higher = better for
/// codrive) exceeds kFloorTolerance.
inline bool floor_holds(const std::string& what, double ratio) {
    if (ratio <= kFloorTolerance) {
        return true;
    }
    fmt::print(stderr,
               "floor check failed: {} is {:.2f} times its floor (more than {:.2f}): the floor "
               "is not the best the system can do, so this figure cannot be trusted\n",
               what, ratio, kFloorTolerance);
    return false;
}

} // namespace codrive::bench
