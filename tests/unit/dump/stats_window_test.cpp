// SPDX-License-Identifier: Apache-2.0
// `--top` rates over the last second (not since the start), and a scan's silent ids in one line.
#include "dump_test_util.hpp"

#include <codrive/dump/stats.hpp>

#include <gtest/gtest.h>

#include <sstream>
#include <string>
#include <vector>

using namespace codrive;
using namespace codrive::dump;
using codrive::dump::testing::kMs;
using codrive::dump::testing::kStart;

namespace {

// The row of `node` in a stats table.
std::string row(const std::string& table, unsigned node) {
    const std::string head = (node < 10 ? "   " : "  ") + std::to_string(node) + "  ";
    const auto at = table.find("\n" + head);
    if (at == std::string::npos) {
        return {};
    }
    return table.substr(at + 1, table.find('\n', at + 1) - at - 1);
}

// The TPDO/s column of a row of a node without heartbeats:
// node, state, HB period, HB jitter, EMCY, SDO, ab/to, SDO mean, TPDO/s, RPDO/s.
std::string tpdo_rate(const std::string& r) {
    std::istringstream in(r);
    std::string token;
    for (int i = 0; i <= 8 && (in >> token); ++i) {
    }
    return token;
}

} // namespace

TEST(DumpStatsWindow, TopRatesFallToZeroOneSecondAfterThePdosStop) {
    Stats s;
    // Node 2: a TPDO every millisecond for 5 s, then nothing.
    for (std::int64_t t = 0; t < 5000; ++t) {
        s.on_frame(Frame::make(0x182, {1, 2}), kStart + t * kMs);
        s.on_pdo(2, true, kStart + t * kMs);
    }
    const std::string live = s.table(kStart + 4999 * kMs);
    EXPECT_EQ(tpdo_rate(row(live, 2)), "1000.0") << live;
    EXPECT_NE(live.find("PDO rates: last 1 s"), std::string::npos) << live;
    const std::string later = s.table(kStart + 6100 * kMs);
    EXPECT_EQ(tpdo_rate(row(later, 2)), "0.0") << later;
    // Without a clock (a file's end), the mean over the trace.
    const std::string file = s.table();
    EXPECT_EQ(tpdo_rate(row(file, 2)), "1000.2") << file;
    EXPECT_EQ(file.find("PDO rates: last 1 s"), std::string::npos) << file;
}

TEST(DumpStatsWindow, NodesThatNeverAnsweredAScanAreOneLineNotRows) {
    Stats s;
    s.on_heartbeat(3, 0x05, kStart);
    s.on_sdo_done(3, 2 * kMs);
    for (NodeId n = 1; n <= 127; ++n) {
        if (n != 3) {
            s.on_sdo_timeout(n);
        }
    }
    const std::string t = s.table();
    EXPECT_FALSE(row(t, 3).empty()) << t;
    EXPECT_TRUE(row(t, 1).empty()) << t;
    EXPECT_TRUE(row(t, 127).empty()) << t;
    EXPECT_NE(t.find("no answer to SDO requests from 126 nodes: 1..2, 4..127\n"), std::string::npos)
        << t;
}

TEST(DumpStatsWindow, WithoutTimestampsThereAreNoRatesNotCountsPerSecond) {
    // candump screen output without -t: 3 TPDOs of node 4 and no time at all.
    codrive::dump::DumpOptions o;
    o.print = false;
    o.stats = true;
    const auto out = codrive::dump::testing::run_dump_bytes("  can0  704   [1]  05\n"
                                                            "  can0  184   [2]  37 06\n"
                                                            "  can0  184   [2]  37 06\n"
                                                            "  can0  184   [2]  37 06\n",
                                                            o);
    EXPECT_NE(
        out.find("4 frames (0 error frames) without timestamps: no PDO rates and no bus load"),
        std::string::npos)
        << out;
    // The node row: TPDO/s and RPDO/s are "-", not the count 3.
    const auto row = out.substr(out.find("\n   4 "),
                                out.find('\n', out.find("\n   4 ") + 1) - out.find("\n   4 "));
    EXPECT_EQ(row.find(" 3"), std::string::npos) << row;
    EXPECT_NE(row.find("-         -"), std::string::npos) << row;
}

TEST(DumpStatsWindow, WithoutTimestampsAnSdoIsCountedButHasNoDuration) {
    // An SDO upload of 1000h from node 4 in candump screen output without -t: one transfer, and
    // no "0.0 ms" mean that nobody measured.
    codrive::dump::DumpOptions o;
    o.print = false;
    o.stats = true;
    const auto out =
        codrive::dump::testing::run_dump_bytes("  can0  604   [8]  40 00 10 00 00 00 00 00\n"
                                               "  can0  584   [8]  43 00 10 00 92 01 02 00\n",
                                               o);
    std::istringstream in(row(out, 4));
    std::vector<std::string> cols;
    for (std::string token; in >> token;) {
        cols.push_back(token);
    }
    ASSERT_GE(cols.size(), 8U) << out;
    EXPECT_EQ(cols[5], "1") << out; // SDO transfers
    EXPECT_EQ(cols[7], "-") << out; // SDO mean
    EXPECT_EQ(out.find("0.0 ms"), std::string::npos) << out;
}
