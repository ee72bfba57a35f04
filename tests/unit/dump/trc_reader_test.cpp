// SPDX-License-Identifier: Apache-2.0
// PEAK .trc reader: the column layouts of 1.0-2.1, CAN FD types, remote frames, error and status
// lines, start time, malformed lines.
#include "dump_test_util.hpp"

#include <codrive/core/socket_can_bus.hpp>

#include <gtest/gtest.h>

using namespace codrive;
using namespace codrive::dump;
using codrive::dump::testing::frames_of;
using codrive::dump::testing::read_trace;
using codrive::dump::testing::run_dump_bytes;

namespace {
// 2026-11-24 00:00:00 UTC: STARTTIME 46350 (days since 1899-12-30).
constexpr std::int64_t kTrcStart = 1'795'478'400'000'000'000LL;
} // namespace

TEST(DumpTrc, Version11ColumnsRtrAndStartTime) {
    const auto items = read_trace(";$FILEVERSION=1.1\n"
                                  ";$STARTTIME=46350.5\n"
                                  ";   Start time: 24.11.2026 12:00:00.000.0\n"
                                  "     1)      1841.5  Rx         0181  2  37 06\n"
                                  "     2)      1842.0  Tx     18FF0001  1  AA\n"
                                  "     3)      1843.0  Rx         0705  1  RTR\n");
    ASSERT_EQ(items.size(), 3U);
    EXPECT_EQ(items[0].frame, Frame::make(0x181, {0x37, 0x06}));
    EXPECT_EQ(items[0].ts_ns, kTrcStart + 43'200'000'000'000LL + 1'841'500'000LL);
    EXPECT_TRUE(items[0].has_ts);
    EXPECT_EQ(items[0].iface, "pcan");
    EXPECT_TRUE(items[1].frame.extended());
    EXPECT_EQ(items[1].frame.id, 0x18FF0001U);
    EXPECT_EQ(items[2].frame, Frame::make_rtr(0x705, 1));
}

TEST(DumpTrc, Version10WithoutHeaderKeepsErrorFramesAndWarnings) {
    TraceFormat format{};
    const auto items = read_trace(";##########\n"
                                  ";   Start time: 11.09.2002 16:00:20.682\n"
                                  "1) 1841 0001 8 00 00 00 00 00 00 00 00\n"
                                  "2) 1842 0001 4 ERROR 00 19 08 08\n"
                                  "3) 1843 FFFFFFFF 4 00 00 00 04 ------BUSLIGHT\n"
                                  "4) 1844 0100 3 RTR\n",
                                  &format);
    EXPECT_EQ(format, TraceFormat::PeakTrc);
    ASSERT_EQ(items.size(), 4U);
    EXPECT_EQ(items[0].frame.id, 1U);
    EXPECT_FALSE(items[0].has_ts && items[0].ts_ns > 10'000'000'000LL) << "no STARTTIME: relative";
    ASSERT_TRUE(items[1].frame.error());
    const auto bit = to_string(decode_error_frame(items[1].frame).at(0));
    EXPECT_NE(bit.find("bit error on transmission"), std::string::npos) << bit;
    EXPECT_NE(bit.find("tx errors 8, rx errors 8"), std::string::npos) << bit;
    ASSERT_TRUE(items[2].frame.error());
    EXPECT_EQ(to_string(decode_error_frame(items[2].frame).at(0)), "bus state error-warning");
    EXPECT_EQ(items[3].frame, Frame::make_rtr(0x100, 3));
}

TEST(DumpTrc, Version13HasBusAndReservedColumns) {
    const auto items = read_trace(";$FILEVERSION=1.3\n"
                                  ";$STARTTIME=46350\n"
                                  "     1)      1841.0 2  Rx         0581 -  8    43 00 10 00 92 "
                                  "01 02 00\n");
    ASSERT_EQ(items.size(), 1U);
    EXPECT_EQ(items[0].frame, Frame::make(0x581, {0x43, 0, 0x10, 0, 0x92, 1, 2, 0}));
    EXPECT_EQ(items[0].iface, "pcan2");
    EXPECT_EQ(items[0].ts_ns, kTrcStart + 1'841'000'000LL);
}

TEST(DumpTrc, Version20CanFdTypesAndRemoteRequests) {
    const auto items =
        read_trace(";$FILEVERSION=2.0\n"
                   ";$STARTTIME=46350\n"
                   "      1      1059.900 DT     0300 Rx 7  00 00 00 00 04 00 00\n"
                   "      2      1060.000 FD     0123 Rx 12 01 02 03 04 05 06 07 08 09 0A 0B 0C\n"
                   "      3      1060.100 FB     0124 Rx 9  01 02 03 04 05 06 07 08 09 0A 0B 0C\n"
                   "      4      1060.200 FE     0125 Tx 1  5A\n"
                   "      5      1060.300 BI 00000126 Tx 2  5A A5\n"
                   "      6      1060.400 RR     0705 Rx 1\n");
    ASSERT_EQ(items.size(), 6U);
    for (const auto& i : items) {
        ASSERT_EQ(i.status, ReadStatus::Frame) << i.error;
    }
    EXPECT_EQ(items[0].ts_ns, kTrcStart + 1'059'900'000LL);
    EXPECT_FALSE(items[0].frame.fd());
    EXPECT_TRUE(items[1].frame.fd());
    EXPECT_EQ(items[1].frame.len, 12);
    EXPECT_EQ(items[1].frame.data[11], 0x0C);
    EXPECT_FALSE((items[1].frame.flags & Frame::kBrs) != 0);
    EXPECT_EQ(items[2].frame.len, 12) << "a length of 9..15 is a CAN FD DLC";
    EXPECT_TRUE((items[2].frame.flags & Frame::kBrs) != 0);
    EXPECT_TRUE(items[3].frame.fd());
    EXPECT_TRUE(items[4].frame.fd() && items[4].frame.extended() &&
                (items[4].frame.flags & Frame::kBrs) != 0);
    EXPECT_EQ(items[5].frame, Frame::make_rtr(0x705, 1));
}

TEST(DumpTrc, Version21ColumnsFromTheHeaderAndStatusLinesReported) {
    const std::string trc = ";$FILEVERSION=2.1\n"
                            ";$STARTTIME=46350\n"
                            ";$COLUMNS=N,O,T,B,I,d,R,L,D\n"
                            "      1         1.000 DT 1      0704 Rx -  1  05\n"
                            "      2         2.000 ST 1         - Rx -  4  00 00 00 10\n"
                            "      3         3.000 ER 1         - Rx -  5  04 01 08 81 00\n"
                            "      4         4.000 EC 1         - Rx -  2  60 02\n"
                            "      5         5.000 EV 1  user event text\n"
                            "      6         6.000 FD 1      0123 Rx -  9  01 02 03 04 05 06 07 "
                            "08 09 0A 0B 0C\n";
    const auto items = read_trace(trc);
    ASSERT_EQ(items.size(), 5U) << "the EV line carries no CAN data";
    EXPECT_EQ(items[0].iface, "pcan1");
    EXPECT_EQ(to_string(decode_error_frame(items[1].frame).at(0)), "bus state bus-off");
    EXPECT_EQ(items[1].ts_ns, kTrcStart + 2'000'000LL);
    const auto prot = to_string(decode_error_frame(items[2].frame).at(0));
    EXPECT_NE(prot.find("stuff error"), std::string::npos) << prot;
    EXPECT_NE(prot.find("rx errors 129"), std::string::npos) << prot;
    EXPECT_EQ(to_string(decode_error_frame(items[3].frame).at(0)),
              "bus state error-warning (tx errors 2, rx errors 96)");
    EXPECT_EQ(items[4].frame.len, 12) << "L is the DLC: 9 means 12 bytes";
    // The user sees the status lines as decoded error frames, not dropped.
    const auto out = run_dump_bytes(trc, {});
    EXPECT_NE(out.find("error frame: bus state bus-off"), std::string::npos) << out;
    EXPECT_NE(out.find("error frame: protocol error: stuff error"), std::string::npos) << out;
}

TEST(DumpTrc, MalformedLinesNameLineAndCauseAndReadingGoesOn) {
    const std::string trc = ";$FILEVERSION=2.0\n"
                            ";$STARTTIME=46350\n"
                            "      1         1.000 DT     0704 Rx 1  05\n"
                            "      2         x.000 DT     0704 Rx 1  05\n"
                            "      3         3.000 DT     0704 Rx 2  05\n"
                            "      4         4.000 XX     0704 Rx 1  05\n"
                            "      5         5.000 DT     0704 Rx 1  G5\n"
                            "      6         6.000 DT     0904 Rx 1  05\n"
                            "      7         7.000 DT     0704 Rx 9  00 00 00 00 00 00 00 00 00\n"
                            "      8         8.000 DT     0704 Rx 1  05\n";
    const auto items = read_trace(trc);
    ASSERT_EQ(items.size(), 8U);
    EXPECT_EQ(items[0].status, ReadStatus::Frame);
    EXPECT_EQ(items[1].error, "4: bad time offset: '      2         x.000 DT     0704 Rx 1  05'");
    EXPECT_EQ(items[2].error.rfind("5: fewer data bytes than the length says", 0), 0U);
    EXPECT_EQ(items[3].error.rfind("6: unknown message type", 0), 0U);
    EXPECT_EQ(items[4].error.rfind("7: bad data byte", 0), 0U);
    EXPECT_EQ(items[5].error.rfind("8: 11-bit identifier out of range", 0), 0U);
    EXPECT_EQ(items[6].error.rfind("9: a classic CAN frame carries at most 8 bytes", 0), 0U);
    EXPECT_EQ(items[7].status, ReadStatus::Frame);
    const auto out = run_dump_bytes(trc, {});
    EXPECT_NE(out.find("codrive-dump: memory:4: bad time offset"), std::string::npos) << out;
}

TEST(DumpTrc, BadHeaderValuesAreReported) {
    const auto items = read_trace(";$FILEVERSION=3.0\n;$STARTTIME=yesterday\n"
                                  ";$COLUMNS=N,O,Q,D\n");
    ASSERT_EQ(items.size(), 3U);
    EXPECT_EQ(items[0].error.rfind("1: unknown TRC file version", 0), 0U) << items[0].error;
    EXPECT_EQ(items[1].error.rfind("2: bad STARTTIME", 0), 0U) << items[1].error;
    EXPECT_EQ(items[2].error.rfind("3: unknown column 'Q'", 0), 0U) << items[2].error;
}

// fuzz_dump_traces (bench/fuzz_long.sh, 516,951 executions): a STARTTIME far in the future
// overflowed the 64-bit nanosecond timestamp (signed overflow, undefined behaviour).
// Since session 32 the bound is kMaxTraceTimeNs (the year 2255, day 129,735), for every reader.
TEST(DumpTrc, TimesPastTheYear2255AreRefusedNotWrapped) {
    const auto items = read_trace(";$FILEVERSION=1.3\n"
                                  ";$STARTTIME=463250.0\n"
                                  ";$STARTTIME=129735.5\n"
                                  ";$STARTTIME=129000\n"
                                  "     1)      1841.0 1  Rx         0704 -  1  05\n"
                                  "     2) 8999999999999.0 1  Rx         0704 -  1  05\n"
                                  "     3)      1842.0 1  Rx         0704 -  1  05\n");
    ASSERT_EQ(items.size(), 5U);
    EXPECT_EQ(items[0].error.rfind("2: bad STARTTIME", 0), 0U) << items[0].error;
    EXPECT_EQ(items[1].error.rfind("3: bad STARTTIME", 0), 0U) << items[1].error;
    ASSERT_EQ(items[2].status, ReadStatus::Frame);
    EXPECT_EQ(items[2].ts_ns, (129'000LL - 25'569) * 86'400'000'000'000LL + 1'841'000'000LL);
    EXPECT_EQ(items[3].error.rfind("6: time offset too large", 0), 0U) << items[3].error;
    EXPECT_EQ(items[4].status, ReadStatus::Frame); // reading goes on
}

TEST(DumpTrc, Version12HasABusColumnBeforeTheType) {
    const auto items = read_trace(";$FILEVERSION=1.2\n"
                                  ";$STARTTIME=46350\n"
                                  "     1)      1841.0 3  Rx         0704  1  05\n");
    ASSERT_EQ(items.size(), 1U);
    EXPECT_EQ(items[0].frame, Frame::make(0x704, {0x05}));
    EXPECT_EQ(items[0].iface, "pcan3");
}

// A status line takes its time from the O column; with $COLUMNS putting the type (T) before it,
// the reader would have used the previous line's time (with the start added twice), so such a
// line is refused, naming the cause; more than 8 status bytes are named as such.
TEST(DumpTrc, AStatusLineBeforeItsTimeOffsetIsRefusedNotGivenAnOldTime) {
    const auto items = read_trace(";$FILEVERSION=2.1\n"
                                  ";$STARTTIME=45254.5\n"
                                  ";$COLUMNS=N,T,O,B,I,d,R,L,D\n"
                                  "      1 DT  1000.000 1  0704 Rx -  1  05\n"
                                  "      2 ST  1001.000 1     - Rx -  4  00 00 00 08\n"
                                  "      3 DT  1002.000 1  0704 Rx -  1  05\n");
    ASSERT_EQ(items.size(), 3U);
    EXPECT_EQ(items[0].status, ReadStatus::Frame);
    EXPECT_EQ(items[1].error.rfind("5: a status line whose $COLUMNS puts the type before the "
                                   "time offset",
                                   0),
              0U)
        << items[1].error;
    EXPECT_EQ(items[2].ts_ns - items[0].ts_ns, 2'000'000);
    const auto nine =
        read_trace(";$FILEVERSION=2.1\n"
                   ";$COLUMNS=N,O,T,B,I,d,R,L,D\n"
                   "      1  1000.000 ST 1     - Rx -  4  00 00 00 08 00 00 00 00 01\n");
    ASSERT_EQ(nine.size(), 1U);
    EXPECT_EQ(nine[0].error.rfind("3: more than 8 status bytes", 0), 0U) << nine[0].error;
}
