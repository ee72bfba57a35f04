// SPDX-License-Identifier: Apache-2.0
// EtherCAT LRW round trip over veth against codrive-ecat-sim (3 slaves) next to a raw-socket
// echo floor measured in the same run (interleaved rounds, spread printed); CPU per cycle; the
// shortest cycle without a lost frame. Every figure is measured twice: the cycle alone, and with
// mailbox traffic beside it (an SDO upload loop on every slave whose datagrams ride in the cyclic
// frame, as a diagnostic poller adds it). Slaves found out of OP before a phase are brought back
// and reported. A ratio above 1.05 to the floor fails the program (the floor would be wrong), so
// does a failed SDO upload.
// Needs root (veth, network namespace, AF_PACKET). Usage: bench_ecat_lrw [cycles] [fifo|other]
// [trials per cycle length]
#include <codrive/ethercat/error.hpp>
#include <codrive/ethercat/master.hpp>
#include <codrive/ethercat/raw_socket_link.hpp>

#include "floor_check.hpp"

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

/// What bring_to_op() found before a phase: slaves that had left OP since the last phase.
struct OpCheck {
    std::size_t left_op = 0; ///< slaves found out of OP
    std::string found;       ///< "slave 1: SAFE-OP, AL status code 0x001B (...)" per slave
    bool restored = true;    ///< every slave is back in OP
};

/// Reads every slave's AL status; slaves found out of OP (an SM watchdog expiry while the bench
/// ran the echo floor, for instance: ETG.1000.6 §6.4.1, AL status code 0x001B) are brought back
/// to OP and reported, so that no phase measures slaves that stopped taking part.
OpCheck bring_to_op(Master& m) {
    OpCheck c;
    for (std::size_t i = 0; i < m.slaves().size(); ++i) {
        auto st = m.read_al_status(i);
        if (!st) {
            c.found +=
                fmt::format(" slave {}: AL status unreadable ({});", i + 1, st.error().message());
            c.restored = false;
            continue;
        }
        if (st->state == AlState::Op && !st->error) {
            continue;
        }
        ++c.left_op;
        c.found += fmt::format(" slave {}: {}{}, AL status code 0x{:04X} ({});", i + 1,
                               to_string(st->state), st->error ? " + error" : "", st->code,
                               al_status_code_describe(st->code));
        // The master keeps the state it last set; it must start from what the slave reports.
        m.slaves()[i].state = st->state;
    }
    if (c.left_op > 0 && !m.set_state_all(AlState::Op)) {
        c.restored = false;
        c.found += " back to OP failed: " + m.last_error();
    }
    return c;
}

/// What one exchange came to.
enum class Outcome { Ok, Lost, WkcShort };

/// One echo exchange of an LRW-sized frame (the floor: no EtherCAT processing at all).
class EchoExchange {
public:
    EchoExchange(RawSocketLink& link, std::size_t image)
        : link_(link), d_{Datagram::logical(Command::Lrw, 0x10000, image)} {}
    Outcome operator()(TimePoint deadline) {
        d_[0].index = index_++;
        const auto n = *encode_frame(d_, tx_);
        (void)link_.send(std::span<const std::uint8_t>(tx_).first(n));
        while (true) {
            auto r = link_.receive(rx_, deadline);
            if (!r) {
                return Outcome::Lost;
            }
            if (frame_index(std::span<const std::uint8_t>(rx_).first(*r)) == d_[0].index) {
                return Outcome::Ok;
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

/// One LRW exchange through the master: a WKC short of the expected one (a slave not in OP)
/// is told apart from a frame that never came back.
Outcome lrw_exchange(Master& m, TimePoint deadline) {
    if (!m.send_process_data()) {
        return Outcome::Lost;
    }
    auto r = m.receive_process_data(deadline);
    if (r) {
        return Outcome::Ok;
    }
    return r.error() == make_error_code(EcatErrc::WorkingCounter) ? Outcome::WkcShort
                                                                  : Outcome::Lost;
}

/// Mailbox traffic beside the cycle: one CoE SDO upload of 1018h:01 (vendor id) in flight on
/// every slave, the next one queued from the completion of the last. The master advances them
/// one step per cyclic frame (no blocking exchange), so the cycle's figures show what they cost.
class SdoLoad {
public:
    explicit SdoLoad(Master& m) : m_(m) {}
    void start() {
        running_ = true;
        for (std::size_t s = 0; s < m_.slaves().size(); ++s) {
            issue(s);
        }
    }
    /// Stops queuing new uploads and finishes the ones in flight with mailbox-only frames.
    void stop() {
        running_ = false;
        for (std::size_t s = 0; s < m_.slaves().size(); ++s) {
            m_.run_mailbox_until_idle(s);
        }
    }
    [[nodiscard]] std::size_t done() const { return done_; }
    [[nodiscard]] std::size_t failed() const { return failed_; }
    [[nodiscard]] const std::string& first_failure() const { return first_failure_; }

private:
    void issue(std::size_t s) {
        const auto r = m_.sdo_upload_async(s, 0x1018, 1, [this, s](CoeOutcome o) {
            if (o.error || o.data.size() != 4) {
                ++failed_;
                if (first_failure_.empty()) {
                    first_failure_ = o.error ? o.sentence : "a 1018h:01 answer of the wrong size";
                }
            } else {
                ++done_;
            }
            if (running_) {
                issue(s);
            }
        });
        if (!r) {
            ++failed_;
            if (first_failure_.empty()) {
                first_failure_ = m_.last_error();
            }
        }
    }

    Master& m_;
    bool running_ = false;
    std::size_t done_ = 0;
    std::size_t failed_ = 0;
    std::string first_failure_;
};

/// Round-trip figures of one path over interleaved rounds.
struct RoundTrips {
    std::vector<double> rtt_us;    ///< every answered exchange
    std::vector<double> round_p50; ///< per round (the spread)
    std::vector<double> round_cpu; ///< master-thread CPU ns per cycle, per round
    std::size_t lost = 0;
    std::size_t wkc_short = 0;

    /// `cycles` back-to-back exchanges, each waiting up to 20 ms (the master's frame timeout).
    void round(const std::function<Outcome(TimePoint)>& exchange, std::size_t cycles) {
        std::vector<double> r;
        r.reserve(cycles);
        const double cpu0 = thread_cpu_ns();
        for (std::size_t i = 0; i < cycles; ++i) {
            const auto t0 = SteadyClock::now();
            const Outcome o = exchange(t0 + milliseconds(20));
            if (o != Outcome::Ok) {
                ++(o == Outcome::Lost ? lost : wkc_short);
                continue;
            }
            r.push_back(std::chrono::duration<double, std::micro>(SteadyClock::now() - t0).count());
        }
        round_cpu.push_back((thread_cpu_ns() - cpu0) / static_cast<double>(cycles));
        round_p50.push_back(bench::percentile(r, 0.5));
        rtt_us.insert(rtt_us.end(), r.begin(), r.end());
    }
};

/// Runs `cycles` cycles at `period`: a frame is lost when its answer is not back within one
/// period of sending it. Wake-ups later than half a period are counted apart (overruns): they are
/// the scheduler's, not the wire's.
struct PeriodResult {
    std::size_t lost = 0;
    std::size_t wkc_short = 0;
    std::size_t overruns = 0;
    std::size_t left_op = 0; ///< slaves found out of OP before this run (and brought back)
};

PeriodResult periodic_run(const std::function<Outcome(TimePoint)>& exchange, Duration period,
                          std::size_t cycles) {
    PeriodResult res;
    auto next = SteadyClock::now() + period;
    for (std::size_t i = 0; i < cycles; ++i) {
        const auto t0 = SteadyClock::now();
        const Outcome o = exchange(t0 + period);
        if (o != Outcome::Ok) {
            ++(o == Outcome::Lost ? res.lost : res.wkc_short);
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

/// The sweep of one path: per period, every trial's result.
struct Sweep {
    std::vector<std::vector<PeriodResult>> trials; ///< [period][trial]
    /// The shortest period at which this and every longer period ran every trial with every
    /// frame back in time with its full working counter (a single clean run below a failing one
    /// is luck, not a figure).
    [[nodiscard]] std::optional<std::size_t> shortest_clean() const {
        std::optional<std::size_t> best;
        for (std::size_t p = 0; p < trials.size(); ++p) {
            for (const auto& t : trials[p]) {
                if (t.lost != 0 || t.wkc_short != 0) {
                    return best;
                }
            }
            best = p;
        }
        return best;
    }
};

void print_path(const char* name, const RoundTrips& r, double sim_cpu_ns) {
    fmt::print("{:<28} {:>9.1f} {:>9.1f} {:>9.1f} {:>14.0f} {:>14.0f} {:>6} {:>6}\n", name,
               bench::percentile(r.rtt_us, 0.5), bench::percentile(r.rtt_us, 0.99),
               bench::percentile(r.rtt_us, 1.0), bench::spread_of(r.round_cpu).median, sim_cpu_ns,
               r.lost, r.wkc_short);
}

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
    // 3 simulated slaves, LRW of the whole process image; beside it on its own veth pair the
    // echo process that is the floor, both up for the whole run.
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
    EchoExchange echo_exchange(**echo_link, image);
    const auto lrw = [&master](TimePoint deadline) { return lrw_exchange(master, deadline); };
    // Slaves found out of OP before a phase, over the whole run (each one brought back).
    std::size_t left_op_total = 0;
    bool op_restored = true;
    const auto check_op = [&](const std::string& phase) {
        const OpCheck c = bring_to_op(master);
        if (c.left_op > 0 || !c.restored) {
            fmt::print("before {}:{}\n", phase, c.found);
        }
        left_op_total += c.left_op;
        op_restored = op_restored && c.restored;
        return c.left_op;
    };

    SdoLoad sdo_load(master);
    double sdo_seconds = 0; // time the SDO loop ran beside the cycle
    const auto with_sdo = [&](const std::function<void()>& phase) {
        const auto t0 = SteadyClock::now();
        sdo_load.start();
        phase();
        sdo_seconds += std::chrono::duration<double>(SteadyClock::now() - t0).count();
        sdo_load.stop();
    };

    // 1. Round trips: `rounds` rounds of LRW, LRW with the SDO loop beside it, and echo, so all
    // three see the same machine.
    const std::size_t rounds = 10;
    const std::size_t per_round = std::max<std::size_t>(1, cycles / rounds);
    RoundTrips lrw_rt;
    RoundTrips mbx_rt;
    RoundTrips echo_rt;
    double sim_cpu_s = 0;
    double mbx_sim_cpu_s = 0;
    double echo_cpu_s = 0;
    for (std::size_t r = 0; r < rounds; ++r) {
        check_op(fmt::format("round-trip round {}", r + 1));
        double c0 = sim_cpu_seconds(sim);
        lrw_rt.round(lrw, per_round);
        sim_cpu_s += sim_cpu_seconds(sim) - c0;
        c0 = sim_cpu_seconds(sim);
        with_sdo([&] { mbx_rt.round(lrw, per_round); });
        mbx_sim_cpu_s += sim_cpu_seconds(sim) - c0;
        c0 = sim_cpu_seconds(echo);
        echo_rt.round(std::ref(echo_exchange), per_round);
        echo_cpu_s += sim_cpu_seconds(echo) - c0;
    }
    const double n_rt = static_cast<double>(per_round * rounds);
    // 2. Shortest cycle with no lost frame: every period, `trials` runs of `cycles` cycles, the
    // LRW and the echo floor interleaved (LRW, echo, LRW, echo...). The slaves' SM watchdog
    // (100 ms by default) expires during every echo run, so they are brought back to OP first.
    const std::vector<Duration> periods{microseconds(1000), microseconds(500), microseconds(250),
                                        microseconds(125),  microseconds(100), microseconds(75),
                                        microseconds(50)};
    const int trials = argc > 3 ? std::stoi(argv[3]) : 2;
    const auto us = [](Duration d) { return std::chrono::duration<double, std::micro>(d).count(); };
    Sweep lrw_sweep;
    Sweep mbx_sweep;
    Sweep echo_sweep;
    for (Duration p : periods) {
        lrw_sweep.trials.emplace_back();
        mbx_sweep.trials.emplace_back();
        echo_sweep.trials.emplace_back();
        for (int t = 0; t < trials; ++t) {
            std::size_t left = check_op(fmt::format("the {:.0f} us run {}", us(p), t + 1));
            lrw_sweep.trials.back().push_back(periodic_run(lrw, p, cycles));
            lrw_sweep.trials.back().back().left_op = left;
            left = check_op(fmt::format("the {:.0f} us run {} with SDO traffic", us(p), t + 1));
            with_sdo([&] { mbx_sweep.trials.back().push_back(periodic_run(lrw, p, cycles)); });
            mbx_sweep.trials.back().back().left_op = left;
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
    fmt::print("late answers to timed-out cycles: {} (unreadable frames: {})\n",
               master.stats().late_frames, master.stats().unreadable_frames);
    fmt::print("round trips: {} interleaved rounds of {} cycles per path\n", rounds, per_round);
    fmt::print("{:<28} {:>9} {:>9} {:>9} {:>14} {:>14} {:>6} {:>6}\n", "", "p50 us", "p99 us",
               "max us", "master CPU ns", "sim CPU ns", "lost", "WKC<");
    print_path("LRW round trip (codrive)", lrw_rt, sim_cpu_s / n_rt * 1e9);
    print_path("LRW + SDO uploads beside", mbx_rt, mbx_sim_cpu_s / n_rt * 1e9);
    print_path("raw-socket echo floor", echo_rt, echo_cpu_s / n_rt * 1e9);
    fmt::print("per-round p50, LRW:  {} us\n",
               bench::describe(bench::spread_of(lrw_rt.round_p50), 1));
    fmt::print("per-round p50, LRW + SDO: {} us\n",
               bench::describe(bench::spread_of(mbx_rt.round_p50), 1));
    fmt::print("per-round p50, echo: {} us\n",
               bench::describe(bench::spread_of(echo_rt.round_p50), 1));
    std::vector<double> latency_ratio;
    std::vector<double> mbx_latency_ratio;
    std::vector<double> cpu_ratio;
    for (std::size_t r = 0; r < rounds; ++r) {
        latency_ratio.push_back(lrw_rt.round_p50[r] > 0 ? echo_rt.round_p50[r] / lrw_rt.round_p50[r]
                                                        : 0);
        mbx_latency_ratio.push_back(
            mbx_rt.round_p50[r] > 0 ? echo_rt.round_p50[r] / mbx_rt.round_p50[r] : 0);
        cpu_ratio.push_back(lrw_rt.round_cpu[r] > 0 ? echo_rt.round_cpu[r] / lrw_rt.round_cpu[r]
                                                    : 0);
    }
    const bench::Spread lat = bench::spread_of(latency_ratio);
    const bench::Spread mbx_lat = bench::spread_of(mbx_latency_ratio);
    const bench::Spread cpu = bench::spread_of(cpu_ratio);
    fmt::print("echo p50 / LRW p50 per round: {} (1 = as fast as the floor)\n",
               bench::describe(lat));
    fmt::print("echo p50 / (LRW + SDO) p50 per round: {}\n", bench::describe(mbx_lat));
    fmt::print("echo CPU / LRW CPU per round: {}\n", bench::describe(cpu));
    fmt::print("SDO uploads beside the cycle: {} done ({:.0f}/s over {:.1f} s), {} failed{}{}\n",
               sdo_load.done(),
               sdo_seconds > 0 ? static_cast<double>(sdo_load.done()) / sdo_seconds : 0.0,
               sdo_seconds, sdo_load.failed(), sdo_load.failed() > 0 ? "; first: " : "",
               sdo_load.first_failure());

    for (std::size_t p = 0; p < periods.size(); ++p) {
        std::string l;
        std::string m;
        std::string e;
        std::size_t left = 0;
        for (int t = 0; t < trials; ++t) {
            const auto& a = lrw_sweep.trials[p][static_cast<std::size_t>(t)];
            const auto& c = mbx_sweep.trials[p][static_cast<std::size_t>(t)];
            const auto& b = echo_sweep.trials[p][static_cast<std::size_t>(t)];
            l += fmt::format(" {}/{}/{}", a.lost, a.wkc_short, a.overruns);
            m += fmt::format(" {}/{}/{}", c.lost, c.wkc_short, c.overruns);
            e += fmt::format(" {}/{}", b.lost, b.overruns);
            left += a.left_op + c.left_op;
        }
        fmt::print("cycle {:>6.0f} us, per run of {}: LRW lost/WKC short/overruns{}   with SDO{}   "
                   "echo floor lost/overruns{}   (slaves brought back to OP before the LRW runs: "
                   "{})\n",
                   us(periods[p]), cycles, l, m, e, left);
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
        return sw.shortest_clean();
    };
    const auto lrw_best = report("LRW (codrive)", lrw_sweep);
    const auto mbx_best = report("LRW with SDO uploads beside it", mbx_sweep);
    const auto echo_best = report("echo floor", echo_sweep);
    fmt::print("slaves found out of OP before a phase and brought back: {}{}\n", left_op_total,
               op_restored ? "" : " (bringing some back FAILED)");

    bool ok = op_restored;
    ok = bench::floor_holds("the LRW round trip (p50, inverted)", lat.median) && ok;
    ok = bench::floor_holds("the LRW + SDO round trip (p50, inverted)", mbx_lat.median) && ok;
    if (sdo_load.failed() > 0 || sdo_load.done() == 0) {
        fmt::print(stderr, "the SDO uploads beside the cycle failed ({} of {})\n",
                   sdo_load.failed(), sdo_load.failed() + sdo_load.done());
        ok = false;
    }
    ok = bench::floor_holds("the master's CPU per LRW cycle (inverted)", cpu.median) && ok;
    // A shorter clean cycle than the floor's is a floor that loses frames it should not.
    const auto beats_floor = [&](const std::optional<std::size_t>& best) {
        return best && (!echo_best || *best > *echo_best);
    };
    if (beats_floor(lrw_best) || beats_floor(mbx_best)) {
        fmt::print(stderr, "floor check failed: the LRW ran clean at a shorter cycle than the echo "
                           "floor, so the floor is not the best this machine can do\n");
        ok = false;
    }
    return ok ? 0 : 1;
}
