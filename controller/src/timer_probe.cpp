// SPDX-License-Identifier: Apache-2.0
// The timer-latency probe: the cyclic thread's wait, measured, and put into words.
#include <codrive/controller/timer_probe.hpp>

#include <algorithm>
#include <cmath>
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

/// Lateness in 1 us bins up to 1 s and one bin beyond, the maximum exactly: the same memory
/// (4 MB, taken before measuring) for a minute or an hour at any cycle.
class LatenessHistogram {
public:
    static constexpr std::size_t kBins = 1'000'000;

    explicit LatenessHistogram(Duration cycle) : cycle_(cycle), bins_(kBins + 1, 0) {}

    void add(Duration late) {
        late = std::max(late, Duration::zero());
        const auto us =
            static_cast<std::size_t>(std::chrono::duration_cast<microseconds>(late).count());
        ++bins_[std::min(us, kBins)];
        ++count_;
        max_ = std::max(max_, late);
        half_ += 2 * late >= cycle_ ? 1 : 0;
        whole_ += late >= cycle_ ? 1 : 0;
    }

    [[nodiscard]] TimerLatency summary(std::uint64_t skipped_slots) const {
        TimerLatency r;
        r.cycle = cycle_;
        r.wakeups = count_;
        r.skipped_slots = skipped_slots;
        r.p50 = quantile(0.50);
        r.p99 = quantile(0.99);
        r.p999 = quantile(0.999);
        r.max = max_;
        r.late_half_cycle = half_;
        r.late_whole_cycle = whole_;
        return r;
    }

private:
    /// The smallest bin with at least q of the samples at or below it (the maximum past the
    /// last bin).
    [[nodiscard]] Duration quantile(double q) const {
        if (count_ == 0) {
            return Duration::zero();
        }
        const auto want = std::max<std::uint64_t>(
            1, static_cast<std::uint64_t>(std::ceil(q * static_cast<double>(count_))));
        std::uint64_t seen = 0;
        for (std::size_t us = 0; us < kBins; ++us) {
            seen += bins_[us];
            if (seen >= want) {
                return microseconds(static_cast<long>(us));
            }
        }
        return max_;
    }

    Duration cycle_;
    std::vector<std::uint32_t> bins_;
    std::uint64_t count_ = 0;
    Duration max_{};
    std::uint64_t half_ = 0;
    std::uint64_t whole_ = 0;
};

/// Cycles read best in microseconds: "1000 us", "250 us", "4000 us".
std::string cycle_text(Duration d) {
    return fmt::format("{} us", std::chrono::duration_cast<microseconds>(d).count());
}

} // namespace

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
    LatenessHistogram h(cycle);
    for (const Duration d : lateness) {
        h.add(d);
    }
    return h.summary(skipped_slots);
}

TimerLatency measure_timer_latency(const TimerProbeOptions& options) {
    const Duration cycle = std::max<Duration>(options.cycle, microseconds(10));
    LatenessHistogram lateness(cycle); // nothing allocates while measuring
    std::vector<std::string> warnings;
    std::uint64_t skipped = 0;
    TimePoint started{};
    TimePoint ended{};
    std::thread probe([&] {
        warnings = apply_realtime(options.realtime);
        started = SteadyClock::now();
        const TimePoint end = started + std::max(options.duration, Duration::zero());
        TimePoint slot = started + cycle;
        for (; slot <= end; slot += cycle) {
            sleep_until(slot); // the cyclic thread's own wait
            const Duration late = SteadyClock::now() - slot;
            lateness.add(late);
            if (late >= cycle) { // the slots it missed are skipped, as the controller does
                const auto missed = static_cast<std::uint64_t>(late / cycle);
                skipped += missed;
                slot += cycle * static_cast<long>(missed);
            }
        }
        ended = SteadyClock::now();
    });
    probe.join();
    TimerLatency r = lateness.summary(skipped);
    r.measured = ended - started;
    r.warnings = std::move(warnings);
    return r;
}

} // namespace codrive::controller
