// SPDX-License-Identifier: Apache-2.0
// `codrive drive` and `codrive run` against simulated drives in another process on vcan.
#include <codrive/testing/process.hpp>
#include <codrive/testing/vcan.hpp>

#include <gtest/gtest.h>

using namespace std::chrono_literals;
using codrive::testing::Process;
using codrive::testing::run;
using codrive::testing::tool_path;

TEST(VcanCli, DriveCommandEnablesMovesAndResets) {
    CODRIVE_REQUIRE_VCAN("vcan0");
    Process sim({tool_path("codrive-sim"), "-i", "vcan0", "--node", "4:akd2g"});
    ASSERT_TRUE(sim.wait_for_output("ready", 10s)) << sim.output();
    const std::string codrive = tool_path("codrive");
    auto status = run({codrive, "drive", "-i", "vcan0", "-n", "4", "status"}, 30s);
    EXPECT_EQ(status.status, 0) << status.output;
    EXPECT_NE(status.output.find("SWITCH ON DISABLED"), std::string::npos) << status.output;
    auto enable = run({codrive, "drive", "-i", "vcan0", "-n", "4", "enable"}, 30s);
    EXPECT_EQ(enable.status, 0) << enable.output;
    EXPECT_NE(enable.output.find("OPERATION ENABLED"), std::string::npos) << enable.output;
    auto move = run({codrive, "drive", "-i", "vcan0", "-n", "4", "move", "--pp", "20000"}, 60s);
    EXPECT_EQ(move.status, 0) << move.output;
    EXPECT_NE(move.output.find("position 20000"), std::string::npos) << move.output;
    auto bad = run({codrive, "drive", "-i", "vcan0", "-n", "9", "status", "--timeout", "500"}, 30s);
    EXPECT_NE(bad.status, 0);
    EXPECT_NE(bad.output.find("node 9"), std::string::npos) << bad.output;
    std::printf("%s%s%s", status.output.c_str(), enable.output.c_str(), move.output.c_str());
}

TEST(VcanCli, DriveStatusSaysWhatToDoAtRestAndNamesTheAkd2gFault) {
    CODRIVE_REQUIRE_VCAN("vcan0");
    // Node 5 faults at once (following error, EMCY 8611h): the AKD2G has no 603Fh, so the code
    // must come from its error history 1003h:01 (manual §5.2.3).
    Process sim({tool_path("codrive-sim"), "-i", "vcan0", "--node", "4:akd2g", "--node", "5:akd2g",
                 "--fault", "5:ferr"});
    ASSERT_TRUE(sim.wait_for_output("inject", 10s)) << sim.output();
    const std::string codrive = tool_path("codrive");
    auto rest = run({codrive, "drive", "-i", "vcan0", "-n", "4", "status"}, 30s);
    EXPECT_EQ(rest.status, 0) << rest.output;
    EXPECT_NE(rest.output.find("SWITCH ON DISABLED: power stage off, ready to be enabled; "
                               "`codrive drive -i vcan0 -n 4 enable` enables it"),
              std::string::npos)
        << rest.output;
    EXPECT_EQ(rest.output.find("did not follow"), std::string::npos) << rest.output;
    auto fault = run({codrive, "drive", "-i", "vcan0", "-n", "5", "status"}, 30s);
    EXPECT_NE(fault.output.find("the drive is in FAULT: error code 0x8611 (F"), std::string::npos)
        << fault.output;
    EXPECT_NE(fault.output.find("`codrive drive -i vcan0 -n 5 reset` clears the fault"),
              std::string::npos)
        << fault.output;
    std::printf("%s%s", rest.output.c_str(), fault.output.c_str());
}

TEST(VcanCli, RunCommandBootsTheBusFileAndShowsAxes) {
    CODRIVE_REQUIRE_VCAN("vcan0");
    Process sim(
        {tool_path("codrive-sim"), "-i", "vcan0", "--node", "1:akd2g", "--node", "2:ds-bvs"});
    ASSERT_TRUE(sim.wait_for_output("node 2", 10s)) << sim.output();
    auto r = run({tool_path("codrive"), "run",
                  std::string(CODRIVE_SOURCE_DIR) + "/vcan-scripts/demo-bus.yml", "--duration", "2",
                  "--enable"},
                 60s);
    EXPECT_EQ(r.status, 0) << r.output;
    EXPECT_NE(r.output.find("node 1 (gantry): boot-up OK"), std::string::npos) << r.output;
    EXPECT_NE(r.output.find("node 1 axis 2 (gantry): enabled"), std::string::npos) << r.output;
    EXPECT_NE(r.output.find("OPERATION ENABLED"), std::string::npos) << r.output;
    EXPECT_NE(r.output.find("SWITCH ON DISABLED"), std::string::npos)
        << "after the run the axes were disabled: " << r.output;
}

TEST(VcanCli, BusFileMistakesAreReportedWithLines) {
    const std::string bad = "/tmp/codrive-bad-bus.yml";
    FILE* f = std::fopen(bad.c_str(), "w");
    ASSERT_NE(f, nullptr);
    std::fputs("bus:\n  interface: vcan0\nnodes:\n  - id: 1\n    profile: akd2g\n    pdos:\n"
               "      tpdo1: {map: [0x607A:00]}\n",
               f);
    std::fclose(f);
    auto r = run({tool_path("codrive"), "run", bad}, 30s);
    EXPECT_EQ(r.status, 2) << r.output;
    EXPECT_NE(r.output.find("codrive-bad-bus.yml:7: node 1 maps 0x607A:00 (INTEGER32) into "
                            "TPDO1 but it is only RPDO-mappable"),
              std::string::npos)
        << r.output;
}
