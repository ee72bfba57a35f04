// SPDX-License-Identifier: Apache-2.0
// Boot-up of nodes that were not freshly reset (issue 19): the same bus file booted twice against
// one simulator, and a boot after `codrive nmt start all`, with real processes on vcan.
#include <codrive/testing/process.hpp>
#include <codrive/testing/vcan.hpp>

#include <gtest/gtest.h>

#include <cstdio>
#include <fstream>
#include <sstream>

using namespace std::chrono_literals;
using codrive::testing::Process;
using codrive::testing::run;
using codrive::testing::RunResult;
using codrive::testing::tool_path;

namespace {

const std::string kDemoBus = std::string(CODRIVE_SOURCE_DIR) + "/vcan-scripts/demo-bus.yml";

std::unique_ptr<Process> start_sim() {
    auto sim = std::make_unique<Process>(std::vector<std::string>{
        tool_path("codrive-sim"), "-i", "vcan0", "--node", "1:akd2g", "--node", "2:ds-bvs"});
    // The User-Mode-Linux guest has one CPU: a UBSan simulator may take a while to come up.
    EXPECT_TRUE(sim->wait_for_output("node 2", 30s)) << sim->output();
    return sim;
}

RunResult run_bus(const std::string& file) {
    return run({tool_path("codrive"), "run", file, "--duration", "2", "--enable"}, 120s);
}

std::size_t count(const std::string& text, const std::string& what) {
    std::size_t n = 0;
    for (auto p = text.find(what); p != std::string::npos; p = text.find(what, p + 1)) {
        ++n;
    }
    return n;
}

/// A run that booted both nodes, enabled every axis and showed them enabled in the status
/// table, whose state comes from the TPDOs (statusword mapped by the boot-up's PDO layout).
void expect_booted_and_pdos_work(const RunResult& r) {
    EXPECT_EQ(r.status, 0) << r.output;
    EXPECT_NE(r.output.find("node 1 (gantry): boot-up OK"), std::string::npos) << r.output;
    EXPECT_NE(r.output.find("node 2 (spindle): boot-up OK"), std::string::npos) << r.output;
    EXPECT_EQ(r.output.find("aborted"), std::string::npos) << r.output;
    EXPECT_NE(r.output.find("node 2 axis 1 (spindle): enabled"), std::string::npos) << r.output;
    EXPECT_NE(r.output.find("node 1 axis 2 (gantry): enabled"), std::string::npos) << r.output;
    EXPECT_GE(count(r.output, "OPERATION ENABLED"), 3U) << "TPDO statuswords: " << r.output;
}

} // namespace

TEST(VcanBootState, SameBusFileBootsTwiceAgainstOneSimulator) {
    CODRIVE_REQUIRE_VCAN("vcan0");
    auto sim = start_sim();
    const RunResult first = run_bus(kDemoBus);
    expect_booted_and_pdos_work(first);
    const RunResult second = run_bus(kDemoBus);
    expect_booted_and_pdos_work(second);
    // The second boot found the nodes as the first run left them and stated what it did.
    EXPECT_NE(second.output.find("NMT enter pre-operational"), std::string::npos) << second.output;
    std::printf("%s", second.output.c_str());
}

TEST(VcanBootState, BootAfterNmtStartAllSucceeds) {
    CODRIVE_REQUIRE_VCAN("vcan0");
    auto sim = start_sim();
    const auto start = run({tool_path("codrive"), "nmt", "-i", "vcan0", "start", "all"}, 120s);
    ASSERT_EQ(start.status, 0) << start.output;
    const RunResult r = run_bus(kDemoBus);
    expect_booted_and_pdos_work(r);
    EXPECT_EQ(count(r.output, "pre-operational check"), 2U) << r.output;
    std::printf("%s", r.output.c_str());
}

TEST(VcanBootState, ResetCommunicationOptionBootsOperationalNodes) {
    CODRIVE_REQUIRE_VCAN("vcan0");
    auto sim = start_sim();
    std::ifstream in(kDemoBus);
    std::stringstream text;
    text << in.rdbuf();
    std::string yaml = text.str();
    const std::string anchor = "  sync_period_us: 4000\n";
    const auto at = yaml.find(anchor);
    ASSERT_NE(at, std::string::npos) << yaml;
    // A margin for the slow guest: the simulator re-initialises after each reset.
    yaml.insert(at + anchor.size(), "  boot_reset: communication\n  sdo_timeout_ms: 2000\n");
    const std::string file = "/tmp/codrive-boot-reset-bus.yml";
    std::ofstream(file) << yaml;
    const RunResult first = run_bus(file);
    expect_booted_and_pdos_work(first);
    ASSERT_EQ(run({tool_path("codrive"), "nmt", "-i", "vcan0", "start", "all"}, 120s).status, 0);
    const RunResult second = run_bus(file);
    expect_booted_and_pdos_work(second);
    EXPECT_EQ(count(second.output, "NMT reset communication"), 2U) << second.output;
    EXPECT_NE(second.output.find("boot-up message after"), std::string::npos) << second.output;
    std::printf("%s", second.output.c_str());
}
