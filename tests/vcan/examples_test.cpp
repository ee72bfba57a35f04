// SPDX-License-Identifier: Apache-2.0
// The example programs, run against a simulated AKD2G in another process on vcan.
#include <codrive/testing/process.hpp>
#include <codrive/testing/vcan.hpp>

#include <gtest/gtest.h>

using namespace std::chrono_literals;
using codrive::testing::example_path;
using codrive::testing::Process;
using codrive::testing::run;
using codrive::testing::tool_path;

namespace {

std::string bus_file() {
    return std::string(CODRIVE_SOURCE_DIR) + "/tests/data/bus/akd2g-csp.yml";
}

struct SimulatedAkd2g {
    Process sim{{tool_path("codrive-sim"), "-i", "vcan0", "--node", "1:akd2g"}};
    SimulatedAkd2g() { EXPECT_TRUE(sim.wait_for_output("ready", 10s)) << sim.output(); }
};

} // namespace

TEST(VcanExamples, MinimalAxisEnablesAndMoves) {
    CODRIVE_REQUIRE_VCAN("vcan0");
    SimulatedAkd2g drive;
    auto r = run({example_path("minimal_axis"), bus_file(), "1", "50000"}, 60s);
    EXPECT_EQ(r.status, 0) << r.output;
    EXPECT_NE(r.output.find("moved from 0 to 50000"), std::string::npos) << r.output;
}

TEST(VcanExamples, CspCoordinatedTracesASquare) {
    CODRIVE_REQUIRE_VCAN("vcan0");
    SimulatedAkd2g drive;
    auto r = run({example_path("csp_coordinated"), bus_file(), "100000"}, 90s);
    EXPECT_EQ(r.status, 0) << r.output;
    EXPECT_NE(r.output.find("corner (0, 0) reached"), std::string::npos) << r.output;
    std::printf("%s", r.output.c_str());
}

TEST(VcanExamples, DiagnosticsReportsNodesAndStatistics) {
    CODRIVE_REQUIRE_VCAN("vcan0");
    SimulatedAkd2g drive;
    auto r = run({example_path("diagnostics"), bus_file(), "1"}, 60s);
    EXPECT_EQ(r.status, 0) << r.output;
    EXPECT_NE(r.output.find("node   1  operational"), std::string::npos) << r.output;
    EXPECT_NE(r.output.find("== statistics"), std::string::npos) << r.output;
}
