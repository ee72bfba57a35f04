// SPDX-License-Identifier: Apache-2.0
// measure_timer_latency() really sleeping: a callback that throws, or a stop request, ends an
// hour's run at once, with the probe thread joined (an unjoined std::thread would terminate).
#include <codrive/controller/timer_probe.hpp>

#include <gtest/gtest.h>

#include <chrono>
#include <stdexcept>

namespace codrive::controller {
namespace {

TimerProbeOptions hour_in_windows() {
    TimerProbeOptions o;
    o.cycle = milliseconds(2);
    o.duration = seconds(3600);
    o.window = milliseconds(100);
    return o;
}

TEST(TimerProbeRun, AnExceptionFromOnWindowEndsTheRunAndComesOut) {
    TimerProbeOptions o = hour_in_windows();
    o.on_window = [](const TimerWindow&) { throw std::runtime_error("enough"); };
    const auto t0 = std::chrono::steady_clock::now();
    EXPECT_THROW((void)measure_timer_latency(o), std::runtime_error);
    EXPECT_LT(std::chrono::steady_clock::now() - t0, std::chrono::seconds(5));
}

TEST(TimerProbeRun, AStopRequestEndsTheRunWithWhatWasMeasured) {
    TimerProbeOptions o = hour_in_windows();
    int windows = 0;
    o.on_window = [&](const TimerWindow&) { ++windows; };
    o.stop = [&] { return windows >= 2; };
    const TimerLatency r = measure_timer_latency(o);
    EXPECT_GE(r.windows.size(), 2U);
    EXPECT_LT(r.measured, seconds(5)) << "the hour was cut short";
    EXPECT_GE(r.wakeups, 1U);
    EXPECT_EQ(r.windows.size(), static_cast<std::size_t>(windows))
        << "every window in the summary was handed over, no more";
}

} // namespace
} // namespace codrive::controller
