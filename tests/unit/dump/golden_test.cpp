// SPDX-License-Identifier: Apache-2.0
// Golden-output tests: hand-made traces in tests/data/traces decoded and compared with *.expected.
// Set CODRIVE_UPDATE_GOLDEN=1 to rewrite the expected files (then review the diff by hand).
#include "dump_test_util.hpp"

#include <gtest/gtest.h>

#include <cstdlib>
#include <fstream>
#include <sstream>

using namespace codrive;
using namespace codrive::dump;
using codrive::dump::testing::run_dump;
using codrive::dump::testing::trace_path;

namespace {

std::string read_file(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    std::stringstream ss;
    ss << in.rdbuf();
    return ss.str();
}

void expect_golden(const std::string& expected_name, const std::string& actual) {
    const auto path = trace_path(expected_name);
    const char* update = std::getenv("CODRIVE_UPDATE_GOLDEN");
    if (update != nullptr && std::string(update) == "1") {
        std::ofstream(path, std::ios::binary) << actual;
        GTEST_SKIP() << "rewrote " << path;
    }
    const auto expected = read_file(path);
    ASSERT_FALSE(expected.empty()) << path << " is missing (run with CODRIVE_UPDATE_GOLDEN=1)";
    if (expected != actual) {
        // Report the first differing line, which is what a reader needs.
        std::istringstream e(expected);
        std::istringstream a(actual);
        std::string el;
        std::string al;
        int line = 0;
        while (true) {
            ++line;
            const bool he = static_cast<bool>(std::getline(e, el));
            const bool ha = static_cast<bool>(std::getline(a, al));
            if (!he && !ha) {
                break;
            }
            if (el != al || he != ha) {
                FAIL() << expected_name << " line " << line << "\n expected: " << el
                       << "\n   actual: " << al;
            }
        }
        FAIL() << expected_name << " differs";
    }
}

} // namespace

TEST(DumpGolden, ServicesNmtHeartbeatGuardingSyncTimeEmcyLss) {
    expect_golden("services.expected", run_dump("services.log", {}));
}

TEST(DumpGolden, SdoExpeditedSegmentedAbortsAndTimeouts) {
    expect_golden("sdo.expected", run_dump("sdo.log", {}));
}

TEST(DumpGolden, SdoBlockTransfersReassembledWithCrcCheck) {
    expect_golden("sdo_block.expected", run_dump("sdo_block.log", {}));
}

TEST(DumpGolden, PdosDecodedWithMappingLearnedFromSdoTraffic) {
    expect_golden("pdo.expected", run_dump("pdo.log", {}));
}

TEST(DumpGolden, ScreenFormatsReadAndBadLinesReportedWithLineNumbers) {
    expect_golden("screen.expected", run_dump("screen.log", {}));
}

TEST(DumpGolden, EdsGivesNamesTypesAndDefaultPdoMapping) {
    DumpOptions o;
    o.line.time = TimeMode::Zero;
    expect_golden("eds.expected",
                  run_dump("eds.log", o, {{10, "eds/real/canopendemo-demodevice.eds"}}));
}

TEST(DumpGolden, FiltersByServiceAndNodeWithDeltaTimestamps) {
    DumpOptions o;
    o.line.time = TimeMode::Delta;
    std::string bad;
    o.only = *parse_service_list("nmt,hb", bad);
    o.nodes.set(4);
    expect_golden("services-filtered.expected", run_dump("services.log", o));
}

TEST(DumpGolden, JsonOnePerFrame) {
    DumpOptions o;
    o.line.json = true;
    std::string bad;
    o.only = *parse_service_list("sdo,pdo", bad);
    expect_golden("pdo.json.expected", run_dump("pdo.log", o));
}

TEST(DumpGolden, StatisticsTablePerNodeAndBusLoad) {
    DumpOptions o;
    o.print = false;
    o.stats = true;
    o.bitrate = 125000;
    expect_golden("stats.expected", run_dump("stats.log", o));
}

TEST(DumpGolden, EmcyVendorTextFromTheProfileMatchedByIdentity) {
    expect_golden("profile.expected", run_dump("profile.log", {}));
}

TEST(DumpGolden, PeakTrc21WithCanFdRemoteErrorStatusCounterAndEventLines) {
    expect_golden("formats/features-v21.expected", run_dump("formats/features-v21.trc", {}));
}

TEST(DumpGolden, VectorAscRelativeTimesCanFdChannelAndErrorFrame) {
    expect_golden("formats/features-asc.expected", run_dump("formats/features.asc", {}));
}

TEST(DumpGolden, CsvWithSemicolonsMillisecondsAndCanFd) {
    expect_golden("formats/features-csv.expected", run_dump("formats/features.csv", {}));
}
