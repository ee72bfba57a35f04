// SPDX-License-Identifier: Apache-2.0
#include "probe_recorder.hpp"

#include <algorithm>
#include <cmath>

namespace codrive::controller::detail {
namespace {

void count(TimerWindow& w, Duration late, Duration cycle, std::uint64_t skipped) {
    ++w.wakeups;
    w.max = std::max(w.max, late);
    w.late_half_cycle += 2 * late >= cycle ? 1 : 0;
    w.late_whole_cycle += late >= cycle ? 1 : 0;
    w.skipped_slots += skipped;
}

} // namespace

ProbeRecorder::ProbeRecorder(Duration cycle, Duration duration, Duration window)
    : cycle_(cycle), bins_(kBins + 1, 0) {
    duration = std::max(duration, Duration::zero());
    if (window <= Duration::zero() || duration == Duration::zero()) {
        return;
    }
    // At most kMaxWindows: a window of 10 us over an hour would take gigabytes.
    constexpr auto kMax = static_cast<Duration::rep>(kMaxWindows);
    window_ = std::max(window, (duration + Duration(kMax - 1)) / kMax);
    const auto n = static_cast<std::size_t>((duration + window_ - Duration(1)) / window_);
    windows_.resize(n);
    for (std::size_t i = 0; i < n; ++i) {
        windows_[i].number = i + 1;
        windows_[i].from = window_ * static_cast<long>(i);
        windows_[i].to = std::min(duration, window_ * static_cast<long>(i + 1));
    }
}

void ProbeRecorder::add(Duration slot, Duration late, std::uint64_t skipped) {
    late = std::max(late, Duration::zero());
    const auto us =
        static_cast<std::size_t>(std::chrono::duration_cast<microseconds>(late).count());
    ++bins_[std::min(us, kBins)];
    count(total_, late, cycle_, skipped);
    if (windows_.empty()) {
        return;
    }
    // A slot at the very end of a window belongs to it: windows of 100 ms at a 1 ms cycle hold
    // 100 slots each.
    const auto at = slot > Duration::zero() ? (slot - Duration(1)) / window_ : 0;
    const std::size_t index = std::min(static_cast<std::size_t>(at), windows_.size() - 1);
    if (index > current_) {
        current_ = index;
        windows_done_.store(index, std::memory_order_release); // the ones before are complete
    }
    count(windows_[current_], late, cycle_, skipped);
}

void ProbeRecorder::finish(Duration ran) {
    std::size_t done = windows_.size();
    if (done > 0 && ran < windows_.back().to) {
        const auto reached = static_cast<std::size_t>((ran + window_ - Duration(1)) / window_);
        done = std::clamp<std::size_t>(reached, current_ + 1, windows_.size());
        windows_[done - 1].to = std::min(windows_[done - 1].to, std::max(ran, Duration::zero()));
    }
    windows_done_.store(done, std::memory_order_release);
}

Duration ProbeRecorder::quantile(double q) const {
    if (total_.wakeups == 0) {
        return Duration::zero();
    }
    const auto want = std::max<std::uint64_t>(
        1, static_cast<std::uint64_t>(std::ceil(q * static_cast<double>(total_.wakeups))));
    std::uint64_t seen = 0;
    for (std::size_t us = 0; us < kBins; ++us) {
        seen += bins_[us];
        if (seen >= want) {
            return microseconds(static_cast<long>(us));
        }
    }
    return total_.max; // past the last bin
}

TimerLatency ProbeRecorder::summary() const {
    TimerLatency r;
    r.cycle = cycle_;
    r.wakeups = total_.wakeups;
    r.skipped_slots = total_.skipped_slots;
    r.p50 = quantile(0.50);
    r.p99 = quantile(0.99);
    r.p999 = quantile(0.999);
    r.max = total_.max;
    r.late_half_cycle = total_.late_half_cycle;
    r.late_whole_cycle = total_.late_whole_cycle;
    r.windows.assign(windows_.begin(), windows_.begin() + static_cast<long>(std::min(
                                                              windows_done(), windows_.size())));
    return r;
}

} // namespace codrive::controller::detail
