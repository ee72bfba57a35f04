// SPDX-License-Identifier: Apache-2.0
// codrive-dump on the trace formats engineers bring, as a user runs it: the commands that
// docs/codrive-dump.md shows (run as written, from a scratch directory), and every sample format
// converted with -w to pcap and pcapng that tshark reads and dissects as CANopen.
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

const std::string kSource = CODRIVE_SOURCE_DIR;

// A scratch directory with `tests` linked to the source tree's, so the documented relative
// paths work and written files land here.
class Scratch {
public:
    explicit Scratch(const std::string& name) {
        dir_ = std::filesystem::temp_directory_path() /
               ("codrive-dump-" + std::to_string(::getpid()) + "-" + name);
        std::filesystem::create_directories(dir_);
        std::filesystem::create_directory_symlink(kSource + "/tests", dir_ / "tests");
    }
    ~Scratch() {
        std::error_code ec;
        std::filesystem::remove_all(dir_, ec);
    }
    Scratch(const Scratch&) = delete;
    Scratch& operator=(const Scratch&) = delete;
    [[nodiscard]] std::string path() const { return dir_.string(); }

    // Runs a command line with the built tools first on PATH, in this directory.
    [[nodiscard]] ct::RunResult shell(const std::string& command) const {
        const auto tools = std::filesystem::path(ct::tool_path("codrive-dump")).parent_path();
        return ct::run({"/bin/sh", "-c",
                        "PATH='" + tools.string() + "':$PATH; cd '" + path() + "' && " + command},
                       60s);
    }

private:
    std::filesystem::path dir_;
};

// The fenced block after the marker comment in docs/codrive-dump.md, one command per line.
std::vector<std::string> documented_trace_commands() {
    std::ifstream in(kSource + "/docs/codrive-dump.md");
    std::string line;
    bool marked = false;
    bool inside = false;
    std::vector<std::string> commands;
    while (std::getline(in, line)) {
        if (line.find("run by tests/integration/dump_formats_host_test.cpp") != std::string::npos) {
            marked = true;
        } else if (marked && line.rfind("```", 0) == 0) {
            if (inside) {
                break;
            }
            inside = true;
        } else if (inside && !line.empty()) {
            commands.push_back(line);
        }
    }
    return commands;
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
    ASSERT_EQ(commands.size(), 6U) << "docs/codrive-dump.md lost its trace-file commands";
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
