// SPDX-License-Identifier: Apache-2.0
// The real tools on the host: `codrive run --check` on bad bus files, the one "cannot open"
// sentence (with the run-in-vcan hint where the kernel has no SocketCAN) from every CAN tool,
// and `codrive latency` measuring this machine's timer.
#include <codrive/core/socket_can_bus.hpp>
#include <codrive/testing/process.hpp>

#include <gtest/gtest.h>

#include <csignal>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>
#include <unistd.h>
#include <vector>

using namespace codrive;
using namespace std::chrono_literals;
namespace ct = codrive::testing;

namespace {

// A bus file in a fresh temporary directory, removed with the test.
class TempBusFile {
public:
    TempBusFile(const std::string& name, const std::string& text) {
        dir_ = std::filesystem::temp_directory_path() /
               ("codrive-cli-" + std::to_string(::getpid()) + "-" + name);
        std::filesystem::create_directories(dir_);
        path_ = (dir_ / name).string();
        std::ofstream(path_) << text;
    }
    ~TempBusFile() {
        std::error_code ec;
        std::filesystem::remove_all(dir_, ec);
    }
    TempBusFile(const TempBusFile&) = delete;
    TempBusFile& operator=(const TempBusFile&) = delete;
    [[nodiscard]] const std::string& path() const { return path_; }

private:
    std::filesystem::path dir_;
    std::string path_;
};

std::size_t count_of(const std::string& text, const std::string& what) {
    std::size_t n = 0;
    for (auto at = text.find(what); at != std::string::npos; at = text.find(what, at + 1)) {
        ++n;
    }
    return n;
}

// What a user must read when `iface` cannot be opened on this machine.
void expect_one_open_sentence(const ct::RunResult& r, const std::string& iface) {
    EXPECT_NE(r.status, 0) << r.output;
    EXPECT_EQ(count_of(r.output, "cannot open " + iface + ":"), 1U) << r.output;
    if (!socketcan_available()) {
        EXPECT_NE(r.output.find("no SocketCAN support"), std::string::npos) << r.output;
        EXPECT_NE(r.output.find("vcan-scripts/run-in-vcan.sh"), std::string::npos) << r.output;
        EXPECT_NE(r.output.find("docs/vcan.md"), std::string::npos) << r.output;
    } else {
        EXPECT_NE(r.output.find("no such network interface"), std::string::npos) << r.output;
        EXPECT_NE(r.output.find("ip link"), std::string::npos) << r.output;
    }
}

constexpr const char* kNoIface = "nocan9"; // exists nowhere

} // namespace

TEST(CliHost, RunCheckPrintsEveryFindingWithItsLineAndFails) {
    TempBusFile f("bad.yml", R"(bus: {interface: vcan0, sync_period_us: 1000}
nodes:
  - id: 1
    profile: akd2g
    writes:
      object: 0x6060:00
      type: i8
      value: 8
    axes:
      axis: 1
      mode: csp
  - id: 2
    profile: nosuchdrive
ethercat:
  interface: ecat0
  slaves:
    - {position: 0, profile: fio, name: [a]}
)");
    const auto r = ct::run({ct::tool_path("codrive"), "run", "--check", f.path()}, 20s);
    EXPECT_EQ(r.status, 2) << r.output;
    EXPECT_NE(r.output.find(f.path() + ":6: node 1 writes must be a list"), std::string::npos)
        << r.output;
    EXPECT_NE(r.output.find(f.path() + ":10: node 1 axes must be a list"), std::string::npos)
        << r.output;
    EXPECT_NE(r.output.find(f.path() + ":12: node 2: unknown profile `nosuchdrive`"),
              std::string::npos)
        << r.output;
    EXPECT_NE(r.output.find(f.path() + ":17: slave 0: `name` must be a single value"),
              std::string::npos)
        << r.output;
    EXPECT_NE(r.output.find("4 problems found"), std::string::npos) << r.output;
    EXPECT_EQ(r.output.find("invalid node"), std::string::npos) << r.output;
    // Validation only: no bus was opened, so no "cannot open" either.
    EXPECT_EQ(r.output.find("cannot open"), std::string::npos) << r.output;
}

TEST(CliHost, RunCheckAcceptsAGoodFileWithoutOpeningTheBus) {
    TempBusFile f("good.yml", R"(bus: {interface: nocan9, sync_period_us: 1000}
nodes:
  - id: 1
    profile: akd2g
    axes:
      - {axis: 1, mode: csp}
)");
    const auto r = ct::run({ct::tool_path("codrive"), "run", "--check", f.path()}, 20s);
    EXPECT_EQ(r.status, 0) << r.output;
    EXPECT_NE(r.output.find(f.path() + ": OK"), std::string::npos) << r.output;
}

TEST(CliHost, EveryCanToolSaysOnceWhyTheInterfaceCannotBeOpened) {
    const std::string codrive = ct::tool_path("codrive");
    expect_one_open_sentence(ct::run({codrive, "nmt", "-i", kNoIface, "start", "all"}, 20s),
                             kNoIface);
    expect_one_open_sentence(ct::run({codrive, "scan", "-i", kNoIface}, 20s), kNoIface);
    expect_one_open_sentence(
        ct::run({codrive, "sdo", "read", "-i", kNoIface, "-n", "1", "0x1000:00"}, 20s), kNoIface);
    expect_one_open_sentence(
        ct::run({ct::tool_path("codrive-sim"), "-i", kNoIface, "--node", "1:akd2g"}, 20s),
        kNoIface);
    expect_one_open_sentence(ct::run({ct::tool_path("codrive-dump"), kNoIface, "-n", "1"}, 20s),
                             kNoIface);
    TempBusFile f("run.yml", R"(bus: {interface: nocan9, sync_period_us: 1000}
nodes:
  - id: 1
    profile: akd2g
)");
    expect_one_open_sentence(ct::run({codrive, "run", "--duration", "1", f.path()}, 20s), kNoIface);
}

TEST(CliHost, SimulatorRefusesAFaultForANodeItDoesNotSimulateBeforeReady) {
    const auto r = ct::run(
        {ct::tool_path("codrive-sim"), "-i", kNoIface, "--node", "1:akd2g", "--fault", "3:sto"},
        20s);
    EXPECT_EQ(r.status, 2) << r.output;
    EXPECT_NE(r.output.find("--fault 3:sto names node 3, which is not simulated"),
              std::string::npos)
        << r.output;
    EXPECT_EQ(r.output.find("ready"), std::string::npos) << r.output;
    EXPECT_EQ(r.output.find("cannot open"), std::string::npos) << r.output;
}

TEST(CliHost, DumpQuietStatsPrintsOnlyTheTable) {
    const auto r = ct::run({ct::tool_path("codrive-dump"), "-q", "--stats", "-r",
                            std::string(CODRIVE_SOURCE_DIR) + "/tests/data/traces/stats.log"},
                           20s);
    EXPECT_EQ(r.status, 0) << r.output;
    EXPECT_EQ(r.output.rfind("node  NMT state", 0), 0U) << "the table comes first: " << r.output;
    EXPECT_NE(r.output.find("466 frames (0 error frames)"), std::string::npos) << r.output;
    EXPECT_EQ(r.output.find("SDO upload"), std::string::npos) << "no per-frame lines: " << r.output;
    EXPECT_EQ(r.output.find('\033'), std::string::npos) << "no escape codes into a pipe";
}

// The probe really sleeps: a quarter second at a 2 ms cycle is 125 slots, each either a
// wake-up or skipped by a late one (the last late one may skip past the end). Whether this
// machine is sound for that cycle is not for the test to say (exit 0 or 1), only that the
// figures and the verdict are there and agree with the exit status.
TEST(CliHost, LatencyMeasuresTheTimerAndGivesAVerdict) {
    const auto r = ct::run(
        {ct::tool_path("codrive"), "latency", "--cycle-us", "2000", "--seconds", "0.25"}, 30s);
    ASSERT_TRUE(r.status == 0 || r.status == 1) << r.output;
    EXPECT_NE(r.output.find(" wake-ups at a 2000 us cycle in "), std::string::npos) << r.output;
    const auto at = r.output.find("timer latency: ");
    ASSERT_NE(at, std::string::npos) << r.output;
    const unsigned long wakeups = std::stoul(r.output.substr(at + 15));
    const auto skipped_at = r.output.find(" or more (");
    ASSERT_NE(skipped_at, std::string::npos) << r.output;
    const unsigned long skipped = std::stoul(r.output.substr(skipped_at + 10));
    EXPECT_GE(wakeups, 1U) << r.output;
    EXPECT_LE(wakeups, 125U) << r.output;
    EXPECT_GE(wakeups + skipped, 125U) << r.output;
    EXPECT_NE(r.output.find("lateness: p50 "), std::string::npos) << r.output;
    if (r.status == 0) {
        EXPECT_EQ(r.output.find("verdict: not sound"), std::string::npos) << r.output;
    } else {
        EXPECT_NE(r.output.find("verdict: not sound for a 2000 us cycle"), std::string::npos)
            << r.output;
    }
}

// A long qualification run reports each window as it ends, then the worst one. Three windows
// of 0.1 s at a 2 ms cycle; whatever this machine's stalls, each window is there, in order.
TEST(CliHost, LatencyReportsEveryWindowAndTheWorst) {
    const auto r = ct::run({ct::tool_path("codrive"), "latency", "--cycle-us", "2000", "--seconds",
                            "0.3", "--window", "0.1"},
                           30s);
    ASSERT_TRUE(r.status == 0 || r.status == 1) << r.output;
    const auto first = r.output.find("window 1 (0.0-0.1 s): ");
    const auto third = r.output.find("window 3 (0.2-0.3 s): ");
    const auto summary = r.output.find("timer latency: ");
    ASSERT_NE(first, std::string::npos) << r.output;
    ASSERT_NE(third, std::string::npos) << r.output;
    EXPECT_LT(first, third);
    EXPECT_LT(third, summary) << "the windows come as they end, before the summary";
    EXPECT_EQ(r.output.find("window 4 "), std::string::npos) << r.output;
    EXPECT_NE(r.output.find("worst of 3 windows: window "), std::string::npos) << r.output;
    const auto refused =
        ct::run({ct::tool_path("codrive"), "latency", "--seconds", "0.5", "--window", "1"}, 30s);
    EXPECT_EQ(refused.status, 2) << refused.output;
    EXPECT_NE(refused.output.find("--window must be 0.1 s to --seconds (0.5), not 1"),
              std::string::npos)
        << refused.output;
}

// Ctrl-C ends an hour's qualification run at once, with the figures of what was measured.
TEST(CliHost, LatencyStopsOnSigintWithTheFiguresSoFar) {
    ct::Process p({ct::tool_path("codrive"), "latency", "--cycle-us", "2000", "--seconds", "3600",
                   "--window", "0.1"});
    ASSERT_TRUE(p.wait_for_output("window 2 (0.1-0.2 s): ", 10s)) << p.output();
    p.signal(SIGINT);
    const auto status = p.wait(5s);
    ASSERT_TRUE(status.has_value()) << "still measuring after SIGINT: " << p.output();
    EXPECT_TRUE(*status == 0 || *status == 1) << p.output();
    EXPECT_NE(p.output().find("codrive: SIGINT received: the figures cover the "),
              std::string::npos)
        << p.output();
    EXPECT_NE(p.output().find("timer latency: "), std::string::npos) << p.output();
    EXPECT_NE(p.output().find("verdict: "), std::string::npos) << p.output();
    EXPECT_EQ(p.output().find("(3599.9-3600.0 s)"), std::string::npos)
        << "windows never reached are not reported";
}

TEST(CliHost, LatencySaysWhichRealtimeSettingItCouldNotApply) {
    const auto r = ct::run({ct::tool_path("codrive"), "latency", "--cycle-us", "5000", "--seconds",
                            "0.05", "--cpu", "4096"},
                           30s);
    EXPECT_TRUE(r.status == 0 || r.status == 1) << r.output;
    EXPECT_NE(r.output.find("codrive: warning: cannot pin to CPU 4096: this machine has "),
              std::string::npos)
        << r.output;
    EXPECT_NE(r.output.find("verdict: "), std::string::npos) << r.output;
}

TEST(CliHost, LatencyRefusesACycleItCannotJudge) {
    const auto r =
        ct::run({ct::tool_path("codrive"), "latency", "--cycle-us", "10", "--seconds", "1"}, 30s);
    EXPECT_EQ(r.status, 2) << r.output;
    EXPECT_NE(r.output.find("--cycle-us must be 50..1000000, not 10"), std::string::npos)
        << r.output;
    const auto nan = ct::run({ct::tool_path("codrive"), "latency", "--seconds", "nan"}, 30s);
    EXPECT_EQ(nan.status, 2) << nan.output;
    EXPECT_NE(nan.output.find("--seconds must be above 0 and at most 3600, not nan"),
              std::string::npos)
        << nan.output;
}
