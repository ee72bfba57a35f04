// SPDX-License-Identifier: Apache-2.0
// codrive-dump capturing live on vcan while other processes talk: decoded stream, filters, pcap.
#include <codrive/testing/process.hpp>
#include <codrive/testing/vcan.hpp>

#include <gtest/gtest.h>

#include <cstdio>
#include <fstream>
#include <sstream>
#include <string>

using namespace std::chrono_literals;
using codrive::testing::Process;
using codrive::testing::run;
using codrive::testing::tool_path;

namespace {

void send(const std::vector<std::string>& frames) {
    std::vector<std::string> argv{tool_path("codrive"), "bus", "send", "-i", "vcan0"};
    argv.insert(argv.end(), frames.begin(), frames.end());
    const auto r = run(argv, 10s);
    ASSERT_EQ(r.status, 0) << r.output;
}

} // namespace

TEST(VcanDump, DecodesSegmentedUploadHeartbeatAndPdosLive) {
    CODRIVE_REQUIRE_VCAN("vcan0");
    Process dump({tool_path("codrive-dump"), "vcan0", "--color", "never", "-n", "12", "--stats"});
    ASSERT_TRUE(dump.wait_for_output("listening on vcan0", 10s)) << dump.output();
    send({"704#05", "604#4008100000000000", "584#410810000C000000", "604#6000000000000000",
          "584#00414B4432472D53", "604#7000000000000000", "584#152D4455414C0000",
          "604#2F001A0001000000", "584#60001A0000000000", "604#23001A0110004160",
          "584#60001A0100000000", "184#3706"});
    const auto status = dump.wait(10s);
    ASSERT_TRUE(status) << "codrive-dump did not stop after 12 frames: " << dump.output();
    EXPECT_EQ(*status, 0) << dump.output();
    const auto out = dump.output();
    EXPECT_NE(out.find("vcan0  704   [1]  05"), std::string::npos) << out;
    EXPECT_NE(out.find("node 4 heartbeat operational"), std::string::npos) << out;
    EXPECT_NE(out.find("node 4 upload 1008:00 Manufacturer device name = \"AKD2G-S-DUAL\" "
                       "(12 bytes, segmented,"),
              std::string::npos)
        << out;
    // The mapping was configured a few frames earlier (count first, then the entry: the
    // decoder uses what it has seen).
    EXPECT_NE(out.find("node 4 TPDO1 Statusword=0x0637 (OPERATION ENABLED"), std::string::npos)
        << out;
    EXPECT_NE(out.find("   4  operational"), std::string::npos) << out;
    std::printf("%s", out.c_str());
}

TEST(VcanDump, FollowsARealSdoClientAndServer) {
    CODRIVE_REQUIRE_VCAN("vcan0");
    Process server({tool_path("codrive"), "sdo", "serve", "-i", "vcan0", "-n", "5"});
    ASSERT_TRUE(server.wait_for_output("ready", 10s)) << server.output();
    Process dump({tool_path("codrive-dump"), "vcan0,0x580:0x780,0x600:0x780", "--color", "never",
                  "--only", "sdo", "-t", "z"});
    ASSERT_TRUE(dump.wait_for_output("listening on vcan0", 10s)) << dump.output();
    auto r = run({tool_path("codrive"), "sdo", "read", "-i", "vcan0", "-n", "5", "0x1008:0"}, 10s);
    EXPECT_EQ(r.status, 0) << r.output;
    r = run({tool_path("codrive"), "sdo", "read", "-i", "vcan0", "-n", "5", "0x1008:0", "--block"},
            10s);
    EXPECT_EQ(r.status, 0) << r.output;
    r = run({tool_path("codrive"), "sdo", "read", "-i", "vcan0", "-n", "5", "0x6502:0"}, 10s);
    EXPECT_NE(r.status, 0) << r.output; // the built-in dictionary has no 6502h: an abort
    ASSERT_TRUE(dump.wait_for_output("0x06020000", 5s)) << dump.output();
    dump.signal(2);
    ASSERT_TRUE(dump.wait(5s)) << dump.output();
    const auto out = dump.output();
    EXPECT_NE(out.find("node 5 upload 1008:00 Manufacturer device name = \"codrive sdo serve\" "
                       "(17 bytes, segmented"),
              std::string::npos)
        << out;
    EXPECT_NE(out.find("node 5 upload 1008:00 Manufacturer device name = \"codrive sdo serve\" "
                       "(17 bytes, block"),
              std::string::npos)
        << out;
    EXPECT_NE(out.find("node 5 SDO abort upload 6502:00 Supported drive modes: 0x06020000"),
              std::string::npos)
        << out;
    std::printf("%s", out.c_str());
    server.signal();
    (void)server.wait(5s);
}

TEST(VcanDump, WritesAPcapThatReadsBackTheSame) {
    CODRIVE_REQUIRE_VCAN("vcan0");
    const std::string pcap = ::testing::TempDir() + "/vcan_dump.pcap";
    Process dump({tool_path("codrive-dump"), "vcan0", "-w", pcap, "-n", "3"});
    ASSERT_TRUE(dump.wait_for_output("listening on vcan0", 10s)) << dump.output();
    send({"000#0104", "080#", "084#1023030001020304"});
    ASSERT_TRUE(dump.wait(10s)) << dump.output();
    const auto r = run({tool_path("codrive-dump"), "-r", pcap, "-t", "n", "--color", "never"}, 10s);
    EXPECT_EQ(r.status, 0) << r.output;
    EXPECT_NE(r.output.find("NMT start node 4"), std::string::npos) << r.output;
    EXPECT_NE(r.output.find("SYNC"), std::string::npos) << r.output;
    EXPECT_NE(r.output.find("node 4: EMCY 0x2310 continuous over-current"), std::string::npos)
        << r.output;
}

TEST(VcanDump, WritesTheHtmlReportOfALiveCapture) {
    CODRIVE_REQUIRE_VCAN("vcan0");
    const std::string html = ::testing::TempDir() + "/vcan_dump_report.html";
    Process dump({tool_path("codrive-dump"), "vcan0", "-q", "-n", "7", "--report", html});
    ASSERT_TRUE(dump.wait_for_output("listening on vcan0", 10s)) << dump.output();
    send({"704#05", "080#", "184#3706", "080#", "184#3706", "704#05", "084#1023030001020304"});
    const auto status = dump.wait(10s);
    ASSERT_TRUE(status) << "codrive-dump did not stop after 7 frames: " << dump.output();
    EXPECT_EQ(*status, 0) << dump.output();
    EXPECT_NE(dump.output().find("report written to " + html), std::string::npos) << dump.output();
    std::ifstream in(html);
    std::stringstream page;
    page << in.rdbuf();
    const auto p = page.str();
    // The page's data: the interface as the source, the frames, node 4 with its heartbeat state,
    // two SYNCs, a TPDO after each, the EMCY as an event with its decoded text.
    EXPECT_NE(p.find("\"source\":\"vcan0\""), std::string::npos);
    EXPECT_NE(p.find("\"frames\":7,"), std::string::npos);
    EXPECT_NE(p.find("\"id\":4,\"state\":\"operational\""), std::string::npos);
    EXPECT_NE(p.find("\"sync\":{\"n\":1,"), std::string::npos);
    EXPECT_NE(p.find("\"tpdo\":2,"), std::string::npos);
    EXPECT_NE(p.find("EMCY 0x2310 continuous over-current"), std::string::npos);
    EXPECT_NE(p.find("uPlot"), std::string::npos);
}
