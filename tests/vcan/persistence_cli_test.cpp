// SPDX-License-Identifier: Apache-2.0
// `codrive save` / `codrive restore` against a simulated DS-BVS in another process on vcan:
// a saved value survives NMT reset node, a restored default comes back after the next reset.
#include <codrive/testing/process.hpp>
#include <codrive/testing/vcan.hpp>

#include <gtest/gtest.h>

#include <thread>

using namespace std::chrono_literals;
using codrive::testing::Process;
using codrive::testing::run;
using codrive::testing::tool_path;

namespace {

/// 6065h (following error window) of `node` as `codrive sdo read` prints it.
std::string window(const std::string& codrive, const std::string& node) {
    auto r =
        run({codrive, "sdo", "read", "-i", "vcan0", "-n", node, "0x6065:0", "--type", "u32"}, 30s);
    EXPECT_EQ(r.status, 0) << r.output;
    return r.output;
}

void reset_node(const std::string& codrive, const std::string& node) {
    auto r = run({codrive, "nmt", "-i", "vcan0", "reset", node}, 30s);
    EXPECT_EQ(r.status, 0) << r.output;
    std::this_thread::sleep_for(300ms); // boot-up and pre-operational
}

} // namespace

TEST(VcanPersistence, SaveKeepsAValueAcrossResetAndRestoreBringsTheDefaultBack) {
    CODRIVE_REQUIRE_VCAN("vcan0");
    Process sim({tool_path("codrive-sim"), "-i", "vcan0", "--node", "1:ds-bvs"});
    // Node 1, where the drive ships (§6.2.74): restoring all defaults also restores 5000h = 1.
    ASSERT_TRUE(sim.wait_for_output("ready", 10s)) << sim.output();
    const std::string codrive = tool_path("codrive");
    const std::string factory = window(codrive, "1");
    auto w = run(
        {codrive, "sdo", "write", "-i", "vcan0", "-n", "1", "0x6065:0", "--type", "u32", "777777"},
        30s);
    ASSERT_EQ(w.status, 0) << w.output;

    auto save = run({codrive, "save", "-i", "vcan0", "-n", "1"}, 30s);
    EXPECT_EQ(save.status, 0) << save.output;
    EXPECT_NE(save.output.find("node 1 (DS-BVS/BVM servo drive): saved all parameters "
                               "(1010h:01h)"),
              std::string::npos)
        << save.output;
    reset_node(codrive, "1");
    EXPECT_NE(window(codrive, "1").find("777777"), std::string::npos) << "saved value kept";

    auto restore = run({codrive, "restore", "-i", "vcan0", "-n", "1", "--what", "all"}, 30s);
    EXPECT_EQ(restore.status, 0) << restore.output;
    EXPECT_NE(restore.output.find("take effect at the next reset node or power-on"),
              std::string::npos)
        << restore.output;
    EXPECT_NE(window(codrive, "1").find("777777"), std::string::npos) << "not before the reset";
    reset_node(codrive, "1");
    EXPECT_EQ(window(codrive, "1"), factory) << "the default is back";

    auto bad = run({codrive, "save", "-i", "vcan0", "-n", "1", "--what", "comm"}, 30s);
    EXPECT_EQ(bad.status, 2) << bad.output;
    EXPECT_NE(bad.output.find("no parameter category 'comm' in 1010h (it has: all)"),
              std::string::npos)
        << bad.output;
    std::printf("%s%s%s", save.output.c_str(), restore.output.c_str(), bad.output.c_str());
}

TEST(VcanPersistence, DsBvsRestoreIsRefusedWhileThePowerStageIsOn) {
    CODRIVE_REQUIRE_VCAN("vcan0");
    Process sim({tool_path("codrive-sim"), "-i", "vcan0", "--node", "4:ds-bvs"});
    ASSERT_TRUE(sim.wait_for_output("ready", 10s)) << sim.output();
    const std::string codrive = tool_path("codrive");
    auto enable = run({codrive, "drive", "-i", "vcan0", "-n", "4", "enable"}, 30s);
    ASSERT_EQ(enable.status, 0) << enable.output;
    auto restore = run({codrive, "restore", "-i", "vcan0", "-n", "4"}, 30s);
    EXPECT_EQ(restore.status, 1) << restore.output;
    EXPECT_NE(restore.output.find("08000022"), std::string::npos) << restore.output;
    EXPECT_NE(restore.output.find("restores defaults only in NMT pre-operational with the power "
                                  "stage disabled"),
              std::string::npos)
        << restore.output;
    std::printf("%s", restore.output.c_str());
}

TEST(VcanCommission, DsBvsComesBackAtTheNewNodeIdAndTheBitRateIsRecorded) {
    // DS-BVS §6.2.74/§6.2.76: 5000h/5002h take effect after save and restart; vcan has no bit
    // rate, so the simulator records the new one and says so.
    CODRIVE_REQUIRE_VCAN("vcan0");
    Process sim({tool_path("codrive-sim"), "-i", "vcan0", "--node", "1:ds-bvs", "-v"});
    ASSERT_TRUE(sim.wait_for_output("ready", 10s)) << sim.output();
    const std::string codrive = tool_path("codrive");
    auto c =
        run({codrive, "commission", "-i", "vcan0", "-n", "1", "--node-id", "5", "--bitrate", "500"},
            60s);
    EXPECT_EQ(c.status, 0) << c.output;
    EXPECT_NE(c.output.find("node 1 (DS-BVS/BVM servo drive) is now node 5: boot-up seen at node "
                            "5, CAN bit rate 500 kbit/s (5002h = 6)"),
              std::string::npos)
        << c.output;
    auto id =
        run({codrive, "sdo", "read", "-i", "vcan0", "-n", "5", "0x5000:0", "--type", "u8"}, 30s);
    EXPECT_EQ(id.status, 0) << id.output;
    EXPECT_NE(id.output.find('5'), std::string::npos) << id.output;
    auto old = run(
        {codrive, "sdo", "read", "-i", "vcan0", "-n", "1", "0x5000:0", "--timeout", "300"}, 30s);
    EXPECT_NE(old.status, 0) << "nobody answers at node 1 any more: " << old.output;
    EXPECT_TRUE(sim.wait_for_output("CAN bit rate now 500 kbit/s", 5s)) << sim.output();
    auto bad =
        run({codrive, "commission", "-i", "vcan0", "-n", "5", "--node-id", "6", "--bitrate", "800"},
            30s);
    EXPECT_EQ(bad.status, 2) << bad.output;
    EXPECT_NE(bad.output.find("800 kbit/s is not supported"), std::string::npos) << bad.output;
    std::printf("%s%s", c.output.c_str(), bad.output.c_str());
}
