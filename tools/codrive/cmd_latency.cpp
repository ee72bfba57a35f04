// SPDX-License-Identifier: Apache-2.0
// `codrive latency`: how late this machine wakes a periodic thread, with a verdict for the
// cycle asked for. Run it before trusting a machine with a cycle (docs/cli/codrive-latency.md).
#include "cli_common.hpp"
#include "command_registry.hpp"

#include <codrive/controller/timer_probe.hpp>

#include <fmt/format.h>

#include <cstdio>

namespace codrive::cli {
namespace {

struct LatencyArgs {
    double cycle_us = 1000;
    double seconds = 10;
    double window = 0; ///< seconds; 0 = one summary only
    int priority = 0;  ///< SCHED_FIFO priority; 0 = normal scheduling
    int cpu = -1;
    bool lock_memory = false;
};

int run_latency(const LatencyArgs& a) {
    // Written so that NaN fails too.
    if (!(a.cycle_us >= 50 && a.cycle_us <= 1e6)) {
        fmt::print(stderr, "codrive: --cycle-us must be 50..1000000, not {}\n", a.cycle_us);
        return kExitUsage;
    }
    if (!(a.seconds > 0 && a.seconds <= 3600)) {
        fmt::print(stderr, "codrive: --seconds must be above 0 and at most 3600, not {}\n",
                   a.seconds);
        return kExitUsage;
    }
    if (a.window != 0 && !(a.window >= 0.1 && a.window <= a.seconds)) {
        fmt::print(stderr, "codrive: --window must be 0.1 s to --seconds ({}), not {}\n", a.seconds,
                   a.window);
        return kExitUsage;
    }
    if (a.priority < 0 || a.priority > 99) {
        fmt::print(stderr, "codrive: --fifo priority must be 1..99, not {}\n", a.priority);
        return kExitUsage;
    }
    controller::TimerProbeOptions o;
    o.cycle =
        std::chrono::duration_cast<Duration>(std::chrono::duration<double, std::micro>(a.cycle_us));
    o.duration = std::chrono::duration_cast<Duration>(std::chrono::duration<double>(a.seconds));
    o.realtime.fifo = a.priority > 0;
    o.realtime.priority = a.priority;
    o.realtime.cpu = a.cpu;
    o.realtime.lock_memory = a.lock_memory;
    if (a.window > 0) {
        o.window = std::chrono::duration_cast<Duration>(std::chrono::duration<double>(a.window));
        // One line a window as it ends, so an hour's run shows how it goes.
        o.on_window = [](const controller::TimerWindow& w) {
            fmt::print("{}\n", w.to_string());
            std::fflush(stdout);
        };
    }
    // Ctrl-C ends a long run early with the figures of what was measured.
    catch_stop_signals();
    o.stop = [] { return stop_requested(); };
    const auto r = controller::measure_timer_latency(o);
    if (stop_requested()) {
        fmt::print(stderr, "codrive: {} received: the figures cover the {:.1f} s measured\n",
                   signal_name(stop_signal()), std::chrono::duration<double>(r.measured).count());
    }
    for (const auto& w : r.warnings) {
        fmt::print(stderr, "codrive: warning: {}\n", w);
    }
    fmt::print("{}", r.to_string());
    // A machine that would skip cycles fails the check, so a script can stop there.
    return r.verdict() == controller::TimerVerdict::SkipsCycles ? kExitFailure : kExitOk;
}

void install_latency(CLI::App& app, int& exit_code) {
    auto a = std::make_shared<LatencyArgs>();
    auto* cmd = app.add_subcommand(
        "latency", "Measure how late this machine wakes a periodic thread (before trusting a "
                   "cycle to it)");
    cmd->add_option("--cycle-us", a->cycle_us, "Cycle to judge (us)")->capture_default_str();
    cmd->add_option("--seconds", a->seconds, "How long to measure (s)")->capture_default_str();
    cmd->add_option("--window", a->window,
                    "Also report every window of this many seconds as it ends, and the worst "
                    "(0.1..--seconds; 0 = off)")
        ->capture_default_str();
    cmd->add_option("--fifo", a->priority,
                    "Run the probe at this SCHED_FIFO priority (1..99), as a cyclic thread would");
    cmd->add_option("--cpu", a->cpu, "Pin the probe to this CPU");
    cmd->add_flag("--lock-memory", a->lock_memory, "Lock the process's memory (mlockall)");
    cmd->callback([a, &exit_code] { exit_code = run_latency(*a); });
}

} // namespace
} // namespace codrive::cli

using codrive::cli::install_latency;
CODRIVE_REGISTER_COMMAND(install_latency);
