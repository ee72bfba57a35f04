// SPDX-License-Identifier: Apache-2.0
// Fixed-size time series and histograms for the report.
#include <codrive/dump/timeline.hpp>

#include <algorithm>
#include <cmath>

namespace codrive::dump {

double LogHistogram::edge_ns(std::size_t i) {
    return kLowNs * std::pow(10.0, static_cast<double>(i) / kPerDecade);
}

long LogHistogram::bin_of(double ns) {
    if (!(ns >= kLowNs)) { // also NaN
        return -1;
    }
    const auto b = static_cast<long>(std::floor(std::log10(ns / kLowNs) * kPerDecade + 1e-9));
    return std::min(b, static_cast<long>(kBins));
}

void LogHistogram::add(double ns) {
    ++total_;
    const long b = bin_of(ns);
    if (b < 0) {
        ++below_;
    } else if (b >= static_cast<long>(kBins)) {
        ++above_;
    } else {
        ++counts_[static_cast<std::size_t>(b)];
    }
}

void PeriodHistogram::bin(std::array<std::uint32_t, kBins>& counts, std::uint64_t& above,
                          double nominal, std::int64_t ns) const {
    const double width = nominal * 2.0 / kBins;
    const double b = width > 0 ? static_cast<double>(ns) / width : 0.0;
    if (b >= static_cast<double>(kBins)) {
        ++above;
        return;
    }
    ++counts[static_cast<std::size_t>(std::max(b, 0.0))];
}

double PeriodHistogram::nominal_ns() const {
    return learned_ == kLearn ? nominal_ns_ : median_learned();
}

double PeriodHistogram::median_learned() const {
    if (learned_ == 0) {
        return 0;
    }
    std::array<std::int64_t, kLearn> s = first_;
    std::sort(s.begin(), s.begin() + static_cast<long>(learned_));
    return static_cast<double>(s[learned_ / 2]);
}

void PeriodHistogram::add(std::int64_t ns) {
    ++total_;
    if (learned_ < kLearn) {
        first_[learned_++] = ns;
        if (learned_ == kLearn) {
            nominal_ns_ = median_learned();
            for (auto v : first_) {
                bin(counts_, above_, nominal_ns_, v);
            }
        }
        return;
    }
    bin(counts_, above_, nominal_ns_, ns);
}

std::array<std::uint32_t, PeriodHistogram::kBins> PeriodHistogram::counts() const {
    if (learned_ == kLearn) {
        return counts_;
    }
    std::array<std::uint32_t, kBins> c{};
    std::uint64_t above = 0;
    const double nominal = nominal_ns();
    for (std::size_t i = 0; i < learned_; ++i) {
        bin(c, above, nominal, first_[i]);
    }
    return c;
}

std::uint64_t PeriodHistogram::above() const {
    if (learned_ == kLearn) {
        return above_;
    }
    std::array<std::uint32_t, kBins> c{};
    std::uint64_t above = 0;
    const double nominal = nominal_ns();
    for (std::size_t i = 0; i < learned_; ++i) {
        bin(c, above, nominal, first_[i]);
    }
    return above;
}

Timeline::Timeline() : bus_(kBuckets) {}

Timeline::PerNode& Timeline::node(NodeId n, std::size_t i) {
    auto& row = nodes_[n];
    if (!row) {
        row = std::make_unique<PerNode[]>(kBuckets);
    }
    return row[i];
}

const Timeline::PerNode& Timeline::node(NodeId n, std::size_t i) const {
    static const PerNode kNever{};
    return nodes_[n] ? nodes_[n][i] : kNever;
}

void Timeline::widen() {
    const std::size_t half = kBuckets / 2;
    for (std::size_t i = 0; i < half; ++i) {
        const Bus& a = bus_[2 * i];
        const Bus& b = bus_[2 * i + 1];
        bus_[i] = Bus{a.bits + b.bits, a.frames + b.frames, a.sync + b.sync, a.emcy + b.emcy,
                      a.anomalies + b.anomalies};
    }
    std::fill(bus_.begin() + static_cast<long>(half), bus_.end(), Bus{});
    for (const auto& owned : nodes_) {
        PerNode* row = owned.get();
        if (row == nullptr) {
            continue;
        }
        for (std::size_t i = 0; i < half; ++i) {
            const PerNode& a = row[2 * i];
            const PerNode& b = row[2 * i + 1];
            row[i] = PerNode{a.tpdo + b.tpdo, a.rpdo + b.rpdo, a.hb + b.hb,
                             a.hb_sum_ns + b.hb_sum_ns, std::max(a.hb_max_ns, b.hb_max_ns)};
        }
        std::fill(row + half, row + kBuckets, PerNode{});
    }
    width_ns_ *= 2;
    used_ = (used_ + 1) / 2;
}

std::size_t Timeline::bucket(std::int64_t ts) {
    if (!started_) {
        started_ = true;
        start_ns_ = ts;
    }
    if (ts < start_ns_) {
        used_ = std::max<std::size_t>(used_, 1);
        return 0;
    }
    while ((ts - start_ns_) / width_ns_ >= static_cast<std::int64_t>(kBuckets)) {
        widen();
    }
    const auto i = static_cast<std::size_t>((ts - start_ns_) / width_ns_);
    used_ = std::max(used_, i + 1);
    return i;
}

} // namespace codrive::dump
