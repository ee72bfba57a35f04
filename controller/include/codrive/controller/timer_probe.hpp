// SPDX-License-Identifier: Apache-2.0
// How late this machine wakes a periodic thread: the check to run before trusting it with a
// cycle. The probe waits the way the controller's dedicated cyclic thread does
// (clock_nanosleep(TIMER_ABSTIME) on CLOCK_MONOTONIC to start + k·cycle, a late wake-up skipping
// the slots it missed) with the same real-time settings, and summarises the lateness.
#pragma once

#include <codrive/controller/realtime.hpp>
#include <codrive/core/time.hpp>

#include <cstddef>
#include <cstdint>
#include <functional>
#include <span>
#include <string>
#include <vector>

namespace codrive::controller {

/// One window of a long run (TimerProbeOptions::window): qualifying a machine for an hour, the
/// worst minute is what matters, not the hour's quantiles.
struct TimerWindow {
    std::size_t number = 0; ///< 1 for the first
    Duration from{};        ///< from the start of the run
    Duration to{};
    std::uint64_t wakeups = 0;
    Duration max{};
    std::uint64_t late_half_cycle = 0;
    std::uint64_t late_whole_cycle = 0;
    std::uint64_t skipped_slots = 0;
    /// "window 3 (120.0-180.0 s): 60000 wake-ups, max 1.6 ms, 2 half a cycle late or more,
    /// 1 slot(s) skipped"
    [[nodiscard]] std::string to_string() const;
};

struct TimerProbeOptions {
    Duration cycle = milliseconds(1);
    Duration duration = seconds(10);
    RealtimeOptions realtime; ///< applied to the probe's own thread, as to the cyclic thread
    /// Above zero: the run is also cut into windows of this length (the last one may be
    /// shorter; at most 100000 windows, shorter ones are widened), each summarised in
    /// TimerLatency::windows.
    Duration window{};
    /// Called on the caller's thread with each window, in order, while the probe goes on
    /// measuring on its own thread: a live report of a long run. A window is handed over once
    /// the next one's first wake-up is in (about 0.1 s plus a cycle after it ends, later if a
    /// stall delays that wake-up). An exception thrown here ends the run and comes out of
    /// measure_timer_latency().
    std::function<void(const TimerWindow&)> on_window;
    /// Asked on the caller's thread about every 100 ms: true ends the run early (Ctrl-C), within
    /// about 0.2 s plus a cycle, and the summary covers what was measured until then
    /// (`measured` says how long).
    std::function<bool()> stop;
};

/// What a cyclic master at this cycle would have met.
enum class TimerVerdict {
    Sound,       ///< every wake-up within half a cycle of its slot
    Jittery,     ///< some wake-up half a cycle late or more, none a whole cycle: no slot lost
    SkipsCycles, ///< some wake-up a whole cycle late or more: a master would skip slots
};

struct TimerLatency {
    Duration cycle{};
    Duration measured{};             ///< wall time of the run
    std::uint64_t wakeups = 0;       ///< wake-ups measured
    std::uint64_t skipped_slots = 0; ///< slots passed while a wake-up was late
    Duration p50{}, p99{}, p999{}, max{};
    std::uint64_t late_half_cycle = 0;  ///< wake-ups half a cycle late or more
    std::uint64_t late_whole_cycle = 0; ///< wake-ups a whole cycle late or more
    std::vector<std::string> warnings;  ///< real-time settings that could not be applied
    std::vector<TimerWindow> windows;   ///< with TimerProbeOptions::window, in order

    [[nodiscard]] TimerVerdict verdict() const;
    /// The window with the most skipped slots, of those the one with the latest wake-up;
    /// nullptr without windows.
    [[nodiscard]] const TimerWindow* worst_window() const;
    /// Three lines: what was measured, the lateness figures, the verdict with what to do; with
    /// windows, the worst one's line before the verdict.
    [[nodiscard]] std::string to_string() const;
};

/// Summarises lateness samples (each wake-up's time after its slot). Quantiles are kept to the
/// microsecond (below 1 s; beyond, the maximum), the maximum exactly.
[[nodiscard]] TimerLatency summarize_lateness(std::span<const Duration> lateness, Duration cycle,
                                              std::uint64_t skipped_slots);

/// Runs the probe on a thread of its own for `options.duration` and returns the summary. Its
/// memory is the same (8 MB, plus 64 bytes a window) for any duration and cycle. `lock_memory`
/// locks the whole process's memory (mlockall), as it does for the controller.
[[nodiscard]] TimerLatency measure_timer_latency(const TimerProbeOptions& options);

} // namespace codrive::controller
