// SPDX-License-Identifier: Apache-2.0
// candump text parsing: log and screen formats, every frame kind, and errors.
#include "dump_test_util.hpp"

#include <codrive/dump/log_parser.hpp>

#include <gtest/gtest.h>

using namespace codrive;
using namespace codrive::dump;

namespace {
TraceRecord parse_ok(std::string_view line) {
    TraceRecord r;
    std::string_view err;
    EXPECT_EQ(parse_log_line(line, r, err), LineStatus::Frame) << line << ": " << err;
    return r;
}
std::string_view parse_error(std::string_view line) {
    TraceRecord r;
    std::string_view err;
    EXPECT_EQ(parse_log_line(line, r, err), LineStatus::Error) << line;
    return err;
}
} // namespace

TEST(DumpLogParser, LogFormatWithTimestampInterfaceAndData) {
    const auto r = parse_ok("(1700000000.123456) can0 181#11223344");
    EXPECT_TRUE(r.has_ts);
    EXPECT_EQ(r.ts_ns, 1700000000123456000LL);
    EXPECT_EQ(r.iface, "can0");
    EXPECT_EQ(r.frame.id, 0x181U);
    EXPECT_EQ(r.frame.len, 4);
    EXPECT_EQ(r.frame.data[3], 0x44);
    EXPECT_FALSE(r.frame.extended());
}

TEST(DumpLogParser, LogFormatKinds) {
    EXPECT_TRUE(parse_ok("(1.5) vcan0 12345678#01").frame.extended());
    EXPECT_EQ(parse_ok("(1.5) vcan0 12345678#01").frame.id, 0x12345678U);
    const auto rtr = parse_ok("(1.0) can0 705#R");
    EXPECT_TRUE(rtr.frame.rtr());
    EXPECT_EQ(rtr.frame.len, 0);
    EXPECT_EQ(parse_ok("(1.0) can0 705#R4").frame.len, 4);
    const auto fd = parse_ok("(1.0) can0 123##1AABBCCDDEEFF001122334455");
    EXPECT_TRUE(fd.frame.fd());
    EXPECT_EQ(fd.frame.len, 12);
    EXPECT_EQ(parse_ok("(1.0) can0 123#11.22.33").frame.len, 3);
    EXPECT_EQ(parse_ok("(1.0) can0 080#").frame.len, 0);
    EXPECT_TRUE(parse_ok("(1.0) can0 20000004#0004000000000000").frame.error());
    EXPECT_EQ(parse_ok("(1.0) can0 181#1122 R").frame.len, 2); // -L direction token ignored
}

TEST(DumpLogParser, ScreenFormats) {
    const auto a = parse_ok("  vcan0  123   [4]  11 22 33 44");
    EXPECT_FALSE(a.has_ts);
    EXPECT_EQ(a.iface, "vcan0");
    EXPECT_EQ(a.frame.id, 0x123U);
    EXPECT_EQ(a.frame.len, 4);
    const auto b = parse_ok(" (1700000000.000001)  vcan0  123   [0] ");
    EXPECT_EQ(b.ts_ns, 1700000000000001000LL);
    const auto c = parse_ok(" (2023-11-14 22:13:20.500000)  can0  701   [1]  7F");
    EXPECT_EQ(c.ts_ns, 1700000000500000000LL);
    EXPECT_TRUE(parse_ok("  can0  705   [1]  remote request").frame.rtr());
    EXPECT_EQ(parse_ok("  can0  123   [2]  01 02   '..'").frame.len, 2); // candump -a
}

TEST(DumpLogParser, CommentsAndBlankLinesAreSkipped) {
    TraceRecord r;
    std::string_view err;
    EXPECT_EQ(parse_log_line("", r, err), LineStatus::Skip);
    EXPECT_EQ(parse_log_line("   ", r, err), LineStatus::Skip);
    EXPECT_EQ(parse_log_line("# comment", r, err), LineStatus::Skip);
}

TEST(DumpLogParser, ErrorsNameTheProblem) {
    EXPECT_EQ(parse_error("(1.0) can0 1G1#00"), "bad CAN identifier");
    EXPECT_EQ(parse_error("(1.0) can0 181#0"), "odd number of data digits");
    EXPECT_EQ(parse_error("(1.0) can0 181#001122334455667788"), "too many data bytes");
    EXPECT_EQ(parse_error("(1.0) can0 800#00"), "11-bit identifier out of range");
    EXPECT_EQ(parse_error("(abc) can0 181#00"), "bad timestamp");
    EXPECT_EQ(parse_error("(1.0 can0 181#00"), "unterminated timestamp");
    EXPECT_EQ(parse_error("  can0  123   [4]  11 22"), "fewer data bytes than the length says");
    EXPECT_EQ(parse_error("  can0  123   4  11 22"), "expected a length such as [8]");
}

TEST(DumpLogParser, ReaderReportsLineNumbersAndContinues) {
    auto in = BufferedInput::from_memory("(1.0) can0 181#00\nbad line\n\n(2.0) can0 182#01\n");
    LogReader reader(*in);
    TraceRecord r;
    EXPECT_EQ(reader.next(r), ReadStatus::Frame);
    EXPECT_EQ(reader.next(r), ReadStatus::Malformed);
    EXPECT_EQ(reader.error().rfind("2: bad CAN identifier", 0), 0U) << reader.error();
    EXPECT_EQ(reader.next(r), ReadStatus::Frame);
    EXPECT_EQ(r.frame.id, 0x182U);
    EXPECT_EQ(reader.next(r), ReadStatus::End);
}

TEST(DumpLogParser, OverlongLineIsReportedOnceAndSkipped) {
    const auto path = ::testing::TempDir() + "/dump_long.log";
    {
        std::FILE* f = std::fopen(path.c_str(), "w");
        std::fputs("(1.0) can0 181#00\n", f);
        for (int i = 0; i < 10000; ++i) {
            std::fputs("xxxxxxxxxx", f);
        }
        std::fputs("\n(2.0) can0 182#01", f); // no final newline
        std::fclose(f);
    }
    auto in = BufferedInput::open(path, 4096);
    ASSERT_TRUE(in);
    LogReader reader(**in);
    TraceRecord r;
    EXPECT_EQ(reader.next(r), ReadStatus::Frame);
    EXPECT_EQ(reader.next(r), ReadStatus::Malformed);
    EXPECT_NE(reader.error().find("longer than 4096 bytes"), std::string_view::npos);
    ASSERT_EQ(reader.next(r), ReadStatus::Frame) << reader.error();
    EXPECT_EQ(r.frame.id, 0x182U);
    EXPECT_EQ(reader.next(r), ReadStatus::End);
}

#include <codrive/dump/stats.hpp>

TEST(DumpStats, WorstCaseFrameBitsIncludeStuffingAndInterframeSpace) {
    // 11-bit: 47 + 8n + floor((34 + 8n - 1) / 4); 29-bit: 67 + 8n + floor((54 + 8n - 1) / 4).
    EXPECT_EQ(frame_bits_worst_case(Frame::make(0x080, {})), 47U + 8U);
    EXPECT_EQ(frame_bits_worst_case(Frame::make(0x181, {1, 2, 3, 4, 5, 6, 7, 8})), 135U);
    Frame ext = Frame::make(0, {1, 2, 3, 4, 5, 6, 7, 8});
    ext.id = 0x1234567;
    ext.flags = Frame::kExtended;
    EXPECT_EQ(frame_bits_worst_case(ext), 67U + 64U + 29U);
}

TEST(DumpLogParser, ScreenDeltaTimestampsAreSummed) {
    const auto items = codrive::dump::testing::read_trace(" (000.000000)  can0  704   [1]  05\n"
                                                          " (000.010000)  can0  705   [1]  05\n"
                                                          " (000.002500)  can0  706   [1]  05\n");
    ASSERT_EQ(items.size(), 3U);
    EXPECT_EQ(items[1].ts_ns, 10'000'000);
    EXPECT_EQ(items[2].ts_ns, 12'500'000) << "candump -t d prints deltas";
}

TEST(DumpLogParser, ScreenFromZeroTimestampsAreKept) {
    const auto items = codrive::dump::testing::read_trace(" (000.000000)  can0  704   [1]  05\n"
                                                          " (000.010000)  can0  705   [1]  05\n"
                                                          " (000.012500)  can0  706   [1]  05\n");
    ASSERT_EQ(items.size(), 3U);
    EXPECT_EQ(items[2].ts_ns, 12'500'000) << "candump -t z counts from the first frame";
}

TEST(DumpLogParser, ScreenExtrasGiveDirectionAndCanFdFlags) {
    const auto items =
        codrive::dump::testing::read_trace("  vcan0  TX - -  181   [2]  37 06\n"
                                           "  vcan0  RX B -  123  [08]  01 02 03 04 05 06 07 08\n"
                                           "  vcan0  RX - -  124  [04]  01 02 03 04\n"
                                           "  vcan0  RX Q -  181   [1]  05\n");
    ASSERT_EQ(items.size(), 4U);
    EXPECT_EQ(items[0].frame, Frame::make(0x181, {0x37, 0x06}));
    EXPECT_TRUE(items[1].frame.fd());
    EXPECT_TRUE((items[1].frame.flags & Frame::kBrs) != 0);
    EXPECT_TRUE(items[2].frame.fd()) << "a two-digit length is candump's CAN FD form";
    EXPECT_EQ(items[3].error.rfind("4: expected candump -x flags", 0), 0U) << items[3].error;
}

// candump -t d prints the time since the previous frame; summed they stay below the year 2255
// (kMaxTraceTimeNs), and a sum past it is named instead of wrapping around.
TEST(DumpLog, DeltaTimesThatAddUpPastTheYear2255AreNamed) {
    std::string screen = " (000.000000)  can0  181   [1]  01\n";
    for (int i = 0; i < 95; ++i) {
        screen += " (99999999.000000)  can0  181   [1]  01\n";
    }
    const auto items = codrive::dump::testing::read_trace(screen);
    ASSERT_EQ(items.size(), 96U);
    EXPECT_EQ(items[90].status, ReadStatus::Frame) << items[90].error;
    EXPECT_EQ(items[90].ts_ns, 90 * 99'999'999'000'000'000LL);
    EXPECT_EQ(items[91].status, ReadStatus::Malformed);
    EXPECT_EQ(items[91].error.rfind("92: the time deltas add up past the year 2255", 0), 0U)
        << items[91].error;
}

// candump -t d written on Windows (CRLF): the look-ahead that recognises deltas reads the lines
// as next_line() does, so the times are summed, not taken as times from zero.
TEST(DumpLog, DeltaTimesAreRecognisedInACrlfFile) {
    std::string screen;
    for (int i = 0; i < 5; ++i) {
        screen += std::string(i == 0 ? " (000.000000)" : " (000.010000)") +
                  "  can0  181   [2]  01 22\r\n";
    }
    const auto items = codrive::dump::testing::read_trace(screen);
    ASSERT_EQ(items.size(), 5U);
    EXPECT_EQ(items[4].status, ReadStatus::Frame) << items[4].error;
    EXPECT_EQ(items[4].ts_ns, 40'000'000) << "deltas summed";
}

// The fraction of a time at the bound takes it past kMaxTraceTimeNs: refused too.
TEST(DumpLog, ATimeWhoseFractionPassesTheBoundIsRefused) {
    const auto items = codrive::dump::testing::read_trace("(9000000000.000000) can0 181#01\n"
                                                          "(9000000000.999999) can0 181#01\n");
    ASSERT_EQ(items.size(), 2U);
    EXPECT_EQ(items[0].status, ReadStatus::Frame);
    EXPECT_EQ(items[0].ts_ns, 9'000'000'000'000'000'000LL);
    EXPECT_EQ(items[1].status, ReadStatus::Malformed);
}

// candump -ta style dates are checked against the calendar: a date that does not exist is a bad
// timestamp, not the first days of the next month.
TEST(DumpLogParser, DatesThatDoNotExistAreBadTimestamps) {
    EXPECT_EQ(parse_ok(" (2024-02-29 00:00:00.000000)  can0  701   [1]  7F").ts_ns,
              1'709'164'800'000'000'000LL);
    EXPECT_EQ(parse_ok(" (2000-02-29 00:00:00.000000)  can0  701   [1]  7F").ts_ns,
              951'782'400'000'000'000LL);
    EXPECT_EQ(parse_error(" (2023-02-29 00:00:00.000000)  can0  701   [1]  7F"), "bad timestamp");
    EXPECT_EQ(parse_error(" (2100-02-29 00:00:00.000000)  can0  701   [1]  7F"), "bad timestamp");
    EXPECT_EQ(parse_error(" (2023-04-31 00:00:00.000000)  can0  701   [1]  7F"), "bad timestamp");
    EXPECT_EQ(parse_error(" (2023-13-01 00:00:00.000000)  can0  701   [1]  7F"), "bad timestamp");
}
