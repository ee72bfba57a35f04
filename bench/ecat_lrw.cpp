// SPDX-License-Identifier: Apache-2.0
// EtherCAT LRW round trip over veth against codrive-ecat-sim (3 slaves) next to a raw-socket
// echo floor measured in the same run; CPU per cycle; the shortest cycle without a lost frame.
// Needs root (veth, network namespace, AF_PACKET). Usage: bench_ecat_lrw [cycles] [fifo|other]
// [trials per cycle length]
#include <codrive/ethercat/master.hpp>
#include <codrive/ethercat/raw_socket_link.hpp>

#include <fmt/format.h>

#include <algorithm>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <fstream>
#include <functional>
#include <optional>
#include <sched.h>
#include <string>
#include <sys/wait.h>
#include <thread>
#include <unistd.h>
#include <vector>

namespace {

using namespace codrive;
using namespace codrive::ethercat;

std::string g_master_if;
std::string g_slave_if;
std::string g_echo_master_if; ///< second pair: the echo floor runs beside the segment
std::string g_echo_slave_if;
std::string g_netns;
bool g_realtime = false;

int sh(const std::string& cmd) {
    return std::system((cmd + " >/dev/null 2>&1").c_str());
}

void teardown() {
    if (!g_netns.empty()) {
        sh("ip link del " + g_master_if);
        sh("ip link del " + g_echo_master_if);
        sh("ip netns del " + g_netns);
    }
}

bool setup() {
    const int pid = static_cast<int>(::getpid()) % 100000;
    g_master_if = fmt::format("ebm{}", pid);
    g_slave_if = fmt::format("ebs{}", pid);
    g_echo_master_if = fmt::format("ebe{}", pid);
    g_echo_slave_if = fmt::format("ebf{}", pid);
    g_netns = fmt::format("codrive-bench-{}", pid);
    const bool echo_pair = sh(fmt::format("ip link add {} type veth peer name {}", g_echo_master_if,
                                          g_echo_slave_if)) == 0 &&
                           sh(fmt::format("ip link set {} up", g_echo_master_if)) == 0;
    return echo_pair && sh("ip netns add " + g_netns) == 0 &&
           sh(fmt::format("ip link set {} netns {}", g_echo_slave_if, g_netns)) == 0 &&
           sh(fmt::format("ip netns exec {} ip link set {} up", g_netns, g_echo_slave_if)) == 0 &&
           sh(fmt::format("ip link add {} type veth peer name {}", g_master_if, g_slave_if)) == 0 &&
           sh(fmt::format("ip link set {} netns {}", g_slave_if, g_netns)) == 0 &&
           sh(fmt::format("ip link set {} up", g_master_if)) == 0 &&
           sh(fmt::format("ip netns exec {} ip link set {} up", g_netns, g_slave_if)) == 0;
}

std::string sim_path() {
    if (const char* d = std::getenv("CODRIVE_TOOLS_DIR")) {
        return std::string(d) + "/codrive-ecat-sim";
    }
    std::vector<char> buf(4096);
    const ssize_t n = ::readlink("/proc/self/exe", buf.data(), buf.size() - 1);
    std::string self(buf.data(), n > 0 ? static_cast<std::size_t>(n) : 0);
    return self.substr(0, self.rfind('/')) + "/../tools/codrive-ecat-sim";
}

pid_t spawn_sim(const std::string& slave_if, const std::vector<std::string>& extra) {
    std::vector<std::string> args{"ip",       "netns",      "exec",  g_netns,
                                  sim_path(), "--ethercat", slave_if};
    args.insert(args.end(), extra.begin(), extra.end());
    const pid_t pid = ::fork();
    if (pid == 0) {
        std::vector<char*> argv;
        for (auto& a : args) {
            argv.push_back(a.data());
        }
        argv.push_back(nullptr);
        if (std::freopen("/dev/null", "w", stdout) == nullptr) {
            _exit(127);
        }
        ::execvp(argv[0], argv.data());
        _exit(127);
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(500));
    return pid;
}

double sim_cpu_seconds(pid_t pid) {
    std::ifstream f(fmt::format("/proc/{}/stat", pid));
    std::string s((std::istreambuf_iterator<char>(f)), std::istreambuf_iterator<char>());
    const auto close = s.rfind(')');
    if (close == std::string::npos) {
        return 0;
    }
    std::vector<std::string> fields;
    std::string cur;
    for (char c : s.substr(close + 2)) {
        if (c == ' ') {
            fields.push_back(cur);
            cur.clear();
        } else {
            cur.push_back(c);
        }
    }
    if (fields.size() < 13) {
        return 0;
    }
    return static_cast<double>(std::stoull(fields[11]) + std::stoull(fields[12])) /
           static_cast<double>(::sysconf(_SC_CLK_TCK));
}

void stop_sim(pid_t pid) {
    ::kill(pid, SIGTERM);
    int st = 0;
    ::waitpid(pid, &st, 0);
}

double thread_cpu_ns() {
    timespec ts{};
    ::clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
    return static_cast<double>(ts.tv_sec) * 1e9 + static_cast<double>(ts.tv_nsec);
}

struct Stats {
    double p50_us = 0;
    double p99_us = 0;
    double max_us = 0;
    double cpu_ns_per_cycle = 0;
    std::size_t lost = 0;
};

Stats summarize(std::vector<double>& rtt, double cpu_ns, std::size_t cycles, std::size_t lost) {
    Stats s;
    std::sort(rtt.begin(), rtt.end());
    if (!rtt.empty()) {
        s.p50_us = rtt[rtt.size() / 2];
        s.p99_us = rtt[std::min(rtt.size() - 1, rtt.size() * 99 / 100)];
        s.max_us = rtt.back();
    }
    s.cpu_ns_per_cycle = cpu_ns / static_cast<double>(cycles);
    s.lost = lost;
    return s;
}

/// Echo floor: the same-size LRW frame through a process that returns it untouched.
Stats echo_floor(RawSocketLink& link, std::size_t image, std::size_t cycles) {
    std::vector<Datagram> d{Datagram::logical(Command::Lrw, 0x10000, image)};
    std::vector<std::uint8_t> tx(kMaxFrameSize);
    std::vector<std::uint8_t> rx(kMaxFrameSize + 64);
    std::vector<double> rtt;
    rtt.reserve(cycles);
    std::size_t lost = 0;
    const double cpu0 = thread_cpu_ns();
    for (std::size_t i = 0; i < cycles; ++i) {
        d[0].index = static_cast<std::uint8_t>(i);
        const auto n = *encode_frame(d, tx);
        const auto t0 = SteadyClock::now();
        (void)link.send(std::span<const std::uint8_t>(tx).first(n));
        bool ok = false;
        while (true) {
            auto r = link.receive(rx, t0 + milliseconds(20));
            if (!r) {
                break;
            }
            if (frame_index(std::span<const std::uint8_t>(rx).first(*r)) == d[0].index) {
                ok = true;
                break;
            }
        }
        if (!ok) {
            ++lost;
            continue;
        }
        rtt.push_back(std::chrono::duration<double, std::micro>(SteadyClock::now() - t0).count());
    }
    return summarize(rtt, thread_cpu_ns() - cpu0, cycles, lost);
}

Stats lrw_run(Master& m, std::size_t cycles) {
    std::vector<double> rtt;
    rtt.reserve(cycles);
    std::size_t lost = 0;
    const double cpu0 = thread_cpu_ns();
    for (std::size_t i = 0; i < cycles; ++i) {
        const auto t0 = SteadyClock::now();
        auto w = m.exchange_process_data();
        if (!w) {
            ++lost;
            continue;
        }
        rtt.push_back(std::chrono::duration<double, std::micro>(SteadyClock::now() - t0).count());
    }
    return summarize(rtt, thread_cpu_ns() - cpu0, cycles, lost);
}

/// Runs `cycles` cycles at `period`: a frame is lost when its answer is not back within one
/// period of sending it. Wake-ups later than half a period are counted apart (overruns): they are
/// the scheduler's, not the wire's.
struct PeriodResult {
    std::size_t lost = 0;
    std::size_t overruns = 0;
};

/// `exchange(deadline)`: sends one frame and waits for its answer until `deadline`.
PeriodResult periodic_run(const std::function<bool(TimePoint)>& exchange, Duration period,
                          std::size_t cycles) {
    PeriodResult res;
    auto next = SteadyClock::now() + period;
    for (std::size_t i = 0; i < cycles; ++i) {
        const auto t0 = SteadyClock::now();
        if (!exchange(t0 + period)) {
            ++res.lost;
        }
        std::this_thread::sleep_until(next);
        if (SteadyClock::now() - next > period / 2) {
            ++res.overruns;
            next = SteadyClock::now(); // re-phase instead of a burst of catch-up cycles
        }
        next += period;
    }
    return res;
}

/// One echo exchange of an LRW-sized frame (the floor: no EtherCAT processing at all).
class EchoExchange {
public:
    EchoExchange(RawSocketLink& link, std::size_t image)
        : link_(link), d_{Datagram::logical(Command::Lrw, 0x10000, image)} {}
    bool operator()(TimePoint deadline) {
        d_[0].index = index_++;
        const auto n = *encode_frame(d_, tx_);
        (void)link_.send(std::span<const std::uint8_t>(tx_).first(n));
        while (true) {
            auto r = link_.receive(rx_, deadline);
            if (!r) {
                return false;
            }
            if (frame_index(std::span<const std::uint8_t>(rx_).first(*r)) == d_[0].index) {
                return true;
            }
        }
    }

private:
    RawSocketLink& link_;
    std::vector<Datagram> d_;
    std::vector<std::uint8_t> tx_ = std::vector<std::uint8_t>(kMaxFrameSize);
    std::vector<std::uint8_t> rx_ = std::vector<std::uint8_t>(kMaxFrameSize + 64);
    std::uint8_t index_ = 0;
};

/// The sweep of one path: per period, every trial's lost frames and overruns.
struct Sweep {
    std::vector<std::vector<PeriodResult>> trials; ///< [period][trial]
    /// The shortest period at which this and every longer period ran every trial with no lost
    /// frame (a single clean run below a failing one is luck, not a figure).
    [[nodiscard]] std::optional<std::size_t> shortest_clean() const {
        std::optional<std::size_t> best;
        for (std::size_t p = 0; p < trials.size(); ++p) {
            for (const auto& t : trials[p]) {
                if (t.lost != 0) {
                    return best;
                }
            }
            best = p;
        }
        return best;
    }
};

} // namespace

int main(int argc, char** argv) {
    const std::size_t cycles = argc > 1 ? std::stoul(argv[1]) : 10000;
    if (!setup()) {
        std::fprintf(stderr, "bench_ecat_lrw: cannot create veth/netns (needs root)\n");
        teardown();
        return 1;
    }
    std::atexit(teardown);
    // A real-time master runs SCHED_FIFO; so do master and simulator here when allowed, which
    // keeps the figures about the stack rather than about the machine's other load.
    sched_param sp{};
    sp.sched_priority = 50;
    if (argc > 2 && std::string(argv[2]) == "fifo") {
        g_realtime = ::sched_setscheduler(0, SCHED_FIFO, &sp) == 0;
    }
    auto link = RawSocketLink::open(g_master_if);
    if (!link) {
        std::fprintf(stderr, "%s\n",
                     RawSocketLink::describe_open_error(g_master_if, link.error()).c_str());
        return 1;
    }
    auto echo_link = RawSocketLink::open(g_echo_master_if);
    if (!echo_link) {
        std::fprintf(
            stderr, "%s\n",
            RawSocketLink::describe_open_error(g_echo_master_if, echo_link.error()).c_str());
        return 1;
    }
    // 1. The real thing: 3 simulated slaves, LRW of the whole process image; beside it on its
    // own veth pair the echo process that is the floor, both up for the whole run.
    const pid_t sim =
        spawn_sim(g_slave_if, {"--slave", "fio", "--slave", "akd2g", "--slave", "ds-bvs"});
    const pid_t echo = spawn_sim(g_echo_slave_if, {"--echo"});
    Master master(**link, RealClock::instance());
    if (!master.scan() || !master.set_state_all(AlState::Op)) {
        std::fprintf(stderr, "bench_ecat_lrw: bring-up failed: %s\n", master.last_error().c_str());
        stop_sim(sim);
        stop_sim(echo);
        return 1;
    }
    const std::size_t image = master.process_image().size();
    const double sim_cpu0 = sim_cpu_seconds(sim);
    const Stats lrw = lrw_run(master, cycles);
    const double sim_cpu = (sim_cpu_seconds(sim) - sim_cpu0) / static_cast<double>(cycles) * 1e9;
    const double echo_cpu0 = sim_cpu_seconds(echo);
    const Stats floor = echo_floor(**echo_link, image, cycles);
    const double echo_cpu = (sim_cpu_seconds(echo) - echo_cpu0) / static_cast<double>(cycles) * 1e9;
    // 2. Shortest cycle with no lost frame: every period, `trials` runs of `cycles` cycles, the
    // LRW and the echo floor interleaved (LRW, echo, LRW, echo...) so both see the same machine.
    const std::vector<Duration> periods{microseconds(1000), microseconds(500), microseconds(250),
                                        microseconds(125),  microseconds(100), microseconds(75),
                                        microseconds(50)};
    const int trials = argc > 3 ? std::stoi(argv[3]) : 2;
    EchoExchange echo_exchange(**echo_link, image);
    const auto lrw_exchange = [&master](TimePoint deadline) {
        return master.send_process_data() && master.receive_process_data(deadline).has_value();
    };
    Sweep lrw_sweep;
    Sweep echo_sweep;
    for (Duration p : periods) {
        lrw_sweep.trials.emplace_back();
        echo_sweep.trials.emplace_back();
        for (int t = 0; t < trials; ++t) {
            lrw_sweep.trials.back().push_back(periodic_run(lrw_exchange, p, cycles));
            echo_sweep.trials.back().push_back(periodic_run(std::ref(echo_exchange), p, cycles));
        }
    }
    stop_sim(sim);
    stop_sim(echo);

    fmt::print("bench_ecat_lrw: {} cycles, 3 slaves (FIO, AKD2G, DS-BVS), LRW of {} bytes, "
               "expected WKC {}\n",
               cycles, image, master.expected_wkc());
    fmt::print("scheduling: {} (machine load average at start: see `uptime`)\n",
               g_realtime ? "SCHED_FIFO 50 for master and simulator" : "SCHED_OTHER");
    fmt::print("late answers to timed-out cycles (stale frames): {}\n",
               master.stats().stale_frames);
    fmt::print("{:<28} {:>9} {:>9} {:>9} {:>14} {:>14} {:>6}\n", "", "p50 us", "p99 us", "max us",
               "master CPU ns", "sim CPU ns", "lost");
    fmt::print("{:<28} {:>9.1f} {:>9.1f} {:>9.1f} {:>14.0f} {:>14.0f} {:>6}\n",
               "LRW round trip (codrive)", lrw.p50_us, lrw.p99_us, lrw.max_us, lrw.cpu_ns_per_cycle,
               sim_cpu, lrw.lost);
    fmt::print("{:<28} {:>9.1f} {:>9.1f} {:>9.1f} {:>14.0f} {:>14.0f} {:>6}\n",
               "raw-socket echo floor", floor.p50_us, floor.p99_us, floor.max_us,
               floor.cpu_ns_per_cycle, echo_cpu, floor.lost);
    const auto us = [](Duration d) { return std::chrono::duration<double, std::micro>(d).count(); };
    for (std::size_t p = 0; p < periods.size(); ++p) {
        std::string l;
        std::string e;
        for (int t = 0; t < trials; ++t) {
            const auto& a = lrw_sweep.trials[p][static_cast<std::size_t>(t)];
            const auto& b = echo_sweep.trials[p][static_cast<std::size_t>(t)];
            l += fmt::format(" {}/{}", a.lost, a.overruns);
            e += fmt::format(" {}/{}", b.lost, b.overruns);
        }
        fmt::print("cycle {:>6.0f} us, lost/overruns per run of {}: LRW{}   echo floor{}\n",
                   us(periods[p]), cycles, l, e);
    }
    const auto report = [&](const char* what, const Sweep& sw) {
        if (const auto best = sw.shortest_clean()) {
            fmt::print("shortest cycle without a lost frame, {}: {:.0f} us ({} runs of {} cycles "
                       "at it and at every longer cycle)\n",
                       what, us(periods[*best]), trials, cycles);
        } else {
            fmt::print("shortest cycle without a lost frame, {}: none of the tested cycles\n",
                       what);
        }
    };
    report("LRW (codrive)", lrw_sweep);
    report("echo floor", echo_sweep);
    return 0;
}
