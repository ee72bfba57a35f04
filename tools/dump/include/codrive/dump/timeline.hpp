// SPDX-License-Identifier: Apache-2.0
// Fixed-size time series and histograms for the report: memory does not grow with the trace.
#pragma once

#include <codrive/core/cob_id.hpp>

#include <array>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <vector>

namespace codrive::dump {

/// A histogram over logarithmic bins: 10 per decade from 1 µs to 100 s (80 bins), values below
/// and above counted apart. For SDO round trips and SYNC→TPDO latencies, whose scale is not
/// known in advance.
class LogHistogram {
public:
    static constexpr std::size_t kBins = 80;
    static constexpr double kLowNs = 1'000.0; ///< lower edge of bin 0
    static constexpr int kPerDecade = 10;
    /// Lower edge of bin `i` in nanoseconds.
    [[nodiscard]] static double edge_ns(std::size_t i);
    /// The bin of a value, or -1 below the first bin, kBins above the last.
    [[nodiscard]] static long bin_of(double ns);
    void add(double ns);
    [[nodiscard]] const std::array<std::uint32_t, kBins>& counts() const { return counts_; }
    [[nodiscard]] std::uint64_t below() const { return below_; }
    [[nodiscard]] std::uint64_t above() const { return above_; }
    [[nodiscard]] std::uint64_t total() const { return total_; }

private:
    std::array<std::uint32_t, kBins> counts_{};
    std::uint64_t below_ = 0;
    std::uint64_t above_ = 0;
    std::uint64_t total_ = 0;
};

/// A histogram of a period around its nominal value: the first kLearn intervals are kept, their
/// median becomes the nominal period, then kBins linear bins cover 0 to twice the nominal
/// period (intervals beyond that are counted as `above`). For the SYNC period.
class PeriodHistogram {
public:
    static constexpr std::size_t kLearn = 16;
    static constexpr std::size_t kBins = 200;
    void add(std::int64_t ns);
    /// Nominal period in ns (0 until the first interval).
    [[nodiscard]] double nominal_ns() const;
    /// Bin width in ns (0 until the first interval).
    [[nodiscard]] double bin_ns() const { return nominal_ns() * 2.0 / kBins; }
    /// The counts, with the intervals still being learned binned too.
    [[nodiscard]] std::array<std::uint32_t, kBins> counts() const;
    [[nodiscard]] std::uint64_t above() const;
    [[nodiscard]] std::uint64_t total() const { return total_; }

private:
    [[nodiscard]] double median_learned() const;
    void bin(std::array<std::uint32_t, kBins>& counts, std::uint64_t& above, double nominal,
             std::int64_t ns) const;
    std::array<std::int64_t, kLearn> first_{};
    std::size_t learned_ = 0;
    double nominal_ns_ = 0;
    std::array<std::uint32_t, kBins> counts_{};
    std::uint64_t above_ = 0;
    std::uint64_t total_ = 0;
};

/// Counters in kBuckets consecutive time buckets of equal width, for the whole bus and per node.
/// The first bucket starts at the first timestamp; a timestamp past the last bucket doubles the
/// width and merges neighbouring buckets until it fits, so the series always covers the whole
/// trace in at most kBuckets points and memory stays fixed.
class Timeline {
public:
    static constexpr std::size_t kBuckets = 512;
    static constexpr std::int64_t kFirstWidthNs = 1'000'000; ///< 1 ms, doubled as needed
    struct Bus {
        std::uint64_t bits = 0;
        std::uint32_t frames = 0;
        std::uint32_t sync = 0;
        std::uint32_t emcy = 0;
        std::uint32_t anomalies = 0; ///< warnings and errors other than EMCY
    };
    struct PerNode {
        std::uint32_t tpdo = 0;
        std::uint32_t rpdo = 0;
        std::uint32_t hb = 0; ///< heartbeat intervals ending in this bucket
        double hb_sum_ns = 0; ///< their sum
        std::int64_t hb_max_ns = 0;
    };

    Timeline();
    /// The bucket of `ts_ns`, widening the buckets if needed. Timestamps before the start (an
    /// out-of-order trace) fall into the first bucket.
    std::size_t bucket(std::int64_t ts_ns);
    [[nodiscard]] Bus& bus(std::size_t i) { return bus_[i]; }
    /// A node's row of buckets is allocated when the node first appears (a few nodes on a typical
    /// bus: 16 KiB each instead of 2 MiB for 128 rows up front).
    [[nodiscard]] PerNode& node(NodeId n, std::size_t i);
    [[nodiscard]] const Bus& bus(std::size_t i) const { return bus_[i]; }
    /// A node that never appeared reads as all-zero buckets.
    [[nodiscard]] const PerNode& node(NodeId n, std::size_t i) const;
    [[nodiscard]] bool started() const { return started_; }
    [[nodiscard]] std::int64_t start_ns() const { return start_ns_; }
    [[nodiscard]] std::int64_t width_ns() const { return width_ns_; }
    /// Buckets in use: up to and including the one of the latest timestamp.
    [[nodiscard]] std::size_t used() const { return used_; }

private:
    void widen();
    bool started_ = false;
    std::int64_t start_ns_ = 0;
    std::int64_t width_ns_ = kFirstWidthNs;
    std::size_t used_ = 0;
    std::vector<Bus> bus_;                                         // kBuckets, allocated once
    std::array<std::unique_ptr<PerNode[]>, kMaxNodeId + 1> nodes_; // kBuckets each, on first use
};

} // namespace codrive::dump
