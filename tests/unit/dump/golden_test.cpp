// SPDX-License-Identifier: Apache-2.0
// Golden-output tests: hand-made traces in tests/data/traces decoded and compared with *.expected.
// Set CODRIVE_UPDATE_GOLDEN=1 to rewrite the expected files (then review the diff by hand).
#include "blf_test_writer.hpp"
#include "dump_test_util.hpp"

#include <gtest/gtest.h>

#include <cstdlib>
#include <fstream>
#include <sstream>

using namespace codrive;
using namespace codrive::dump;
using codrive::dump::testing::run_dump;
using codrive::dump::testing::run_dump_bytes;
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

// A BLF file made by the test writer (BLF is binary: the sample is built here, not kept in the
// tree): every CAN object kind, header versions 1 and 2, an object the reader skips, one it
// cannot decode (reported, then reading goes on) and an error frame.
TEST(DumpGolden, VectorBlfObjectKindsSkippedAndBadObjectsAndErrorFrame) {
    using codrive::dump::testing::blf_event_object;
    using codrive::dump::testing::blf_file;
    using codrive::dump::testing::blf_object;
    using codrive::dump::testing::BlfEvent;
    using codrive::dump::testing::BlfWriteOptions;
    const std::int64_t t0 = 1'795'478'400'000'000'000LL;
    const auto ms = [&](std::int64_t n) { return t0 + n * 1'000'000; };
    Frame fd = Frame::make(0x284, {});
    fd.flags = Frame::kFd | Frame::kBrs;
    fd.len = 12;
    fd.data[0] = 0x27;
    Frame ext = Frame::make(0x18FF0001, {1, 2, 3});
    ext.flags = Frame::kExtended;
    const std::vector<BlfEvent> events = {
        {Frame::make(0x000, {0x01, 0x04}), ms(0), 1, BlfObjectType::CanMessage},
        {Frame::make(0x704, {0x05}), ms(10), 1, BlfObjectType::CanMessage2},
        {Frame::make(0x604, {0x40, 0x00, 0x10, 0x00, 0, 0, 0, 0}), ms(20), 1,
         BlfObjectType::CanFdMessage64},
        {Frame::make(0x584, {0x43, 0x00, 0x10, 0x00, 0x92, 0x01, 0x02, 0x00}), ms(21), 1,
         BlfObjectType::CanFdMessage},
        {Frame::make_rtr(0x705, 1), ms(30), 1, BlfObjectType::CanFdMessage64},
        {fd, ms(40), 2, BlfObjectType::CanFdMessage},
        {ext, ms(50), 1, BlfObjectType::CanMessage},
        {Frame{}, ms(60), 1, BlfObjectType::CanErrorExt},
    };
    BlfWriteOptions v1;
    BlfWriteOptions v2;
    v2.header_version = 2;
    std::string stream;
    for (std::size_t i = 0; i < events.size(); ++i) {
        stream += blf_event_object(events[i], t0, i % 2 == 0 ? v1 : v2);
        if (i == 2) {
            stream += blf_object(65, std::string(40, 't'), 0); // APP_TEXT: skipped
            std::string bad(16, '\0');
            bad[0] = 1;
            bad[5] = 0x08; // 11-bit id 0x800
            stream += blf_object(BlfObjectType::CanMessage, bad, 25'000'000);
        }
    }
    v1.container_bytes = 64;
    expect_golden("formats/features-blf.expected", run_dump_bytes(blf_file(t0, stream, v1), {}));
}
