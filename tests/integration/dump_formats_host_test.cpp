// SPDX-License-Identifier: Apache-2.0
// codrive-dump on the trace formats engineers bring, as a user runs it: the commands that
// docs/codrive-dump.md shows (run as written, from a scratch directory), and every sample format
// converted with -w to pcap and pcapng that tshark reads and dissects as CANopen.
#include "dump_scratch.hpp"

#include <codrive/testing/process.hpp>

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>
#include <unistd.h>
#include <vector>

using namespace std::chrono_literals;
namespace ct = codrive::testing;

namespace {

using ct::dump::kSource;
using ct::dump::Scratch;

std::vector<std::string> documented_trace_commands() {
    return ct::dump::documented_commands("tests/integration/dump_formats_host_test.cpp");
}

std::size_t lines_of(const std::string& s) {
    std::size_t n = 0;
    for (char c : s) {
        n += c == '\n' ? 1 : 0;
    }
    return n;
}

} // namespace

TEST(DumpFormatsHost, DocumentedTraceCommandsRunAsWritten) {
    const auto commands = documented_trace_commands();
    ASSERT_EQ(commands.size(), 7U) << "docs/codrive-dump.md lost its trace-file commands";
    Scratch scratch("docs");
    std::vector<ct::RunResult> results;
    for (const auto& c : commands) {
        results.push_back(scratch.shell(c + " 2>&1"));
        EXPECT_EQ(results.back().status, 0) << c << "\n" << results.back().output;
    }
    // A PEAK 2.1 trace decoded, with its absolute start time.
    EXPECT_NE(results[0].output.find("(1795478400.021000)  pcan1  584"), std::string::npos)
        << results[0].output;
    EXPECT_NE(results[0].output.find("node 4 upload 1000:00 Device type = 0x00020192"),
              std::string::npos)
        << results[0].output;
    // The ASC file converted: tshark dissects all 12 frames, CANopen where they are CANopen.
    EXPECT_TRUE(std::filesystem::exists(scratch.path() + "/conversation.pcapng"));
    const auto& tshark = results[2].output;
    EXPECT_NE(tshark.find("NMT Error Control: Boot-up"), std::string::npos) << tshark;
    EXPECT_NE(tshark.find("Initiate upload response"), std::string::npos) << tshark;
    EXPECT_NE(tshark.find("0x18ff0001"), std::string::npos) << tshark;
    // The pcapng read back: the SDO exchange, timestamps from zero, the ASC channel's name.
    // (-t z counts from the first line printed.)
    EXPECT_NE(results[3].output.find("(000.001000)  can1   584"), std::string::npos)
        << results[3].output;
    EXPECT_EQ(lines_of(results[3].output), 2U) << results[3].output;
    EXPECT_TRUE(std::filesystem::exists(scratch.path() + "/conversation.pcap"));
    // The BLF sample (zlib containers): the SDO exchange on BLF channel 1, absolute times.
    EXPECT_NE(results[5].output.find("(1795478400.021000)  can1   584"), std::string::npos)
        << results[5].output;
    EXPECT_NE(results[5].output.find("node 4 upload 1000:00 Device type = 0x00020192"),
              std::string::npos)
        << results[5].output;
    EXPECT_EQ(lines_of(results[5].output), 2U) << results[5].output;
    // The ASC sample gzip-compressed: read as it is, the same SDO exchange.
    EXPECT_NE(results[6].output.find("(1795478400.021000)  can1   584"), std::string::npos)
        << results[6].output;
    EXPECT_EQ(lines_of(results[6].output), 2U) << results[6].output;
}

TEST(DumpFormatsHost, EveryFormatConvertsToCapturesTsharkReads) {
    Scratch scratch("tshark");
    const std::vector<std::string> samples = {
        "conversation.log",          "conversation-screen.txt", "conversation-screen-delta.txt",
        "conversation-v11.trc",      "conversation-v13.trc",    "conversation-v20.trc",
        "conversation-v21.trc",      "conversation.asc",        "conversation-python-can.csv",
        "conversation-savvycan.csv", "conversation.blf",        "conversation-ixxat.csv"};
    for (const auto& sample : samples) {
        // pcapng for every format; classic pcap (the same records) for two, tshark is slow.
        const bool also_pcap = sample == "conversation-v21.trc" || sample == "conversation.asc";
        for (const std::string ext : {".pcapng", ".pcap"}) {
            if (ext == ".pcap" && !also_pcap) {
                continue;
            }
            const auto out = sample + ext;
            const auto w = scratch.shell("codrive-dump -r tests/data/traces/formats/" + sample +
                                         " -w " + out + " 2>&1");
            ASSERT_EQ(w.status, 0) << sample << ": " << w.output;
            EXPECT_EQ(w.output, "") << "nothing printed with -w alone";
            // One line per frame, the id of each; -d makes tshark decode CANopen.
            const auto t = scratch.shell("tshark -r " + out +
                                         " -d can.subdissector,canopen -T fields -e can.id "
                                         "-e canopen.nmt_ctrl.node_id 2>/dev/null");
            ASSERT_EQ(t.status, 0) << out << ": " << t.output;
            const std::size_t frames =
                sample == "conversation-savvycan.csv" || sample == "conversation-ixxat.csv" ? 11
                                                                                            : 12;
            EXPECT_EQ(lines_of(t.output), frames) << out << ":\n" << t.output;
            EXPECT_NE(t.output.find("419364865"), std::string::npos) << "the 29-bit id 18FF0001";
            EXPECT_NE(t.output.find("1412"), std::string::npos) << "the SDO response 584h";
        }
    }
}
