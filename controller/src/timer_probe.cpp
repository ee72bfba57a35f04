// SPDX-License-Identifier: Apache-2.0
// The timer-latency probe: the cyclic thread's wait, measured, and put into words.
#include <codrive/controller/timer_probe.hpp>

#include "probe_recorder.hpp"

#include <algorithm>
#include <atomic>
#include <exception>
#include <fmt/format.h>
#include <thread>

namespace codrive::controller {
namespace {

/// "62 us" below a millisecond, "14.1 ms" above.
std::string span_text(Duration d) {
    if (d < milliseconds(1)) {
        return fmt::format("{} us", std::chrono::duration_cast<microseconds>(d).count());
    }
    return fmt::format("{:.1f} ms", to_ms(d));
}

/// Cycles read best in microseconds: "1000 us", "250 us", "4000 us".
std::string cycle_text(Duration d) {
    return fmt::format("{} us", std::chrono::duration_cast<microseconds>(d).count());
}

} // namespace

std::string TimerWindow::to_string() const {
    return fmt::format("window {} ({:.1f}-{:.1f} s): {} wake-ups, max {}, {} half a cycle late or "
                       "more, {} slot(s) skipped",
                       number, std::chrono::duration<double>(from).count(),
                       std::chrono::duration<double>(to).count(), wakeups, span_text(max),
                       late_half_cycle, skipped_slots);
}

const TimerWindow* TimerLatency::worst_window() const {
    const auto worse = [](const TimerWindow& a, const TimerWindow& b) {
        return a.skipped_slots != b.skipped_slots ? a.skipped_slots < b.skipped_slots
                                                  : a.max < b.max;
    };
    const auto it = std::max_element(windows.begin(), windows.end(), worse);
    return it == windows.end() ? nullptr : &*it;
}

TimerVerdict TimerLatency::verdict() const {
    if (late_whole_cycle > 0) {
        return TimerVerdict::SkipsCycles;
    }
    return late_half_cycle > 0 ? TimerVerdict::Jittery : TimerVerdict::Sound;
}

std::string TimerLatency::to_string() const {
    std::string out = fmt::format(
        "timer latency: {} wake-ups at a {} cycle in {:.1f} s (clock_nanosleep to an absolute "
        "CLOCK_MONOTONIC time, as the controller's cyclic thread waits)\n",
        wakeups, cycle_text(cycle), std::chrono::duration<double>(measured).count());
    out += fmt::format("lateness: p50 {}, p99 {}, p99.9 {}, max {}; {} wake-up(s) half a cycle "
                       "late or more, {} a whole cycle or more ({} slot(s) skipped)\n",
                       span_text(p50), span_text(p99), span_text(p999), span_text(max),
                       late_half_cycle, late_whole_cycle, skipped_slots);
    if (const TimerWindow* w = worst_window(); w != nullptr) {
        out += fmt::format("worst of {} windows: {}\n", windows.size(), w->to_string());
    }
    switch (verdict()) {
    case TimerVerdict::Sound:
        out += fmt::format("verdict: sound for a {} cycle: every wake-up came within half a "
                           "cycle of its slot\n",
                           cycle_text(cycle));
        break;
    case TimerVerdict::Jittery:
        out += fmt::format(
            "verdict: jittery for a {} cycle: no slot would be skipped, but wake-ups came up to "
            "{} late; check that the drives' synchronous window (1007h) or SYNC0 shift allows "
            "that, or use a longer cycle\n",
            cycle_text(cycle), span_text(max));
        break;
    case TimerVerdict::SkipsCycles:
        out += fmt::format(
            "verdict: not sound for a {} cycle: a cyclic master here would have skipped {} "
            "slot(s), the worst wake-up {} late; use a cycle and slave watchdog well above {}, "
            "real-time scheduling (SCHED_FIFO), a CPU of its own, or other hardware\n",
            cycle_text(cycle), skipped_slots, span_text(max), span_text(max));
        break;
    }
    return out;
}

TimerLatency summarize_lateness(std::span<const Duration> lateness, Duration cycle,
                                std::uint64_t skipped_slots) {
    detail::ProbeRecorder r(cycle, Duration::zero(), Duration::zero());
    for (const Duration d : lateness) {
        r.add(Duration::zero(), d, 0);
    }
    TimerLatency out = r.summary();
    out.skipped_slots = skipped_slots;
    return out;
}

TimerLatency measure_timer_latency(const TimerProbeOptions& options) {
    const Duration cycle = std::max<Duration>(options.cycle, microseconds(10));
    const Duration duration = std::max(options.duration, Duration::zero());
    // Nothing allocates while measuring: the bins and the windows are taken here.
    detail::ProbeRecorder recorder(cycle, duration, options.window);
    std::vector<std::string> warnings;
    TimePoint started{};
    TimePoint ended{};
    std::atomic<bool> over{false};
    std::atomic<bool> stop{false};
    std::thread probe([&] {
        warnings = apply_realtime(options.realtime);
        started = SteadyClock::now();
        const TimePoint end = started + duration;
        TimePoint slot = started + cycle;
        for (; slot <= end && !stop.load(std::memory_order_relaxed); slot += cycle) {
            sleep_until(slot); // the cyclic thread's own wait
            const Duration late = SteadyClock::now() - slot;
            // The slots it missed are skipped, as the controller does.
            const auto missed = late >= cycle ? static_cast<std::uint64_t>(late / cycle) : 0U;
            recorder.add(slot - started, late, missed);
            slot += cycle * static_cast<long>(missed);
        }
        ended = SteadyClock::now();
        recorder.finish(ended - started);
        over.store(true, std::memory_order_release);
    });
    std::exception_ptr failed;
    if (options.on_window || options.stop) {
        // This thread hands the windows over as they end and asks whether to stop; the probe
        // never waits for it. A callback that throws ends the run: the probe is stopped and
        // joined before the exception goes on.
        try {
            std::size_t told = 0;
            while (true) {
                const bool done = over.load(std::memory_order_acquire);
                for (const std::size_t ready = recorder.windows_done();
                     options.on_window && told < ready; ++told) {
                    options.on_window(recorder.window(told));
                }
                if (done) {
                    break;
                }
                if (options.stop && options.stop()) {
                    stop.store(true, std::memory_order_relaxed);
                }
                std::this_thread::sleep_for(milliseconds(100));
            }
        } catch (...) {
            failed = std::current_exception();
            stop.store(true, std::memory_order_relaxed);
        }
    }
    probe.join();
    if (failed) {
        std::rethrow_exception(failed);
    }
    TimerLatency r = recorder.summary();
    r.measured = ended - started;
    r.warnings = std::move(warnings);
    return r;
}

} // namespace codrive::controller
