// SPDX-License-Identifier: Apache-2.0
// codrive-ecat-sim: a chain of simulated EtherCAT slaves answering on a raw Ethernet interface.
#include "delay_line.hpp"

#include <codrive/sim/ecat/drive_profiles.hpp>
#include <codrive/sim/ecat/segment.hpp>
#include <codrive/sim/sim_device.hpp>

#include <codrive/ethercat/al_state.hpp>
#include <codrive/ethercat/pcap_writer.hpp>
#include <codrive/ethercat/raw_socket_link.hpp>

#include <codrive/core/value.hpp>

#include <CLI/CLI.hpp>
#include <fmt/format.h>

#include <atomic>
#include <cmath>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <random>
#include <vector>

namespace {

std::atomic<bool> g_stop{false};
std::atomic<int> g_toggle{0};
std::atomic<int> g_mailbox_toggle{0};
std::atomic<int> g_fault{0};

void on_stop(int) {
    g_stop = true;
}
void on_usr1(int) {
    ++g_toggle;
}
void on_usr2(int) {
    ++g_mailbox_toggle;
}
void on_fault_signal(int) {
    ++g_fault;
}
std::atomic<int> g_leave_op{0};
void on_leave_op_signal(int) {
    ++g_leave_op;
}

} // namespace

int main(int argc, char** argv) {
    using namespace codrive;
    using namespace codrive::ethercat;
    CLI::App app{"codrive-ecat-sim: simulated EtherCAT slaves (FIO, AKD2G, DS-BVS) on a raw "
                 "Ethernet interface (e.g. one end of a veth pair). The CAN simulator is the "
                 "separate codrive-sim."};
    app.set_version_flag("--version", "codrive-ecat-sim " CODRIVE_VERSION);
    std::string iface;
    std::vector<std::string> profiles;
    int mute_on_signal = -1;
    std::vector<int> mailbox_silent;
    int mute_mailbox_on_signal = -1;
    unsigned drop_permille = 0;
    unsigned delay_us = 0;
    std::vector<std::string> refuse;
    std::string lose_answers;
    std::string pcap;
    std::vector<std::string> foe_dirs;
    std::string foe_busy;
    std::string fault_on_signal;
    bool echo = false;
    app.add_option("--ethercat", iface, "interface to answer on")->required();
    app.add_option("--slave", profiles,
                   "slave profile in chain order: fio, akd2g, ds-bvs, generic, generic-nopdo");
    app.add_option("--mute-on-signal", mute_on_signal,
                   "SIGUSR1 toggles this slave silent (it stops answering)");
    app.add_option("--mailbox-silent", mailbox_silent,
                   "this slave consumes mailbox requests but never answers");
    app.add_option("--mute-mailbox-on-signal", mute_mailbox_on_signal,
                   "SIGUSR2 toggles this slave's mailbox silent (it consumes requests, never "
                   "answers; process data goes on)");
    app.add_option("--drop-frames", drop_permille,
                   "lose this many of every 1000 frames after the slaves processed them "
                   "(pseudo-random, fixed seed)")
        ->check(CLI::Range(0U, 1000U));
    app.add_option("--delay-us", delay_us,
                   "hold every frame this many µs after the slaves processed it before it goes "
                   "back (a slow host or line; the frames keep their order and rate)")
        ->check(CLI::Range(0U, 100000U));
    app.add_option("--refuse", refuse,
                   "POS:STATE:CODE — refuse the transition into STATE with AL status CODE");
    app.add_option("--lose-mailbox-answers", lose_answers,
                   "POS:N — lose every other frame that carries slave POS's mailbox answer until "
                   "N are lost (the master must ask for a repeat, ETG.1000.4 §6.7.2)");
    app.add_option("--foe-dir", foe_dirs,
                   "POS:DIR — slave POS's FoE files live in DIR too (reads find them there, "
                   "writes store them there)");
    app.add_option("--foe-busy", foe_busy,
                   "POS:N — slave POS answers the next N FoE DATA of a write with BUSY");
    app.add_option("--fault-on-signal", fault_on_signal,
                   "POS:AXIS — SIGRTMIN injects an over-current fault on this axis (from 1) of "
                   "slave POS, as writing 1 to its control object 2FF0h+AXIS-1 sub 2 does");
    std::string leave_op_on_signal;
    app.add_option("--leave-op-on-signal", leave_op_on_signal,
                   "POS:CODE[:N] — SIGRTMIN+1 drops slave POS from OP to SAFE-OP with AL status "
                   "CODE (a local error), and it refuses the next N OP requests with CODE");
    std::vector<std::string> clock_drift;
    app.add_option("--clock-drift-ppm", clock_drift,
                   "POS:PPM — slave POS's DC clock runs PPM parts per million fast (negative: "
                   "slow); default +20, -20, +30, -30, +40, -40 ppm by position");
    app.add_option("--pcap", pcap, "write every frame received and sent to this pcap file");
    app.add_flag("--echo", echo, "return frames untouched (raw-socket floor for benchmarks)");
    CLI11_PARSE(app, argc, argv);

    sim::ecat::EcatSegment segment;
    if (!echo) {
        if (profiles.empty()) {
            profiles = {"fio", "akd2g", "ds-bvs"};
        }
        std::uint32_t serial = 1001;
        for (const auto& p : profiles) {
            auto slave = sim::ecat::make_drive_slave(p, serial++);
            if (!slave) {
                std::fprintf(stderr,
                             "codrive-ecat-sim: unknown slave profile '%s' (use fio, "
                             "akd2g, ds-bvs, generic or generic-nopdo)\n",
                             p.c_str());
                return 2;
            }
            segment.add(std::move(slave));
        }
    }
    for (std::size_t i = 0; i < segment.size(); ++i) {
        segment.slave(i).dc_clock().set_drift_ppm(sim::ecat::default_clock_drift_ppm(i));
    }
    for (const auto& d : clock_drift) {
        const auto colon = d.find(':');
        const auto pos = parse_uint(d.substr(0, colon));
        char* end = nullptr;
        const std::string ppm_text = colon == std::string::npos ? "" : d.substr(colon + 1);
        const double ppm = std::strtod(ppm_text.c_str(), &end);
        if (!pos || *pos >= segment.size() || ppm_text.empty() || end == nullptr || *end != '\0' ||
            !(std::abs(ppm) <= 1000.0)) {
            std::fprintf(stderr,
                         "codrive-ecat-sim: bad --clock-drift-ppm '%s' (POS:PPM, e.g. 1:-50; POS a "
                         "configured slave, |PPM| up to 1000)\n",
                         d.c_str());
            return 2;
        }
        segment.slave(*pos).dc_clock().set_drift_ppm(ppm);
    }
    for (int pos : mailbox_silent) {
        if (pos >= 0 && static_cast<std::size_t>(pos) < segment.size()) {
            segment.slave(static_cast<std::size_t>(pos)).faults().mailbox_silent = true;
        }
    }
    for (const auto& r : refuse) {
        const auto a = r.find(':');
        const auto b = r.rfind(':');
        const auto pos = parse_uint(r.substr(0, a));
        const auto parsed =
            a == b ? std::nullopt : al_state_from_string(r.substr(a + 1, b - a - 1));
        const auto code = parse_uint(r.substr(b + 1));
        if (!pos || !parsed.has_value() || !code || *pos >= segment.size()) {
            std::fprintf(stderr,
                         "codrive-ecat-sim: bad --refuse '%s' (POS:STATE:CODE, e.g. "
                         "1:op:0x001A)\n",
                         r.c_str());
            return 2;
        }
        const AlState state = parsed.value_or(AlState::Init);
        segment.slave(*pos).faults().refuse[state] = static_cast<std::uint16_t>(*code);
    }

    // FoE options: the slave must list FoE in its SII (the AKD2G does).
    const auto foe_slave = [&](const std::string& arg, const char* what, const char* form,
                               std::string& rest) -> sim::ecat::FoeServer* {
        const auto colon = arg.find(':');
        const auto pos = parse_uint(arg.substr(0, colon));
        if (colon == std::string::npos || !pos || *pos >= segment.size() ||
            segment.slave(*pos).foe() == nullptr) {
            std::fprintf(stderr,
                         "codrive-ecat-sim: bad %s '%s' (%s, POS a slave with FoE such as "
                         "an akd2g)\n",
                         what, arg.c_str(), form);
            return nullptr;
        }
        rest = arg.substr(colon + 1);
        return segment.slave(*pos).foe();
    };
    for (const auto& d : foe_dirs) {
        std::string dir;
        auto* foe = foe_slave(d, "--foe-dir", "POS:DIR", dir);
        if (foe == nullptr) {
            return 2;
        }
        foe->set_directory(dir);
    }
    if (!foe_busy.empty()) {
        std::string n;
        auto* foe = foe_slave(foe_busy, "--foe-busy", "POS:N", n);
        const auto count = parse_uint(n);
        if (foe == nullptr || !count) {
            return 2;
        }
        foe->busy_next(static_cast<int>(*count));
    }

    sim::ecat::MailboxAnswerLoss loss;
    if (!lose_answers.empty()) {
        const auto colon = lose_answers.find(':');
        const auto pos = parse_uint(lose_answers.substr(0, colon));
        const auto n =
            colon == std::string::npos ? std::nullopt : parse_uint(lose_answers.substr(colon + 1));
        if (!pos || !n || *pos >= segment.size()) {
            std::fprintf(stderr,
                         "codrive-ecat-sim: bad --lose-mailbox-answers '%s' (POS:N, e.g. 1:3)\n",
                         lose_answers.c_str());
            return 2;
        }
        loss.arm(static_cast<std::size_t>(*pos), *n);
    }
    std::size_t fault_slave = 0;
    unsigned fault_axis = 0;
    if (!fault_on_signal.empty()) {
        const auto colon = fault_on_signal.find(':');
        const auto pos = parse_uint(fault_on_signal.substr(0, colon));
        const auto axis = colon == std::string::npos
                              ? std::nullopt
                              : parse_uint(fault_on_signal.substr(colon + 1));
        if (!pos || !axis || *pos >= segment.size() || *axis < 1 ||
            segment.slave(static_cast<std::size_t>(*pos))
                    .app()
                    .od()
                    .find(static_cast<std::uint16_t>(sim::kControlObject + *axis - 1)) == nullptr) {
            std::fprintf(stderr,
                         "codrive-ecat-sim: bad --fault-on-signal '%s' (POS:AXIS, e.g. 0:2; the "
                         "slave must have that axis)\n",
                         fault_on_signal.c_str());
            return 2;
        }
        fault_slave = static_cast<std::size_t>(*pos);
        fault_axis = static_cast<unsigned>(*axis);
    }
    std::size_t leave_op_slave = 0;
    std::uint16_t leave_op_code = 0;
    unsigned leave_op_refusals = 0;
    if (!leave_op_on_signal.empty()) {
        const auto a = leave_op_on_signal.find(':');
        const auto b = a == std::string::npos ? a : leave_op_on_signal.find(':', a + 1);
        // Plain values, not optionals: an invalid part becomes a value the check below refuses
        // (GCC's -O3 flow analysis misreads an optional built in a conditional expression).
        const std::uint64_t pos =
            parse_uint(leave_op_on_signal.substr(0, a)).value_or(segment.size());
        const std::uint64_t code =
            a == std::string::npos
                ? 0
                : parse_uint(leave_op_on_signal.substr(a + 1, b - a - 1)).value_or(0);
        const std::uint64_t n = b == std::string::npos
                                    ? 0
                                    : parse_uint(leave_op_on_signal.substr(b + 1)).value_or(1001);
        if (pos >= segment.size() || code == 0 || code > 0xFFFF || n > 1000) {
            std::fprintf(stderr,
                         "codrive-ecat-sim: bad --leave-op-on-signal '%s' (POS:CODE[:N], e.g. "
                         "0:0x001A:2; POS a configured slave, CODE 1..0xFFFF, N 0..1000)\n",
                         leave_op_on_signal.c_str());
            return 2;
        }
        leave_op_slave = static_cast<std::size_t>(pos);
        leave_op_code = static_cast<std::uint16_t>(code);
        leave_op_refusals = static_cast<unsigned>(n);
    }
    auto link = RawSocketLink::open(iface);
    if (!link) {
        std::fprintf(stderr, "codrive-ecat-sim: %s\n",
                     RawSocketLink::describe_open_error(iface, link.error()).c_str());
        return 3;
    }
    PcapWriter writer;
    if (!pcap.empty()) {
        if (!writer.open(pcap)) {
            std::fprintf(stderr, "codrive-ecat-sim: cannot write %s\n", pcap.c_str());
            return 2;
        }
        (*link)->set_tap([&](std::span<const std::uint8_t> f, bool) { writer.write(f); });
    }
    std::signal(SIGTERM, on_stop);
    std::signal(SIGINT, on_stop);
    std::signal(SIGUSR1, on_usr1);
    std::signal(SIGUSR2, on_usr2);
    std::signal(SIGRTMIN, on_fault_signal);
    std::signal(SIGRTMIN + 1, on_leave_op_signal);
    std::minstd_rand drop_rng(20);
    sim::ecat::DelayLine delayed{microseconds(delay_us)};
    const auto send = [&link](std::span<const std::uint8_t> f) { (void)(*link)->send(f); };
    std::uint64_t dropped = 0;
    std::printf("codrive-ecat-sim: %zu slave(s) on %s ready\n", segment.size(), iface.c_str());
    std::fflush(stdout);

    std::vector<std::uint8_t> buf(kMaxFrameSize + 64);
    int toggles_seen = 0;
    int mailbox_toggles_seen = 0;
    int faults_seen = 0;
    int leave_op_seen = 0;
    while (!g_stop) {
        if (const int t = g_fault.load(); t != faults_seen && fault_axis != 0) {
            faults_seen = t;
            const std::array<std::uint8_t, 1> on{1};
            (void)segment.slave(fault_slave)
                .app()
                .od()
                .write(static_cast<std::uint16_t>(sim::kControlObject + fault_axis - 1),
                       sim::kControlOverCurrent, on, true);
            std::printf("codrive-ecat-sim: slave %zu axis %u: over-current injected\n", fault_slave,
                        fault_axis);
            std::fflush(stdout);
        }
        if (const int t = g_leave_op.load(); t != leave_op_seen && leave_op_code != 0) {
            leave_op_seen = t;
            auto& slave = segment.slave(leave_op_slave);
            if (slave.leave_op(leave_op_code)) {
                slave.faults().refuse_op_requests = leave_op_refusals;
                slave.faults().refuse_op_code = leave_op_code;
            }
            std::printf("codrive-ecat-sim: slave %zu: left OP with AL status code 0x%04X, "
                        "refuses the next %u OP request(s)\n",
                        leave_op_slave, leave_op_code, leave_op_refusals);
            std::fflush(stdout);
        }
        if (const int t = g_toggle.load(); t != toggles_seen) {
            toggles_seen = t;
            if (mute_on_signal >= 0 && static_cast<std::size_t>(mute_on_signal) < segment.size()) {
                auto& f = segment.slave(static_cast<std::size_t>(mute_on_signal)).faults();
                f.silent = !f.silent;
                std::printf("codrive-ecat-sim: slave %d %s\n", mute_on_signal,
                            f.silent ? "stops answering" : "answers again");
                std::fflush(stdout);
            }
        }
        if (const int t = g_mailbox_toggle.load(); t != mailbox_toggles_seen) {
            mailbox_toggles_seen = t;
            if (mute_mailbox_on_signal >= 0 &&
                static_cast<std::size_t>(mute_mailbox_on_signal) < segment.size()) {
                auto& f = segment.slave(static_cast<std::size_t>(mute_mailbox_on_signal)).faults();
                f.mailbox_silent = !f.mailbox_silent;
                std::printf("codrive-ecat-sim: slave %d mailbox %s\n", mute_mailbox_on_signal,
                            f.mailbox_silent ? "goes silent" : "answers again");
                std::fflush(stdout);
            }
        }
        // The SM watchdog runs on time, not on frames: a master that died sends none.
        const TimePoint now = SteadyClock::now();
        for (std::size_t i = 0; i < segment.size(); ++i) {
            auto& slave = segment.slave(i);
            if (slave.tick(now)) {
                std::printf(
                    "codrive-ecat-sim: slave %zu (%s): no process data for %.0f ms, SM "
                    "watchdog expired: SAFE-OP + error 0x%04X, bus-loss reaction "
                    "applied\n",
                    i, slave.sii().name.c_str(),
                    std::chrono::duration<double, std::milli>(slave.watchdog_time()).count(),
                    slave.al_status_code());
                std::fflush(stdout);
            }
        }
        delayed.release(SteadyClock::now(), send);
        const TimePoint quiet = SteadyClock::now() + milliseconds(10);
        auto n = (*link)->receive(buf, delayed.next_due(quiet));
        if (!n && SteadyClock::now() < quiet) {
            continue; // a held frame is due
        }
        if (!n) {
            // No frame for 10 ms: the drives run on, as real ones do. Stepping them only before
            // a frame made the first frame after a pause (between two `codrive` commands) pay
            // for the whole pause in 1 ms motor steps of every axis, too late for the master's
            // frame timeout. While frames come, they step before each frame as before.
            for (std::size_t i = 0; i < segment.size(); ++i) {
                segment.slave(i).idle(SteadyClock::now());
            }
            continue;
        }
        std::span<std::uint8_t> frame(buf.data(), *n);
        if (!echo && !segment.process(frame, SteadyClock::now())) {
            continue;
        }
        if (echo && frame.size() > 6) {
            frame[6] = static_cast<std::uint8_t>(frame[6] | 0x02);
        }
        if (!echo && loss.lose(segment, frame)) {
            continue; // the frame with the answer never reaches the master
        }
        if (drop_permille != 0 && drop_rng() % 1000 < drop_permille) {
            ++dropped;
            continue; // lost on the way back, after the slaves processed it
        }
        if (delayed.active()) {
            delayed.hold(frame, SteadyClock::now());
        } else {
            send(frame);
        }
    }
    std::printf("codrive-ecat-sim: stopped after %llu frames (%llu dropped)\n",
                static_cast<unsigned long long>(segment.frames()),
                static_cast<unsigned long long>(dropped));
    for (std::size_t i = 0; i < segment.size(); ++i) {
        auto& slave = segment.slave(i);
        const std::uint64_t lost = i == loss.slave() ? loss.lost() : 0;
        if (slave.mailbox_repeats() != 0 || lost != 0) {
            std::printf("codrive-ecat-sim: slave %zu: %llu mailbox answers lost, %llu repeats "
                        "served\n",
                        i, static_cast<unsigned long long>(lost),
                        static_cast<unsigned long long>(slave.mailbox_repeats()));
        }
    }
    return 0;
}
