// SPDX-License-Identifier: Apache-2.0
// Fixed-size log-linear timing histogram.
#include <codrive/sync/period_stats.hpp>

#include <algorithm>
#include <bit>
#include <cmath>
#include <fmt/format.h>

namespace codrive::sync {

namespace {
// Magnitudes below kLinear units have their own bucket; above, each power of two is split into
// kSub buckets (relative precision 1/kSub).
constexpr std::uint64_t kLinear = 128;
constexpr std::uint64_t kSub = 64;
constexpr std::size_t kBuckets = kLinear + kSub * 57; // up to 2^63 units
} // namespace

std::size_t PeriodStats::bucket_of(std::uint64_t units) {
    if (units < kLinear) {
        return static_cast<std::size_t>(units);
    }
    const auto msb = static_cast<unsigned>(std::bit_width(units) - 1); // >= 7
    const unsigned shift = msb - 6;                                    // sub in [64, 127]
    const std::uint64_t sub = units >> shift;
    return static_cast<std::size_t>(kLinear + (shift - 1) * kSub + (sub - kSub));
}

std::uint64_t PeriodStats::bucket_floor(std::size_t index) {
    if (index < kLinear) {
        return index;
    }
    const std::uint64_t shift = (index - kLinear) / kSub + 1;
    const std::uint64_t sub = (index - kLinear) % kSub + kSub;
    return sub << shift;
}

PeriodStats::PeriodStats(Duration resolution)
    : resolution_(resolution.count() > 0 ? resolution : microseconds(1)), positive_(kBuckets, 0),
      negative_(kBuckets, 0) {}

void PeriodStats::add(Duration value) {
    if (count_ == 0 || value < min_) {
        min_ = value;
    }
    if (count_ == 0 || value > max_) {
        max_ = value;
    }
    ++count_;
    sum_ns_ += static_cast<long double>(value.count());
    const auto ns = value.count();
    const std::uint64_t magnitude =
        ns >= 0 ? static_cast<std::uint64_t>(ns) : static_cast<std::uint64_t>(-(ns + 1)) + 1;
    const std::uint64_t units = magnitude / static_cast<std::uint64_t>(resolution_.count());
    auto& buckets = ns >= 0 ? positive_ : negative_;
    ++buckets[std::min(bucket_of(units), kBuckets - 1)];
}

void PeriodStats::reset() {
    std::fill(positive_.begin(), positive_.end(), 0);
    std::fill(negative_.begin(), negative_.end(), 0);
    count_ = 0;
    min_ = max_ = Duration{0};
    sum_ns_ = 0;
}

Duration PeriodStats::mean() const {
    if (count_ == 0) {
        return Duration{0};
    }
    return Duration{
        static_cast<Duration::rep>(std::llround(sum_ns_ / static_cast<long double>(count_)))};
}

Duration PeriodStats::percentile(double p) const {
    if (count_ == 0) {
        return Duration{0};
    }
    p = std::clamp(p, 0.0, 1.0);
    // Rank of the sample, 1-based: the smallest value with at least p·n samples at or below.
    auto rank = static_cast<std::uint64_t>(std::ceil(p * static_cast<double>(count_)));
    rank = std::clamp<std::uint64_t>(rank, 1, count_);
    if (rank == count_) {
        return max_; // the extremes are known exactly
    }
    if (rank == 1) {
        return min_;
    }
    std::uint64_t seen = 0;
    const auto units = [this](std::size_t i) {
        return resolution_ * static_cast<std::int64_t>(bucket_floor(i));
    };
    // Most negative first: the negative buckets by falling magnitude, then the positive ones.
    for (std::size_t i = kBuckets; i-- > 0;) {
        seen += negative_[i];
        if (seen >= rank) {
            return std::clamp(-units(i), min_, max_);
        }
    }
    for (std::size_t i = 0; i < kBuckets; ++i) {
        seen += positive_[i];
        if (seen >= rank) {
            return std::clamp(units(i), min_, max_);
        }
    }
    return max_;
}

std::string PeriodStats::summary() const {
    return fmt::format(
        "n={} min {:.1f} us mean {:.1f} us p50 {:.1f} us p99 {:.1f} us max {:.1f} us", count_,
        to_us(min()), to_us(mean()), to_us(p50()), to_us(p99()), to_us(max()));
}

} // namespace codrive::sync
