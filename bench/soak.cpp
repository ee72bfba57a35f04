// SPDX-License-Identifier: Apache-2.0
// Soak on vcan: N SYNC cycles with simulated drives in CSP (run codrive-sim first, or use
// bench/soak.sh); prints lost PDOs, heap, fds and threads at cycle 10,000 and at the end.
//   bench_soak [CYCLES] [SYNC_PERIOD_US] [IFACE] [NODES]
// Defaults: 1000000 cycles, 2000 us, vcan0, NODES "1:akd2g,2:akd2g,3:akd2g,4:akd2g" (as
// codrive-sim hosts them, one axis each).
// Exit status 0 when the soak passed (see SoakReport::verdict), 1 otherwise.
#include <codrive/testing/soak.hpp>

#include <csignal>
#include <cstdio>
#include <cstdlib>

namespace {
volatile std::sig_atomic_t g_stop = 0;
void on_signal(int) {
    g_stop = 1;
}
} // namespace

int main(int argc, char** argv) {
    codrive::testing::SoakOptions o;
    o.cycles = argc > 1 ? std::strtoull(argv[1], nullptr, 10) : 1'000'000;
    o.sync_period_us =
        argc > 2 ? static_cast<std::uint32_t>(std::strtoul(argv[2], nullptr, 10)) : 2000;
    if (argc > 3) {
        o.iface = argv[3];
    }
    if (o.cycles == 0 || o.sync_period_us < 250 ||
        (argc > 4 && !codrive::testing::parse_soak_nodes(argv[4], o.nodes))) {
        std::fprintf(stderr,
                     "usage: %s [CYCLES>0] [SYNC_PERIOD_US>=250] [IFACE] [ID:PROFILE,...]\n",
                     argv[0]);
        return 2;
    }
    o.sample_at = std::min<std::uint64_t>(10'000, o.cycles);
    std::signal(SIGINT, on_signal);
    std::signal(SIGTERM, on_signal);
    o.stop = [] { return g_stop != 0; };
    o.on_running = [&] {
        std::printf("soak: running %llu cycles at %u us on %s\n",
                    static_cast<unsigned long long>(o.cycles), o.sync_period_us, o.iface.c_str());
        std::fflush(stdout);
    };
    o.progress_every = 100'000;
    o.on_progress = [](const std::string& line) {
        std::printf("%s\n", line.c_str());
        std::fflush(stdout);
    };
    const auto report = codrive::testing::run_soak(o);
    std::fputs(report.to_string().c_str(), stdout);
    const std::string verdict = report.verdict();
    std::printf("soak: %s%s\n", verdict.empty() ? "PASSED" : "FAILED: ", verdict.c_str());
    return verdict.empty() ? 0 : 1;
}
