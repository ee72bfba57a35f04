// SPDX-License-Identifier: Apache-2.0
// `codrive ecat dc`: configure distributed clocks, distribute the reference time for a while and
// report each slave's system time difference (0x092C).
#include "cmd_ecat_dc.hpp"
#include "command_registry.hpp"
#include "ecat_session.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cstdlib>
#include <memory>
#include <thread>

namespace codrive::cli {
namespace {

using namespace codrive::ethercat;

struct DcOptions {
    std::string iface;
    double seconds = 1.0;
    unsigned cycle_us = 1000;
    bool no_compensation = false;
};

int run_dc(const DcOptions& o) {
    if (o.cycle_us == 0 || o.seconds < 0 || o.seconds > 3600) {
        fmt::print(stderr, "codrive: --cycle-us must be at least 1 and --seconds 0..3600\n");
        return kExitUsage;
    }
    auto s = open_segment(o.iface);
    if (!s) {
        return kExitNoBus;
    }
    Master& m = *s->master;
    if (!m.configure_dc()) {
        fmt::print(stderr, "codrive: distributed clocks: {}\n", m.last_error());
        return kExitFailure;
    }
    if (!m.dc_reference()) {
        fmt::print("no slave has a distributed clock\n");
        return kExitOk;
    }
    // The reference clock's system time distributed every cycle (ETG.1000.4 §9.1.3), as the
    // cyclic frame of `codrive drive` and the controller does; sampled every 100 ms.
    std::vector<std::int64_t> worst(m.slaves().size(), 0);
    const auto cycle = microseconds(o.cycle_us);
    const TimePoint end = SteadyClock::now() + std::chrono::duration_cast<Duration>(
                                                   std::chrono::duration<double>(o.seconds));
    TimePoint next = SteadyClock::now();
    TimePoint sample = next + milliseconds(100);
    while (SteadyClock::now() < end) {
        if (!o.no_compensation && !m.distribute_system_time()) {
            fmt::print(stderr, "codrive: distributing the system time: {}\n", m.last_error());
            return kExitFailure;
        }
        if (SteadyClock::now() >= sample) {
            sample += milliseconds(100);
            if (auto st = m.dc_status()) {
                for (const auto& d : *st) {
                    worst[d.position] =
                        std::max(worst[d.position], std::abs(d.offset_to_reference));
                }
            }
        }
        next += cycle;
        std::this_thread::sleep_until(next);
    }
    auto st = m.dc_status();
    if (!st) {
        fmt::print(stderr, "codrive: reading the DC registers: {}\n", m.last_error());
        return kExitFailure;
    }
    fmt::print("reference clock: {}; {} over {:.1f} s every {} µs\n",
               m.slave_label(*m.dc_reference()),
               o.no_compensation ? "system time NOT distributed" : "system time distributed",
               o.seconds, o.cycle_us);
    for (const auto& d : *st) {
        worst[d.position] = std::max(worst[d.position], std::abs(d.offset_to_reference));
        if (d.position == *m.dc_reference()) {
            fmt::print("{}: reference clock, system time {} ns\n", m.slave_label(d.position),
                       d.system_time);
            continue;
        }
        fmt::print("{}: system time difference (0x092C) {} ns, offset to reference {} ns (max "
                   "|offset| {} ns), delay {} ns\n",
                   m.slave_label(d.position), d.difference, d.offset_to_reference,
                   worst[d.position], d.delay);
    }
    return kExitOk;
}

} // namespace

void install_ecat_dc(CLI::App& ecat, int& exit_code) {
    auto opts = std::make_shared<DcOptions>();
    auto* dc = ecat.add_subcommand(
        "dc", "distributed clocks: configure, distribute the reference time, report each "
              "slave's system time difference (0x092C)");
    dc->add_option("--ethercat", opts->iface, "network interface")->required();
    dc->add_option("--seconds", opts->seconds,
                   "how long to distribute the reference clock's time before the report "
                   "(default 1)");
    dc->add_option("--cycle-us", opts->cycle_us, "distribution period in µs (default 1000)");
    dc->add_flag("--no-compensation", opts->no_compensation,
                 "do not distribute the time after the start-up burst: shows how the clocks "
                 "drift apart");
    dc->callback([opts, &exit_code] { exit_code = run_dc(*opts); });
}

} // namespace codrive::cli
