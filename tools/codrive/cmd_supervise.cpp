// SPDX-License-Identifier: Apache-2.0
// `codrive supervise`: boots nodes, then watches them (heartbeat, EMCY, reboots) and brings
// rebooted nodes back automatically, printing every event as a sentence.
#include "cli_common.hpp"
#include "command_registry.hpp"

#include <codrive/master/master.hpp>

#include <atomic>
#include <csignal>
#include <fmt/format.h>

namespace codrive::cli {
namespace {

std::atomic<bool> g_stop{false};

struct SuperviseArgs {
    std::string iface;
    std::vector<unsigned> nodes;
    int heartbeat_ms = 100;
    int consumer_ms = 0;
    int guard_ms = 0;
    int life_factor = 3;
    bool no_start = false;
    double duration_s = 0;
    unsigned master_id = 0;
};

int run_supervise(const SuperviseArgs& a) {
    auto s = open_bus(a.iface);
    if (!s) {
        return kExitNoBus;
    }
    master::MasterConfig mc;
    mc.node_id = static_cast<NodeId>(a.master_id);
    mc.heartbeat_period = a.master_id != 0 ? milliseconds(a.heartbeat_ms) : milliseconds(0);
    master::Master m(*s->bus, RealClock::instance(), mc);
    s->loop->add_timed(&m);
    m.set_event_handler([](const master::MasterEvent& e) {
        fmt::print("[{}] {}\n", master::to_string(e.kind), e.text);
        std::fflush(stdout);
    });
    for (unsigned id : a.nodes) {
        if (!valid_node_id(id)) {
            fmt::print(stderr, "codrive: node id must be 1..127, not {}\n", id);
            return kExitUsage;
        }
        master::NodeConfig c;
        c.id = static_cast<NodeId>(id);
        if (a.guard_ms > 0) {
            c.guard_time = milliseconds(a.guard_ms);
            c.life_time_factor = static_cast<std::uint8_t>(a.life_factor);
        } else {
            c.heartbeat_producer = milliseconds(a.heartbeat_ms);
            c.heartbeat_consumer = milliseconds(a.consumer_ms);
        }
        c.start = !a.no_start;
        m.add_node(c);
    }
    std::signal(SIGINT, [](int) { g_stop = true; });
    std::signal(SIGTERM, [](int) { g_stop = true; });
    bool all_ok = true;
    m.boot_all([&](const std::vector<master::BootReport>& reports) {
        for (const auto& r : reports) {
            fmt::print("{}", r.to_string());
            all_ok = all_ok && r.ok;
        }
        std::fflush(stdout);
    });
    const TimePoint end =
        a.duration_s > 0
            ? SteadyClock::now() +
                  std::chrono::duration_cast<Duration>(std::chrono::duration<double>(a.duration_s))
            : kNever;
    while (!g_stop && SteadyClock::now() < end) {
        (void)s->loop->poll_once(std::chrono::milliseconds(100));
    }
    s->loop->remove_timed(&m);
    return all_ok ? kExitOk : kExitFailure;
}

void install_supervise(CLI::App& app, int& exit_code) {
    auto a = std::make_shared<SuperviseArgs>();
    auto* cmd = app.add_subcommand(
        "supervise", "Boot nodes and watch them: heartbeat loss, EMCY, reboots (auto-recovered)");
    cmd->add_option("-i,--iface", a->iface, "CAN interface")->required();
    cmd->add_option("-n,--node", a->nodes, "Node id (repeat for several)")->required();
    cmd->add_option("--heartbeat", a->heartbeat_ms, "Heartbeat producer time written to 1017h (ms)")
        ->capture_default_str();
    cmd->add_option("--consumer", a->consumer_ms,
                    "Master's consumer time (ms; default 1.5 x heartbeat)");
    cmd->add_option("--guard", a->guard_ms, "Use node guarding with this guard time (ms)");
    cmd->add_option("--life-factor", a->life_factor, "Life time factor for node guarding")
        ->capture_default_str();
    cmd->add_flag("--no-start", a->no_start, "Leave nodes pre-operational after boot-up");
    cmd->add_option("--duration", a->duration_s,
                    "Stop after this many seconds (default: run "
                    "until SIGINT)");
    cmd->add_option("--master-id", a->master_id, "Produce the master's own heartbeat as this node");
    cmd->callback([a, &exit_code] { exit_code = run_supervise(*a); });
}

} // namespace
} // namespace codrive::cli

using codrive::cli::install_supervise;
CODRIVE_REGISTER_COMMAND(install_supervise);
