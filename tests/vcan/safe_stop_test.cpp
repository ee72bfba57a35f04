// SPDX-License-Identifier: Apache-2.0
// Ctrl-C and SIGTERM to the programs that hold drives (issue 19): `codrive run --enable`,
// `codrive drive jog/move` and codrive-demo, each a real process against codrive-sim on vcan.
// Each must end within its shutdown budget, and the wire must show the documented safe stop:
// quick stop then disable voltage after the enable, the drive in SWITCH ON DISABLED, the node
// pre-operational.
#include <codrive/testing/can_wire.hpp>
#include <codrive/testing/process.hpp>
#include <codrive/testing/vcan.hpp>

#include <gtest/gtest.h>

#include <csignal>
#include <cstdio>
#include <fstream>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <unistd.h>

using namespace codrive;
using namespace std::chrono_literals;
using codrive::testing::CanWire;
using codrive::testing::example_path;
using codrive::testing::Process;
using codrive::testing::tool_path;

namespace {

/// One single-axis AKD2G (node 1) in CSP, SYNC every 4 ms, heartbeat 100 ms; plus `extra`
/// node entries.
std::string write_stop_bus_file(const std::string& extra = "") {
    const std::string path = "/tmp/codrive-safe-stop-" + std::to_string(::getpid()) + ".yml";
    std::ofstream(path) << "bus:\n  interface: vcan0\n  sync_period_us: 4000\n"
                           "  master: {node_id: 127, heartbeat_ms: 100}\nnodes:\n"
                           "  - id: 1\n    profile: akd2g\n    heartbeat_ms: 100\n"
                           "    axes:\n      - {axis: 1, mode: csp}\n"
                        << extra;
    return path;
}

/// CiA 402 §6.2 controlword commands and statusword states.
bool is_enable_operation(std::uint16_t cw) {
    return (cw & 0x8F) == 0x0F;
}
bool is_quick_stop(std::uint16_t cw) {
    return (cw & 0x86) == 0x02;
}
bool is_disable_voltage(std::uint16_t cw) {
    return (cw & 0x82) == 0x00;
}
bool is_operation_enabled(std::uint16_t sw) {
    return (sw & 0x6F) == 0x27;
}
bool is_switch_on_disabled(std::uint16_t sw) {
    return (sw & 0x4F) == 0x40;
}

std::string hex(const std::vector<std::uint16_t>& v) {
    std::string s;
    for (auto x : v) {
        char b[8];
        std::snprintf(b, sizeof b, "%04X ", x);
        s += b;
    }
    return s;
}

/// Enable operation, then quick stop, then disable voltage, in that order, in what the master
/// sent to `node`.
void expect_quick_stop_then_disable(const CanWire& wire, NodeId node) {
    const auto& cw = wire.controlwords(node);
    std::size_t i = 0;
    while (i < cw.size() && !is_enable_operation(cw[i])) {
        ++i;
    }
    ASSERT_LT(i, cw.size()) << "no enable operation sent; controlwords " << hex(cw);
    while (i < cw.size() && !is_quick_stop(cw[i])) {
        ++i;
    }
    ASSERT_LT(i, cw.size()) << "no quick stop after the enable; controlwords " << hex(cw);
    while (i < cw.size() && !is_disable_voltage(cw[i])) {
        ++i;
    }
    EXPECT_LT(i, cw.size()) << "no disable voltage after the quick stop; controlwords " << hex(cw);
}

/// No coasting: the master's first disable voltage after its quick stop comes only once the
/// drive reported standstill — SWITCH ON DISABLED reached by itself (605Ah 1/2) or QUICK STOP
/// ACTIVE with bit 10 "target reached" (605Ah 5/6: DS-BVS §6.2.81, AKD2G §5.4.2).
void expect_disable_only_at_standstill(const CanWire& wire, NodeId node) {
    const auto& t = wire.timeline(node);
    std::string seen;
    std::optional<std::uint16_t> last_sw;
    bool quick_stop = false;
    for (const auto& e : t) {
        char b[16];
        std::snprintf(b, sizeof b, "%s%04X ", e.controlword ? "cw" : "sw", e.value);
        seen += b;
        if (!e.controlword) {
            last_sw = e.value;
            continue;
        }
        if (is_quick_stop(e.value)) {
            quick_stop = true;
        } else if (quick_stop && is_disable_voltage(e.value)) {
            ASSERT_TRUE(last_sw.has_value()) << seen;
            const bool halted_in_quick_stop = (*last_sw & 0x6F) == 0x07 && (*last_sw & 0x400) != 0;
            EXPECT_TRUE(is_switch_on_disabled(*last_sw) || halted_in_quick_stop)
                << "node " << int(node) << ": disable voltage while the drive reported 0x"
                << std::hex << *last_sw << " (still on its quick-stop ramp): " << seen;
            return;
        }
    }
    ADD_FAILURE() << "node " << int(node) << ": no disable voltage after a quick stop: " << seen;
}

/// The drive's own statusword (SDO, after the master is gone) and its heartbeat state.
void expect_disabled_and_pre_operational(CanWire& wire, NodeId node, std::uint16_t sw_index) {
    const auto sw = wire.read_u16(node, sw_index);
    ASSERT_TRUE(sw.has_value()) << "node " << int(node) << " does not answer SDO";
    EXPECT_TRUE(is_switch_on_disabled(*sw))
        << "node " << int(node) << " statusword 0x" << std::hex << *sw;
    EXPECT_TRUE(
        wire.wait([&] { return wire.hb_state(node) == codrive::testing::kNmtPreOperational; }, 1s))
        << "node " << int(node) << " heartbeat state " << int(wire.hb_state(node).value_or(0xFF));
}

/// Sends `sig` and waits for the exit while reading the wire; returns the milliseconds it
/// took (-1: still running after 5 s) and the exit status.
std::pair<double, int> stop_with(Process& p, CanWire& wire, int sig) {
    const auto t0 = SteadyClock::now();
    p.signal(sig);
    const bool ended = wire.wait([&] { return !p.running(); }, 5s);
    const double ms = std::chrono::duration<double, std::milli>(SteadyClock::now() - t0).count();
    wire.run_for(300ms); // the last frames and a heartbeat
    return {ended ? ms : -1.0, ended ? p.wait(0ms).value_or(-1) : -1};
}

bool has(const Process& p, const std::string& text) {
    return p.output().find(text) != std::string::npos;
}

/// has(), read at most every 50 ms: the wire's wait calls its predicate after every frame, and
/// each read of the output is a file read (slow in the guest).
std::function<bool()> output_has(const Process& p, const std::string& text) {
    auto next = std::make_shared<TimePoint>();
    return [&p, text, next] {
        const TimePoint now = SteadyClock::now();
        if (now < *next) {
            return false;
        }
        *next = now + 50ms;
        return has(p, text);
    };
}

void run_command_stops_safely(int sig) {
    CODRIVE_REQUIRE_VCAN("vcan0");
    Process sim({tool_path("codrive-sim"), "-i", "vcan0", "--node", "1:akd2g:1"});
    ASSERT_TRUE(sim.wait_for_output("ready", 30s)) << sim.output();
    CanWire wire;
    ASSERT_TRUE(wire.ok());
    const std::string bus = write_stop_bus_file();
    Process run({tool_path("codrive"), "run", bus, "--enable", "--refresh", "1000"});
    ASSERT_TRUE(wire.wait(output_has(run, "node 1 axis 1: enabled"), 30s)) << run.output();
    ASSERT_TRUE(wire.wait(
        [&] {
            const auto& sw = wire.statuswords(1);
            return !sw.empty() && is_operation_enabled(sw.back());
        },
        2s))
        << "statuswords " << hex(wire.statuswords(1));
    wire.run_for(200ms);
    ASSERT_TRUE(run.running()) << run.output();
    const auto [ms, status] = stop_with(run, wire, sig);
    std::printf("codrive run: %s to exit: %.0f ms, exit status %d\n",
                sig == SIGINT ? "SIGINT" : "SIGTERM", ms, status);
    EXPECT_GE(ms, 0.0) << "still running 5 s after the signal\n" << run.output();
    EXPECT_LT(ms, 2000.0) << run.output();
    EXPECT_EQ(status, 0) << run.output();
    EXPECT_TRUE(has(run, sig == SIGINT ? "SIGINT received: safe shutdown"
                                       : "SIGTERM received: safe shutdown"))
        << run.output();
    expect_quick_stop_then_disable(wire, 1);
    expect_disable_only_at_standstill(wire, 1);
    expect_disabled_and_pre_operational(wire, 1, 0x6041);
    std::remove(bus.c_str());
}

} // namespace

TEST(VcanSafeStop, RunCommandStopsSafelyOnSigint) {
    run_command_stops_safely(SIGINT);
}

TEST(VcanSafeStop, RunCommandStopsSafelyOnSigterm) {
    run_command_stops_safely(SIGTERM);
}

// A signal while a node is still booting (node 5 does not exist: its boot-up waits on SDO
// timeouts of 3 s): start() gives up at once and sends every node NMT pre-operational.
TEST(VcanSafeStop, RunCommandInterruptedDuringBootUpExits130AndLeavesNodesPreOperational) {
    CODRIVE_REQUIRE_VCAN("vcan0");
    Process sim({tool_path("codrive-sim"), "-i", "vcan0", "--node", "1:akd2g:1"});
    ASSERT_TRUE(sim.wait_for_output("ready", 30s)) << sim.output();
    CanWire wire;
    ASSERT_TRUE(wire.ok());
    const std::string bus =
        write_stop_bus_file("  - id: 5\n    profile: akd2g\n    sdo_timeout_ms: 3000\n");
    Process run({tool_path("codrive"), "run", bus, "--enable"});
    // Node 5's boot-up probes it over SDO (3 probes of 3 s): the boot-up is under way and the
    // signal handlers are installed.
    ASSERT_TRUE(wire.wait([&] { return wire.sdo_requests(5) > 0; }, 30s)) << run.output();
    wire.run_for(300ms);
    ASSERT_TRUE(run.running()) << "the boot-up ended before the signal\n" << run.output();
    const std::size_t nmt_before = wire.nmt().size();
    const auto [ms, status] = stop_with(run, wire, SIGINT);
    std::printf("codrive run during boot-up: SIGINT to exit: %.0f ms, exit status %d\n", ms,
                status);
    EXPECT_GE(ms, 0.0) << run.output();
    EXPECT_LT(ms, 2000.0) << run.output();
    EXPECT_EQ(status, 130) << run.output();
    EXPECT_TRUE(has(run, "stopped by request during the boot-up")) << run.output();
    // NMT enter pre-operational (0x80) to all nodes, and no NMT start (0x01) after it.
    bool pre_op = false;
    for (std::size_t i = nmt_before; i < wire.nmt().size(); ++i) {
        const auto [cs, node] = wire.nmt()[i];
        if (cs == 0x80 && node == 0) {
            pre_op = true;
        }
        EXPECT_FALSE(pre_op && cs == 0x01) << "NMT start after the stop";
    }
    EXPECT_TRUE(pre_op) << "no NMT enter pre-operational after the signal";
    std::remove(bus.c_str());
}

// `codrive drive` holds the axis over SDO (no PDOs, node left in its NMT state): a signal
// during a jog or a long move quick-stops and disables it and exits 128 + the signal.
TEST(VcanSafeStop, DriveCommandHoldingAnAxisStopsItOnSigintAndSigterm) {
    CODRIVE_REQUIRE_VCAN("vcan0");
    Process sim({tool_path("codrive-sim"), "-i", "vcan0", "--node", "1:akd2g:1"});
    ASSERT_TRUE(sim.wait_for_output("ready", 30s)) << sim.output();
    for (const int sig : {SIGINT, SIGTERM}) {
        SCOPED_TRACE(sig == SIGINT ? "jog, SIGINT" : "move, SIGTERM");
        CanWire wire;
        ASSERT_TRUE(wire.ok());
        const std::vector<std::string> action =
            sig == SIGINT
                ? std::vector<std::string>{"jog", "--velocity", "20000", "--seconds", "30"}
                : std::vector<std::string>{"move", "--pp", "2000000000"};
        std::vector<std::string> argv{tool_path("codrive"), "drive", "-i", "vcan0", "-n", "1"};
        argv.insert(argv.end(), action.begin(), action.end());
        Process drive(argv);
        ASSERT_TRUE(wire.wait(
            [&] {
                for (auto cw : wire.controlwords(1)) {
                    if (is_enable_operation(cw)) {
                        return true;
                    }
                }
                return false;
            },
            30s)) // a UBSan build in a loaded guest needs seconds to start
            << drive.output();
        wire.run_for(500ms); // moving
        ASSERT_TRUE(drive.running()) << drive.output();
        const auto [ms, status] = stop_with(drive, wire, sig);
        std::printf("codrive drive %s: signal to exit: %.0f ms, exit status %d\n",
                    action[0].c_str(), ms, status);
        EXPECT_GE(ms, 0.0) << drive.output();
        EXPECT_LT(ms, 2000.0) << drive.output();
        EXPECT_EQ(status, 128 + sig) << drive.output();
        expect_quick_stop_then_disable(wire, 1);
        expect_disable_only_at_standstill(wire, 1);
        const auto sw = wire.read_u16(1, 0x6041);
        ASSERT_TRUE(sw.has_value());
        EXPECT_TRUE(is_switch_on_disabled(*sw)) << "statusword 0x" << std::hex << *sw << "\n"
                                                << drive.output();
    }
}

// The README demo interrupted while it homes: every axis of both drives ends disabled and both
// nodes pre-operational.
TEST(VcanSafeStop, DemoProgramStopsSafelyOnSigint) {
    CODRIVE_REQUIRE_VCAN("vcan0");
    Process sim(
        {tool_path("codrive-sim"), "-i", "vcan0", "--node", "1:akd2g", "--node", "2:ds-bvs"});
    ASSERT_TRUE(sim.wait_for_output("node 2", 30s)) << sim.output();
    CanWire wire;
    ASSERT_TRUE(wire.ok());
    Process demo(
        {example_path("demo"), std::string(CODRIVE_SOURCE_DIR) + "/vcan-scripts/demo-bus.yml"});
    ASSERT_TRUE(wire.wait(output_has(demo, "== homing"), 60s)) << demo.output();
    wire.run_for(100ms);
    ASSERT_TRUE(demo.running()) << demo.output();
    const auto [ms, status] = stop_with(demo, wire, SIGINT);
    std::printf("codrive-demo: SIGINT to exit: %.0f ms, exit status %d\n", ms, status);
    EXPECT_GE(ms, 0.0) << demo.output();
    EXPECT_LT(ms, 2000.0) << demo.output();
    EXPECT_EQ(status, 130) << demo.output();
    EXPECT_TRUE(has(demo, "SIGINT received: safe shutdown")) << demo.output();
    expect_quick_stop_then_disable(wire, 1);
    expect_quick_stop_then_disable(wire, 2);
    expect_disable_only_at_standstill(wire, 1);
    expect_disable_only_at_standstill(wire, 2);
    expect_disabled_and_pre_operational(wire, 1, 0x6041);
    expect_disabled_and_pre_operational(wire, 1, 0x6841); // AKD2G axis 2
    expect_disabled_and_pre_operational(wire, 2, 0x6041);
}

// The DS-BVS keeps 605Ah = 6 (quick-stop ramp 6085h = 1000 rpm/s, then stays in QUICK STOP
// ACTIVE: DS-BVS §6.2.89, §6.2.122): jogging at 600 rpm it needs about 0.6 s to stop. The safe
// stop on a signal waits for bit 10 before disable voltage; disabling at once would let the
// motor coast.
TEST(VcanSafeStop, DriveCommandWaitsForTheDsBvsQuickStopRampBeforeDisabling) {
    CODRIVE_REQUIRE_VCAN("vcan0");
    Process sim({tool_path("codrive-sim"), "-i", "vcan0", "--node", "2:ds-bvs"});
    ASSERT_TRUE(sim.wait_for_output("ready", 30s)) << sim.output();
    CanWire wire;
    ASSERT_TRUE(wire.ok());
    Process drive({tool_path("codrive"), "drive", "-i", "vcan0", "-n", "2", "jog", "--velocity",
                   "600", "--seconds", "30"});
    ASSERT_TRUE(wire.wait(
        [&] {
            for (auto cw : wire.controlwords(2)) {
                if (is_enable_operation(cw)) {
                    return true;
                }
            }
            return false;
        },
        30s)) // a UBSan build in a loaded guest needs several seconds to start
        << drive.output();
    wire.run_for(1500ms); // up to speed
    ASSERT_TRUE(drive.running()) << drive.output();
    const auto [ms, status] = stop_with(drive, wire, SIGINT);
    std::printf("codrive drive jog on the DS-BVS at 600 rpm: SIGINT to exit: %.0f ms\n", ms);
    EXPECT_GE(ms, 0.0) << drive.output();
    EXPECT_LT(ms, 2000.0) << drive.output();
    EXPECT_EQ(status, 130) << drive.output();
    expect_quick_stop_then_disable(wire, 2);
    expect_disable_only_at_standstill(wire, 2);
    const auto sw = wire.read_u16(2, 0x6041);
    ASSERT_TRUE(sw.has_value());
    EXPECT_TRUE(is_switch_on_disabled(*sw)) << "statusword 0x" << std::hex << *sw << "\n"
                                            << drive.output();
}
