// SPDX-License-Identifier: Apache-2.0
// codrive-sim: simulated CiA 402 drives (AKD2G, DS-BVS) on a SocketCAN interface.
#include <codrive/core/eds.hpp>
#include <codrive/core/event_loop.hpp>
#include <codrive/core/socket_can_bus.hpp>
#include <codrive/sim/options.hpp>
#include <codrive/sim/sim_device.hpp>

#include <CLI/CLI.hpp>
#include <fmt/format.h>

#include <algorithm>
#include <cerrno>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <functional>
#include <memory>
#include <string_view>
#include <sys/signalfd.h>
#include <unistd.h>
#include <vector>

using namespace codrive;
using namespace codrive::sim;

namespace {

struct Options {
    std::string iface;
    std::vector<std::string> nodes;
    std::vector<std::string> faults;
    std::string eds_dir;
    unsigned heartbeat_ms = 0;
    unsigned step_us = 1000;
    /// SO_RCVBUF(FORCE) of the simulator's socket. Generous by default: one process serves
    /// every simulated node, and a simulator starved of CPU for a while (a loaded machine, a
    /// one-CPU guest) must not overflow its socket and silently miss SYNCs or RPDOs.
    int rcvbuf_bytes = 4 << 20;
    bool verbose = false;
};

void print(const std::string& line) {
    std::fputs(line.c_str(), stdout);
    std::fputc('\n', stdout);
    std::fflush(stdout);
}

int run(const Options& o) {
    std::vector<NodeSpec> specs;
    for (const auto& text : o.nodes) {
        NodeSpec s;
        std::string err;
        if (!parse_node_spec(text, s, err)) {
            std::fprintf(stderr, "codrive-sim: %s\n", err.c_str());
            return 2;
        }
        if (!s.profile->can()) {
            std::fprintf(stderr, "codrive-sim: node %u: %s has no CAN interface (EtherCAT only)\n",
                         s.node, std::string(s.profile->name()).c_str());
            return 2;
        }
        for (const auto& other : specs) {
            if (other.node == s.node) {
                std::fprintf(stderr, "codrive-sim: node %u is given twice\n", s.node);
                return 2;
            }
        }
        specs.push_back(s);
    }
    std::vector<FaultSpec> faults;
    for (const auto& text : o.faults) {
        FaultSpec f;
        std::string err;
        if (!parse_fault_spec(text, f, err)) {
            std::fprintf(stderr, "codrive-sim: %s\n", err.c_str());
            return 2;
        }
        // Checked before the bus is opened and before any "ready": a fault aimed at a node that
        // is not simulated would otherwise never fire while the test waits for it.
        const bool simulated = std::any_of(specs.begin(), specs.end(),
                                           [&f](const NodeSpec& s) { return s.node == f.node; });
        if (!simulated) {
            std::fprintf(stderr,
                         "codrive-sim: --fault %s names node %u, which is not simulated (add "
                         "--node %u:PROFILE or fix the node id)\n",
                         text.c_str(), f.node, f.node);
            return 2;
        }
        faults.push_back(f);
    }

    // Signals arrive through a signalfd on the loop, so handlers never run inside services.
    sigset_t mask;
    sigemptyset(&mask);
    for (int sig : {SIGINT, SIGTERM, SIGUSR1, SIGUSR2}) {
        sigaddset(&mask, sig);
    }
    sigprocmask(SIG_BLOCK, &mask, nullptr);
    const int sfd = signalfd(-1, &mask, SFD_NONBLOCK | SFD_CLOEXEC);
    if (sfd < 0) {
        std::perror("codrive-sim: signalfd");
        return 1;
    }

    auto loop = EventLoop::create();
    if (!loop) {
        std::fprintf(stderr, "codrive-sim: cannot create the event loop: %s\n",
                     loop.error().message().c_str());
        return 1;
    }
    SocketCanOptions bus_options;
    bus_options.rcvbuf_bytes = o.rcvbuf_bytes;
    auto bus = SocketCanBus::open(o.iface, bus_options);
    if (!bus) {
        std::fprintf(stderr, "codrive-sim: %s\n",
                     describe_can_open_error(o.iface, bus.error()).c_str());
        return 1;
    }
    std::vector<std::unique_ptr<SimDevice>> devices;
    for (const auto& s : specs) {
        SimDeviceConfig c;
        c.node = s.node;
        c.profile = s.profile;
        c.axes = s.axes;
        c.step = microseconds(o.step_us);
        auto d = std::make_unique<SimDevice>(**bus, c);
        if (o.verbose) {
            d->set_log_handler([](const std::string& line) { print("codrive-sim: " + line); });
        }
        if (o.heartbeat_ms != 0) {
            std::uint8_t b[2];
            put_le<std::uint16_t>(b, static_cast<std::uint16_t>(o.heartbeat_ms));
            (void)d->store_parameter(0x1017, 0, {b, 2});
        }
        devices.push_back(std::move(d));
    }
    if (!o.eds_dir.empty()) {
        std::error_code ec;
        std::filesystem::create_directories(o.eds_dir, ec);
        for (const auto& d : devices) {
            const std::string path =
                fmt::format("{}/node{}-{}.eds", o.eds_dir, d->node(), d->profile().name());
            if (auto r = save_eds(d->describe(), path); !r) {
                std::fprintf(stderr, "codrive-sim: node %u: cannot write %s: %s\n", d->node(),
                             path.c_str(), r.error().message().c_str());
                return 1;
            }
            print(fmt::format("codrive-sim: node {}: wrote {}", d->node(), path));
        }
    }

    (*bus)->set_frame_handler([&devices](const Frame& f, TimePoint t) {
        for (auto& d : devices) {
            d->on_frame(f, t);
        }
    });
    if (auto r = (*bus)->attach(**loop); !r) {
        std::fprintf(stderr, "codrive-sim: cannot attach %s: %s\n", o.iface.c_str(),
                     r.error().message().c_str());
        return 1;
    }
    EventLoop& ev = **loop;
    int exit_code = 0;
    (void)ev.add_fd(sfd, 0x001 /* EPOLLIN */, [&](std::uint32_t) {
        signalfd_siginfo info{};
        while (::read(sfd, &info, sizeof info) == static_cast<ssize_t>(sizeof info)) {
            const auto sig = static_cast<int>(info.ssi_signo);
            if (sig == SIGINT || sig == SIGTERM) {
                print(fmt::format("codrive-sim: {} received, stopping",
                                  sig == SIGINT ? "SIGINT" : "SIGTERM"));
                ev.stop();
            } else if (sig == SIGUSR1) {
                // SIGUSR1 toggles the STO input of every axis of every node.
                for (auto& d : devices) {
                    for (unsigned a = 0; a < d->axis_count(); ++a) {
                        const bool on = !d->axis(a).sto();
                        d->axis(a).set_sto(on);
                        print(fmt::format("codrive-sim: node {} axis {}: STO {}", d->node(), a + 1,
                                          on ? "active" : "released"));
                    }
                }
            } else if (sig == SIGUSR2) {
                // SIGUSR2 resets every node (as NMT reset node: boot-up follows).
                for (auto& d : devices) {
                    print(fmt::format("codrive-sim: node {}: reset", d->node()));
                    d->reset_node(ev.now());
                }
            }
        }
    });

    const TimePoint start = ev.now();
    for (auto& d : devices) {
        ev.add_timed(d.get());
        d->start(start);
        print(fmt::format("codrive-sim: {} ready on {}", d->summary(), o.iface));
    }
    for (const auto& f : faults) {
        SimDevice* target = nullptr;
        for (auto& d : devices) {
            if (d->node() == f.node) {
                target = d.get();
            }
        }
        if (target == nullptr) {
            std::fprintf(stderr, "codrive-sim: fault for node %u, which is not simulated\n",
                         f.node);
            return 2;
        }
        ev.call_at(start + f.after, [&ev, target, f] {
            print(fmt::format("codrive-sim: node {} axis {}: inject {}", f.node, f.axis + 1,
                              to_string(f.kind)));
            target->inject(f.axis, f.kind, ev.now());
        });
    }
    // Frames the kernel dropped because the socket was full never reached any node: say so once
    // a second while it happens, and in total at exit, so a missed SYNC is never silent.
    std::uint64_t reported_drops = 0;
    std::function<void()> report_drops = [&] {
        const std::uint64_t dropped = (*bus)->stats().rx_dropped;
        if (dropped != reported_drops) {
            print(fmt::format("codrive-sim: {} received frames dropped by the kernel (socket "
                              "receive buffer full; {} in total): the nodes missed them",
                              dropped - reported_drops, dropped));
            reported_drops = dropped;
        }
        ev.call_at(ev.now() + seconds(1), report_drops);
    };
    ev.call_at(start + seconds(1), report_drops);
    if (auto r = ev.run(); !r) {
        std::fprintf(stderr, "codrive-sim: event loop failed: %s\n", r.error().message().c_str());
        exit_code = 1;
    }
    const BusStats& st = (*bus)->stats();
    print(fmt::format("codrive-sim: stopped; {} received frames dropped by the kernel, {} sends "
                      "refused (transmit queue full), {} sends delayed; {} frames received, {} "
                      "sent",
                      st.rx_dropped, st.tx_queue_full, st.tx_queued, st.rx_frames, st.tx_frames));
    for (auto& d : devices) {
        ev.remove_timed(d.get());
    }
    ev.remove_fd(sfd);
    ::close(sfd);
    return exit_code;
}

} // namespace

namespace {

// `codrive-sim --ethercat IFACE --slave fio ...` (issue 9's command line) runs the EtherCAT slave
// simulator, a separate program because it needs a raw socket and no SocketCAN: hand over to
// codrive-ecat-sim from the same directory with the same arguments.
[[noreturn]] void exec_ethercat_simulator(char** argv) {
    std::error_code ec;
    const auto self = std::filesystem::read_symlink("/proc/self/exe", ec);
    const std::string ecat_sim =
        (ec ? std::filesystem::path(argv[0]).parent_path() : self.parent_path()) /
        "codrive-ecat-sim";
    argv[0] = const_cast<char*>(ecat_sim.c_str());
    ::execv(ecat_sim.c_str(), argv);
    std::fprintf(stderr, "codrive-sim: --ethercat needs %s next to codrive-sim: %s\n",
                 ecat_sim.c_str(), std::strerror(errno));
    std::exit(2);
}

bool wants_ethercat(int argc, char** argv) {
    for (int i = 1; i < argc; ++i) {
        const std::string_view arg = argv[i];
        if (arg == "--ethercat" || arg.starts_with("--ethercat=")) {
            return true;
        }
    }
    return false;
}

} // namespace

int main(int argc, char** argv) {
    if (wants_ethercat(argc, argv)) {
        exec_ethercat_simulator(argv);
    }
    CLI::App app{"codrive-sim: simulated CiA 402 drives on a CAN interface.\n"
                 "With --ethercat IFACE --slave fio|akd2g|ds-bvs|generic|generic-nopdo ...: "
                 "simulated EtherCAT "
                 "slaves (runs codrive-ecat-sim).\n"
                 "Signals: SIGUSR1 toggles STO on every axis, SIGUSR2 resets every node, "
                 "SIGINT/SIGTERM stop."};
    app.set_version_flag("--version", "codrive-sim " CODRIVE_VERSION);
    Options o;
    app.add_option("-i,--interface", o.iface, "CAN interface (vcan0, can0)")->required();
    app.add_option("--node", o.nodes, "ID:PROFILE[:AXES], repeatable (profiles: akd2g, ds-bvs)")
        ->required();
    app.add_option("--fault", o.faults,
                   "NODE[.AXIS]:KIND[@TIME], repeatable; KIND: sto, overcurrent, "
                   "following-error, heartbeat-loss, reset; e.g. 1.2:sto@2s");
    app.add_option("--write-eds", o.eds_dir, "write an EDS per node into DIR and continue");
    app.add_option("--heartbeat", o.heartbeat_ms,
                   "producer heartbeat time (1017h) in ms, kept across resets (default 0: off)");
    app.add_option("--step-us", o.step_us, "motion step in microseconds (default 1000)")
        ->check(CLI::Range(100U, 100000U));
    app.add_option("--rcvbuf", o.rcvbuf_bytes,
                   "socket receive buffer in bytes (default 4194304; 0: the kernel's default)")
        ->check(CLI::Range(0, 1 << 30));
    app.add_flag("-v,--verbose", o.verbose, "log NMT changes, faults and EMCY");
    CLI11_PARSE(app, argc, argv);
    return run(o);
}
