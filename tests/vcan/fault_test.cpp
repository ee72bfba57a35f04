// SPDX-License-Identifier: Apache-2.0
// Faults with real processes on vcan: the master process is killed while the drives run CSP
// (their heartbeat consumers must bring them to the manual's fault reaction), a node reboots
// in the middle of CSP motion, and error frames put the bus error-passive and bus-off.
//
// The master is this binary running SoakVcanMaster.DISABLED_Run (soak_test.cpp); the drives
// are codrive-sim processes; the test watches the wire on its own socket.
#include <codrive/testing/can_wire.hpp>
#include <codrive/testing/process.hpp>
#include <codrive/testing/vcan.hpp>

#include <gtest/gtest.h>
#include <linux/can/error.h>

#include <climits>
#include <csignal>
#include <cstdlib>
#include <memory>
#include <optional>
#include <unistd.h>

using namespace codrive;
using namespace std::chrono_literals;
using codrive::testing::Process;
using codrive::testing::self_exe;
using codrive::testing::tool_path;

namespace {

/// The master process: SYNC every 4 ms, every axis enabled in CSP.
std::unique_ptr<Process> start_master(const std::string& nodes, unsigned consumer_ms) {
    ::setenv("CODRIVE_SOAK_NODES", nodes.c_str(), 1);
    ::setenv("CODRIVE_SOAK_CONSUMER_MS", std::to_string(consumer_ms).c_str(), 1);
    auto p = std::make_unique<Process>(
        std::vector<std::string>{self_exe(), "--gtest_also_run_disabled_tests",
                                 "--gtest_filter=SoakVcanMaster.DISABLED_Run"});
    ::unsetenv("CODRIVE_SOAK_NODES");
    ::unsetenv("CODRIVE_SOAK_CONSUMER_MS");
    return p;
}

/// Waits until the master process prints "soak: running"; false at once if it exits first.
bool wait_running(Process& master) {
    for (int i = 0; i < 400; ++i) {
        if (master.wait_for_output("soak: running", 100ms)) {
            return true;
        }
        if (!master.running()) {
            return false;
        }
    }
    return false;
}

using Wire = codrive::testing::CanWire;

constexpr std::uint16_t kHeartbeatLostEmcy = 0x8130; // CiA 301 "life guard / heartbeat error"
constexpr std::uint8_t kPreOperational = codrive::testing::kNmtPreOperational;
constexpr std::uint8_t kOperational = codrive::testing::kNmtOperational;

} // namespace

TEST(VcanFault, KilledMasterMakesAkd2gFaultF7002AndDsBvsQuickStopAndGoPreOperational) {
    CODRIVE_REQUIRE_VCAN("vcan0");
    Process sim(
        {tool_path("codrive-sim"), "-i", "vcan0", "--node", "1:akd2g:1", "--node", "3:ds-bvs"});
    ASSERT_TRUE(sim.wait_for_output("node 3", 10s)) << sim.output();
    // Both drives enabled in CSP and following set-points when the master dies.
    auto master = start_master("1:akd2g,3:ds-bvs", 300);
    ASSERT_TRUE(wait_running(*master)) << master->output();
    Wire wire;
    ASSERT_TRUE(wire.ok());
    ASSERT_TRUE(wire.wait([&] { return wire.tpdos(1) > 10 && wire.tpdos(3) > 10; }, 5s))
        << "the drives are not exchanging PDOs before the kill";
    EXPECT_FALSE(wire.emcy_seen(1, kHeartbeatLostEmcy));

    master->signal(SIGKILL);
    master->wait(5s);
    // Consumer time 300 ms: both nodes must react within a second of the last heartbeat.
    EXPECT_TRUE(wire.wait(
        [&] {
            return wire.emcy_seen(1, kHeartbeatLostEmcy) && wire.emcy_seen(3, kHeartbeatLostEmcy);
        },
        2s))
        << "no EMCY 8130h (heartbeat lost) from node 1 and node 3\n"
        << sim.output();
    wire.run_for(300ms); // quick stop ramps, heartbeats report the new NMT state
    // AKD2G (akd2g.md §4.3.1): F7002 "Fieldbus Heartbeat lost" — a fault: statusword bit 3.
    const auto sw1 = wire.read_u16(1, 0x6041);
    ASSERT_TRUE(sw1.has_value()) << "node 1 does not answer SDO";
    EXPECT_NE(*sw1 & 0x0008, 0) << "node 1 statusword 0x" << std::hex << *sw1;
    // DS-BVS (ds-bvs.md §2.6): 1029h:01 = 0 → pre-operational; 6007h = 3 → quick stop, which
    // with the default 605Ah = 6 ramps down and stays in QUICK STOP ACTIVE (statusword xxx0 0111:
    // bit 5 clear); no fault is latched (6007h 3 is not 1).
    EXPECT_EQ(wire.hb_state(3), kPreOperational);
    const auto sw3 = wire.read_u16(3, 0x6041);
    ASSERT_TRUE(sw3.has_value()) << "node 3 does not answer SDO";
    EXPECT_EQ(*sw3 & 0x006F, 0x0007) << "node 3 not in QUICK STOP ACTIVE: 0x" << std::hex << *sw3;
    EXPECT_EQ(*sw3 & 0x0008, 0) << "node 3 latched a fault: 0x" << std::hex << *sw3;
    std::printf("after the kill: node 1 statusword 0x%04X, node 3 statusword 0x%04X, NMT 0x%02X\n",
                *sw1, *sw3, wire.hb_state(3).value_or(0));
    EXPECT_TRUE(sim.running()) << sim.output();
}

TEST(VcanFault, NodeRebootDuringCspMotionIsReportedAndTheNodeIsRecovered) {
    CODRIVE_REQUIRE_VCAN("vcan0");
    // Two sim processes, so SIGUSR2 (reset every node of a process) reboots node 2 only.
    Process sim1({tool_path("codrive-sim"), "-i", "vcan0", "--node", "1:akd2g:1"});
    Process sim2({tool_path("codrive-sim"), "-i", "vcan0", "--node", "2:akd2g:1"});
    ASSERT_TRUE(sim1.wait_for_output("ready", 10s)) << sim1.output();
    ASSERT_TRUE(sim2.wait_for_output("ready", 10s)) << sim2.output();
    auto master = start_master("1:akd2g,2:akd2g", 0);
    ASSERT_TRUE(wait_running(*master)) << master->output();
    Wire wire;
    ASSERT_TRUE(wire.ok());
    ASSERT_TRUE(wire.wait([&] { return wire.tpdos(2) > 10; }, 5s));

    sim2.signal(SIGUSR2);
    EXPECT_TRUE(master->wait_for_output("node 2: rebooted on its own", 5s)) << master->output();
    EXPECT_TRUE(master->wait_for_output("node 2: recovered after reboot", 15s)) << master->output();
    // Recovered: operational again with its PDOs configured (TPDOs on SYNC), and node 1 kept
    // running throughout.
    const std::uint64_t before = wire.tpdos(2);
    EXPECT_TRUE(wire.wait([&] { return wire.tpdos(2) > before + 20; }, 5s))
        << "node 2 sends no TPDOs after recovery\n"
        << master->output();
    // Its heartbeat (100 ms) reports operational again; the last one seen may still be the
    // boot-up message when the first TPDOs arrive.
    EXPECT_TRUE(wire.wait([&] { return wire.hb_state(2) == kOperational; }, 2s))
        << "node 2 heartbeat state " << int(wire.hb_state(2).value_or(0xFF));
    EXPECT_EQ(wire.hb_state(1), kOperational);
    EXPECT_TRUE(master->running()) << master->output();
    master->signal(SIGTERM);
    master->wait(10s);
    std::printf("%s", master->output().c_str());
}

TEST(VcanFault, InjectedErrorPassiveAndBusOffFramesAreReportedAndCyclicTrafficContinues) {
    CODRIVE_REQUIRE_VCAN("vcan0");
    Process sim({tool_path("codrive-sim"), "-i", "vcan0", "--node", "1:akd2g:1"});
    ASSERT_TRUE(sim.wait_for_output("ready", 10s)) << sim.output();
    auto master = start_master("1:akd2g", 0);
    ASSERT_TRUE(wait_running(*master)) << master->output();
    Wire wire;
    ASSERT_TRUE(wire.ok());

    // SocketCAN error frames (linux/can/error.h) as a CAN controller driver reports them.
    Frame passive;
    passive.flags = Frame::kError;
    passive.id = CAN_ERR_CRTL | CAN_ERR_CNT;
    passive.len = 8;
    passive.data[1] = CAN_ERR_CRTL_TX_PASSIVE;
    passive.data[6] = 128;
    Frame bus_off;
    bus_off.flags = Frame::kError;
    bus_off.id = CAN_ERR_BUSOFF;
    bus_off.len = 8;
    Frame restarted;
    restarted.flags = Frame::kError;
    restarted.id = CAN_ERR_RESTARTED;
    restarted.len = 8;
    ASSERT_TRUE(wire.send(passive));
    EXPECT_TRUE(master->wait_for_output("error-passive", 5s)) << master->output();
    ASSERT_TRUE(wire.send(bus_off));
    EXPECT_TRUE(master->wait_for_output("bus-off", 5s)) << master->output();
    ASSERT_TRUE(wire.send(restarted));
    EXPECT_TRUE(master->wait_for_output("restarted", 5s)) << master->output();

    const std::uint64_t syncs = wire.syncs();
    const std::uint64_t tpdos = wire.tpdos(1);
    EXPECT_TRUE(
        wire.wait([&] { return wire.syncs() > syncs + 50 && wire.tpdos(1) > tpdos + 50; }, 5s))
        << "SYNC/PDO traffic stopped after the bus events\n"
        << master->output();
    EXPECT_EQ(wire.hb_state(1), kOperational);
    EXPECT_EQ(master->output().find("heartbeat lost"), std::string::npos) << master->output();
    EXPECT_TRUE(master->running()) << master->output();
    master->signal(SIGTERM);
    master->wait(10s);
    std::printf("%s", master->output().c_str());
}
