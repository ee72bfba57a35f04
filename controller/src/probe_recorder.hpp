// SPDX-License-Identifier: Apache-2.0
// What the timer probe keeps while it measures: each wake-up's lateness in 1 us bins (for the
// quantiles), the counts and the exact maximum, and the same counts per window of a long run,
// all in memory taken before measuring.
#pragma once

#include <codrive/controller/timer_probe.hpp>

#include <atomic>
#include <cstddef>
#include <cstdint>
#include <vector>

namespace codrive::controller::detail {

class ProbeRecorder {
public:
    /// 1 us bins up to 1 s, one bin beyond (8 MB: 64-bit counts never wrap).
    static constexpr std::size_t kBins = 1'000'000;
    /// A run is cut into at most this many windows; shorter windows are widened.
    static constexpr std::size_t kMaxWindows = 100'000;

    /// `window` zero: no windows. Otherwise windows of `window` cover `duration`, the last one
    /// possibly shorter.
    ProbeRecorder(Duration cycle, Duration duration, Duration window);

    /// The wake-up for the slot `slot` after the start came `late`; `skipped` slots passed
    /// while it was late. Called by the probe thread only; allocates nothing.
    void add(Duration slot, Duration late, std::uint64_t skipped);
    /// The run is over after `ran`: every window it reached is complete, the last one ending
    /// at `ran` if the run was stopped early; windows it never reached are left out.
    void finish(Duration ran);

    /// Windows complete so far (they are not written any more): another thread may read
    /// window(i) for i below this.
    [[nodiscard]] std::size_t windows_done() const {
        return windows_done_.load(std::memory_order_acquire);
    }
    [[nodiscard]] const TimerWindow& window(std::size_t i) const { return windows_[i]; }
    /// Everything but `measured` and `warnings`, the windows included.
    [[nodiscard]] TimerLatency summary() const;

private:
    [[nodiscard]] Duration quantile(double q) const;

    Duration cycle_;
    Duration window_{};
    std::vector<std::uint64_t> bins_;
    TimerWindow total_;
    std::vector<TimerWindow> windows_;
    std::size_t current_ = 0;
    std::atomic<std::size_t> windows_done_{0};
};

} // namespace codrive::controller::detail
