// SPDX-License-Identifier: Apache-2.0
// Master supervision with real processes on vcan: scan, heartbeat loss of a killed node, and
// automatic recovery when it comes back; the full controller demo against simulated drives.
#include <codrive/testing/process.hpp>
#include <codrive/testing/vcan.hpp>

#include <gtest/gtest.h>

#include <csignal>

using namespace std::chrono_literals;
using codrive::testing::example_path;
using codrive::testing::Process;
using codrive::testing::tool_path;

TEST(VcanMaster, ScanFindsExactlyTheRunningNodes) {
    CODRIVE_REQUIRE_VCAN("vcan0");
    Process sim(
        {tool_path("codrive-sim"), "-i", "vcan0", "--node", "3:akd2g", "--node", "7:ds-bvs"});
    ASSERT_TRUE(sim.wait_for_output("node 7", 10s)) << sim.output();
    const auto r = codrive::testing::run({tool_path("codrive"), "scan", "-i", "vcan0"}, 30s);
    EXPECT_EQ(r.status, 0) << r.output;
    EXPECT_NE(r.output.find("2 nodes found"), std::string::npos) << r.output;
    EXPECT_NE(r.output.find("\n   3  "), std::string::npos) << r.output;
    EXPECT_NE(r.output.find("\n   7  "), std::string::npos) << r.output;
    std::printf("%s", r.output.c_str());
}

TEST(VcanMaster, KilledNodeIsReportedLostAndRebootedNodeIsRecoveredAutomatically) {
    CODRIVE_REQUIRE_VCAN("vcan0");
    auto sim = std::make_unique<Process>(
        std::vector<std::string>{tool_path("codrive-sim"), "-i", "vcan0", "--node", "5:akd2g"});
    ASSERT_TRUE(sim->wait_for_output("ready", 10s)) << sim->output();
    Process sup(
        {tool_path("codrive"), "supervise", "-i", "vcan0", "-n", "5", "--heartbeat", "100"});
    ASSERT_TRUE(sup.wait_for_output("boot-up OK", 15s)) << sup.output();
    sim->signal(SIGKILL);
    sim->wait(5s);
    EXPECT_TRUE(sup.wait_for_output("node 5: heartbeat lost", 5s)) << sup.output();
    sim = std::make_unique<Process>(
        std::vector<std::string>{tool_path("codrive-sim"), "-i", "vcan0", "--node", "5:akd2g"});
    EXPECT_TRUE(sup.wait_for_output("node 5: recovered after reboot", 15s)) << sup.output();
    EXPECT_NE(sup.output().find("back to operational"), std::string::npos) << sup.output();
    sup.signal(SIGINT);
    sup.wait(5s);
    std::printf("%s", sup.output().c_str());
}

TEST(VcanController, DemoScenarioBootsHomesMovesFaultsAndRecovers) {
    CODRIVE_REQUIRE_VCAN("vcan0");
    Process sim(
        {tool_path("codrive-sim"), "-i", "vcan0", "--node", "1:akd2g", "--node", "2:ds-bvs"});
    ASSERT_TRUE(sim.wait_for_output("node 2", 10s)) << sim.output();
    Process demo(
        {example_path("demo"), std::string(CODRIVE_SOURCE_DIR) + "/vcan-scripts/demo-bus.yml"});
    const auto status = demo.wait(120s);
    ASSERT_TRUE(status) << "demo hung: " << demo.output();
    const std::string out = demo.output();
    EXPECT_EQ(*status, 0) << out;
    EXPECT_NE(out.find("node 1 (gantry): boot-up OK"), std::string::npos) << out;
    EXPECT_NE(out.find("homing: ok"), std::string::npos) << out;
    // The demo checks the final position itself (within 1,000 increments of the target).
    EXPECT_NE(out.find("coordinated move done in"), std::string::npos) << out;
    EXPECT_EQ(out.find("coordinated move ended off target"), std::string::npos) << out;
    EXPECT_NE(out.find("EMCY 0x2310"), std::string::npos) << out;
    EXPECT_NE(out.find("Over current"), std::string::npos) << "vendor text" << out;
    EXPECT_NE(out.find("enable again: ok"), std::string::npos) << out;
    EXPECT_NE(out.find("demo OK"), std::string::npos) << out;
}
