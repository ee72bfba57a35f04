// SPDX-License-Identifier: Apache-2.0
// codrive-sim as a real process on vcan: ready line, boot-up, heartbeat, SDO, EMCY, signals.
#include <codrive/sdo/blocking.hpp>
#include <codrive/testing/process.hpp>
#include <codrive/testing/vcan.hpp>
#include <codrive/testing/vcan_recorder.hpp>

#include <gtest/gtest.h>

#include <csignal>
#include <vector>

using namespace codrive;
using namespace std::chrono_literals;
using codrive::testing::Process;
using codrive::testing::tool_path;
using Recorder = codrive::testing::VcanRecorder;

namespace {

std::string sim_path() {
    auto p = tool_path("codrive-sim");
    return p;
}

} // namespace

TEST(SimVcan, TwoNodesBootAnswerSdoAndSendHeartbeats) {
    CODRIVE_REQUIRE_VCAN("vcan0");
    Recorder rec;
    Process sim({sim_path(), "-i", "vcan0", "--node", "5:akd2g", "--node", "6:ds-bvs",
                 "--heartbeat", "100"});
    ASSERT_TRUE(sim.wait_for_output("codrive-sim: node 6 ds-bvs (1 axis) ready on vcan0", 10s))
        << sim.output();
    EXPECT_NE(sim.output().find("codrive-sim: node 5 akd2g (2 axes) ready on vcan0"),
              std::string::npos);
    auto sdo = sdo::BlockingSdo::open("vcan0");
    ASSERT_TRUE(sdo) << sdo.error().message();
    auto vendor = (*sdo)->read<std::uint32_t>(5, 0x1018, 1);
    ASSERT_TRUE(vendor) << vendor.error().to_string();
    EXPECT_EQ(*vendor, 0x6AU);
    auto type = (*sdo)->read<std::uint32_t>(6, 0x1000, 0);
    ASSERT_TRUE(type) << type.error().to_string();
    EXPECT_EQ(*type, 0x00020192U);
    auto name = (*sdo)->read<std::string>(6, 0x1008, 0);
    ASSERT_TRUE(name) << name.error().to_string();
    EXPECT_EQ(*name, "DS-BVS");
    rec.drain(350ms);
    for (std::uint32_t id : {0x705U, 0x706U}) {
        const auto ec = rec.with_id(id);
        ASSERT_GE(ec.size(), 3U) << "boot-up and heartbeats on " << std::hex << id;
        EXPECT_EQ(ec[0].len, 1);
        EXPECT_EQ(ec[0].data[0], 0x00) << "boot-up first";
        EXPECT_EQ(ec[1].data[0], 0x7F) << "then pre-operational heartbeats";
    }
    sim.signal(SIGTERM);
    const auto status = sim.wait(5s);
    ASSERT_TRUE(status) << sim.output();
    EXPECT_EQ(*status, 0) << sim.output();
}

TEST(SimVcan, FaultInjectionThroughTheControlObjectSendsEmcy) {
    CODRIVE_REQUIRE_VCAN("vcan0");
    Recorder rec;
    Process sim({sim_path(), "-i", "vcan0", "--node", "7:akd2g"});
    ASSERT_TRUE(sim.wait_for_output("ready on vcan0", 10s)) << sim.output();
    auto sdo = sdo::BlockingSdo::open("vcan0");
    ASSERT_TRUE(sdo);
    ASSERT_TRUE((*sdo)->write<std::uint8_t>(7, 0x2FF1, 2, 1)); // over-current on axis 2
    // The AKD2G has no 603Fh (§5.6): AXIS2.FAULT1 (5104h:01, §5.3.84) names the fault.
    auto code = (*sdo)->read<std::uint16_t>(7, 0x5104, 1);
    ASSERT_TRUE(code);
    EXPECT_EQ(*code, 0xFF07);
    rec.drain();
    const auto emcy = rec.with_id(0x87);
    ASSERT_EQ(emcy.size(), 1U);
    EXPECT_EQ(emcy[0].data[0], 0x07);
    EXPECT_EQ(emcy[0].data[1], 0xFF);
    sim.signal(SIGINT);
    ASSERT_TRUE(sim.wait(5s));
}

TEST(SimVcan, CommandLineFaultAndSigusr2Reset) {
    CODRIVE_REQUIRE_VCAN("vcan0");
    Recorder rec;
    Process sim(
        {sim_path(), "-i", "vcan0", "--node", "8:ds-bvs", "--fault", "8:overcurrent@200ms"});
    ASSERT_TRUE(sim.wait_for_output("ready on vcan0", 10s)) << sim.output();
    ASSERT_TRUE(sim.wait_for_output("inject overcurrent", 5s)) << sim.output();
    rec.drain();
    auto emcy = rec.with_id(0x88);
    ASSERT_EQ(emcy.size(), 1U);
    EXPECT_EQ(emcy[0].data[0] | (emcy[0].data[1] << 8), 0x2310);
    sim.signal(SIGUSR2);
    ASSERT_TRUE(sim.wait_for_output("node 8: reset", 5s)) << sim.output();
    rec.drain();
    EXPECT_EQ(rec.with_id(0x708).size(), 2U) << "boot-up at start and after the reset";
    sim.signal(SIGTERM);
    const auto status = sim.wait(5s);
    ASSERT_TRUE(status);
    EXPECT_EQ(*status, 0);
}
