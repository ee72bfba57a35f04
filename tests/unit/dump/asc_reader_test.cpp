// SPDX-License-Identifier: Apache-2.0
// Vector .asc reader: header, classic/extended/remote/error events, CAN FD events, relative
// timestamps, decimal base, malformed lines.
#include "dump_test_util.hpp"

#include <codrive/core/socket_can_bus.hpp>

#include <fmt/format.h>
#include <gtest/gtest.h>
#include <linux/can/error.h>

#include <string>

using namespace codrive;
using namespace codrive::dump;
using codrive::dump::testing::frames_of;
using codrive::dump::testing::read_trace;
using codrive::dump::testing::run_dump_bytes;

namespace {
// 2026-11-24 00:00:00 UTC.
constexpr std::int64_t kMidnight = 1'795'478'400'000'000'000LL;
} // namespace

TEST(DumpAsc, ClassicExtendedRemoteAndErrorFramesWithTheDate) {
    TraceFormat format{};
    const auto items = read_trace("date Tue Nov 24 01:02:03.250 pm 2026\n"
                                  "base hex  timestamps absolute\n"
                                  "internal events logged\n"
                                  "// version 9.0.0\n"
                                  "Begin Triggerblock Tue Nov 24 01:02:03.250 pm 2026\n"
                                  "   0.000000 Start of measurement\n"
                                  "   0.012345 1  181             Rx   d 2 37 06  Length = 1 "
                                  "BitCount = 2 ID = 385\n"
                                  "   0.013000 2  18FEF100x       Tx   d 3 01 02 03\n"
                                  "   0.014000 1  705             Rx   r 1\n"
                                  "   0.014500 1  706             Rx   r\n"
                                  "   0.015000 1  ErrorFrame\n"
                                  "   0.016000 1  Statistic: D 3 R 1 XD 0 XR 0 E 1 O 0 B 0.5%\n"
                                  "End TriggerBlock\n",
                                  &format);
    EXPECT_EQ(format, TraceFormat::VectorAsc);
    ASSERT_EQ(items.size(), 5U);
    const std::int64_t start = kMidnight + (13 * 3600 + 2 * 60 + 3) * 1'000'000'000LL + 250'000'000;
    EXPECT_EQ(items[0].frame, Frame::make(0x181, {0x37, 0x06}));
    EXPECT_EQ(items[0].ts_ns, start + 12'345'000);
    EXPECT_EQ(items[0].iface, "can1");
    EXPECT_TRUE(items[1].frame.extended());
    EXPECT_EQ(items[1].frame.id, 0x18FEF100U);
    EXPECT_EQ(items[1].iface, "can2");
    EXPECT_EQ(items[2].frame, Frame::make_rtr(0x705, 1));
    EXPECT_EQ(items[3].frame, Frame::make_rtr(0x706, 0));
    ASSERT_TRUE(items[4].frame.error());
    EXPECT_EQ(to_string(decode_error_frame(items[4].frame).at(0)), "protocol error: unspecified");
    // The bus-error class bit can-utils' asc2log and python-can give a bare ErrorFrame, beside
    // the protocol class a Linux driver sets with it; so `-w` keeps it for Wireshark.
    EXPECT_EQ(items[4].frame.id, static_cast<std::uint32_t>(CAN_ERR_PROT | CAN_ERR_BUSERROR));
}

TEST(DumpAsc, CanFdEventsWithAndWithoutSymbolicName) {
    const auto items = read_trace(
        "date Tue Nov 24 00:00:00 2026\n"
        "base hex  timestamps absolute\n"
        "   1.000000 CANFD   1 Rx        123                                   1 0 9 12 01 02 03 "
        "04 "
        "05 06 07 08 09 0A 0B 0C   130000   140 303000 0 0 0 0 0\n"
        "   1.100000 CANFD   1 Tx 1ABCDEFx  MotorCmd                           0 0 2  2 AA BB   "
        "50000   80 201000 0 0 0 0 0\n"
        "   1.200000 CANFD   1 Rx        181                                   0 0 2  2 37 06   "
        "50000   80 0 0 0 0 0 0\n"
        "   1.300000 CANFD   1 Rx        705                                   0 0 1  0   "
        "50000   80 10 0 0 0 0 0\n"
        "   1.400000 CANFD   1 Rx        ErrorFrame\n");
    const auto f = frames_of(items);
    ASSERT_EQ(f.size(), 5U) << (items.empty() ? "" : items[0].error);
    EXPECT_TRUE(f[0].frame.fd());
    EXPECT_TRUE((f[0].frame.flags & Frame::kBrs) != 0);
    EXPECT_EQ(f[0].frame.len, 12);
    EXPECT_EQ(f[0].frame.data[11], 0x0C);
    EXPECT_EQ(f[0].ts_ns, kMidnight + 1'000'000'000LL);
    EXPECT_TRUE(f[1].frame.fd() && f[1].frame.extended());
    EXPECT_EQ(f[1].frame.id, 0x1ABCDEFU);
    EXPECT_FALSE(f[2].frame.fd()) << "no EDL flag: a classic frame on a CAN FD channel";
    EXPECT_EQ(f[2].frame, Frame::make(0x181, {0x37, 0x06}));
    EXPECT_EQ(f[3].frame, Frame::make_rtr(0x705, 1));
    EXPECT_TRUE(f[4].frame.error());
}

TEST(DumpAsc, RelativeTimestampsAddUpAndDecimalBase) {
    const auto items = read_trace("date Tue Nov 24 00:00:00.000 2026\n"
                                  "base dec  timestamps relative\n"
                                  "   0.010000 1  385             Rx   d 2 55 6\n"
                                  "   0.005000 1  1796            Rx   d 1 5\n");
    ASSERT_EQ(items.size(), 2U);
    EXPECT_EQ(items[0].frame, Frame::make(0x181, {0x37, 0x06}));
    EXPECT_EQ(items[0].ts_ns, kMidnight + 10'000'000);
    EXPECT_EQ(items[1].frame, Frame::make(0x704, {0x05}));
    EXPECT_EQ(items[1].ts_ns, kMidnight + 15'000'000);
}

TEST(DumpAsc, DetectedFromEventLinesWithoutHeader) {
    TraceFormat format{};
    const auto items = read_trace("   0.012345 1  181             Rx   d 1 05\n", &format);
    EXPECT_EQ(format, TraceFormat::VectorAsc);
    ASSERT_EQ(items.size(), 1U);
    EXPECT_EQ(items[0].ts_ns, 12'345'000) << "no date: time since the start of the measurement";
}

TEST(DumpAsc, MalformedLinesNameLineAndCause) {
    const std::string asc = "date Tue Nov 24 00:00:00.000 2026\n"
                            "base hex  timestamps absolute\n"
                            "   0.010000 1  181             Rx   d 2 37\n"
                            "   0.020000 1  8000            Rx   d 1 05\n"
                            "   0.030000 1  181             Rx   q 1 05\n"
                            "   0.040000 1  181             Rx   d 1 XY\n"
                            "garbage here\n"
                            "   0.050000 CANFD   1 Rx 123  1 0 9 10 01 02\n"
                            "   0.060000 1  181             Rx   d 1 05\n";
    const auto items = read_trace(asc);
    ASSERT_EQ(items.size(), 7U);
    EXPECT_EQ(items[0].error.rfind("3: fewer data bytes than the DLC says", 0), 0U)
        << items[0].error;
    EXPECT_EQ(items[1].error.rfind("4: bad CAN identifier", 0), 0U) << items[1].error;
    EXPECT_EQ(items[2].error.rfind("5: expected 'd <dlc>' or 'r'", 0), 0U) << items[2].error;
    EXPECT_EQ(items[3].error.rfind("6: bad data byte", 0), 0U) << items[3].error;
    EXPECT_EQ(items[4].error.rfind("7: not an ASC header or event line", 0), 0U) << items[4].error;
    EXPECT_EQ(items[5].error.rfind("8: data length does not match the DLC", 0), 0U)
        << items[5].error;
    EXPECT_EQ(items[6].status, ReadStatus::Frame);
    EXPECT_EQ(items[6].ts_ns, kMidnight + 60'000'000);
}

TEST(DumpAsc, UnreadableDateIsReportedAndTimesCountFromZero) {
    const auto items = read_trace("date someday\n   0.010000 1  181  Rx   d 1 05\n");
    ASSERT_EQ(items.size(), 2U);
    EXPECT_EQ(items[0].error.rfind("1: unreadable date", 0), 0U) << items[0].error;
    EXPECT_EQ(items[1].ts_ns, 10'000'000);
}

// The date line is checked against the calendar (a leap day is accepted only in a leap year).
TEST(DumpAsc, ADateThatDoesNotExistIsUnreadable) {
    auto items = read_trace("date Thu Feb 29 01:02:03.000 2024\n   0.010000 1  181  Rx   d 1 05\n");
    ASSERT_EQ(items.size(), 1U);
    EXPECT_EQ(items[0].ts_ns, 1'709'168'523'010'000'000LL);
    items = read_trace("date Wed Feb 29 01:02:03.000 2023\n   0.010000 1  181  Rx   d 1 05\n");
    ASSERT_EQ(items.size(), 2U);
    EXPECT_EQ(items[0].error.rfind("1: unreadable date", 0), 0U) << items[0].error;
    EXPECT_EQ(items[1].ts_ns, 10'000'000);
    items = read_trace("date Sat Jun 31 01:02:03.000 2023\n   0.010000 1  181  Rx   d 1 05\n");
    ASSERT_EQ(items.size(), 2U);
    EXPECT_EQ(items[0].error.rfind("1: unreadable date", 0), 0U) << items[0].error;
}

// CANoe writes what it knows of an error frame after "ErrorFrame" (lines from python-can's
// logfile.asc): an SJA1000 ECC in binary, the CAN-Core registers, or a text in CANFD events.
TEST(DumpAsc, ErrorFrameDetailsBecomeTheProtocolErrorTheyDescribe) {
    const auto items = read_trace(
        "date Tue Nov 24 00:00:00.000 2026\n"
        "base hex  timestamps absolute\n"
        "   2.501000 1 ErrorFrame\n"
        "   2.501010 1 ErrorFrame ECC: 10100010\n"
        "   2.501020 2 ErrorFrame Flags = 0xe CodeExt = 0x20a2 Code = 0x82 ID = 0 DLC = 0 "
        "Position = 5 Length = 11300\n"
        "  30.806898 CANFD   5 Tx ErrorFrame Not Acknowledge error, dominant error flag fffe c7 "
        "31ca Arb. 556 44 0 0 f 64 00 00 1331984 11 0 46500250 460a0250 20011736 20010205\n"
        "   2.501030 1 ErrorFrame ECC: 1010001\n");
    ASSERT_EQ(items.size(), 5U);
    const auto text = [&](std::size_t i) {
        EXPECT_TRUE(items[i].frame.error()) << i;
        std::string all;
        for (const auto& e : decode_error_frame(items[i].frame)) {
            all += (all.empty() ? "" : "; ") + to_string(e);
        }
        return all;
    };
    EXPECT_EQ(text(0), "protocol error: unspecified");
    EXPECT_EQ(text(1), "protocol error: stuff error in the identifier bits 28-21 (11-bit: 10-3)");
    EXPECT_EQ(text(2), "protocol error: stuff error");
    EXPECT_EQ(text(3), "protocol error: on transmission in the ACK slot; transmission not "
                       "acknowledged (no other node on the bus?)");
    EXPECT_EQ(text(4), "protocol error: unspecified") << "seven bits are not an ECC";
}

// A CANFD event with more than 8 data bytes is CAN FD even when its flags lack EDL (python-can's
// test_CanFdMessage64.asc and logfile.asc have such lines): the frame is kept, not dropped. A
// classic event with a DLC above F (python-can writes "d 40" for a 64-byte frame not marked CAN
// FD) names the DLC.
TEST(DumpAsc, CanFdEventWithoutEdlButSixtyFourBytesIsCanFd) {
    std::string data;
    for (int i = 0; i < 64; ++i) {
        data += fmt::format(" {:02X}", i);
    }
    const auto items = read_trace(
        "date Tue Nov 24 00:00:00 2026\n"
        "base hex  timestamps absolute\n"
        "   1.000000 CANFD   4 Rx        4EE                                   0 1 f 64" +
        data + " 1331984 11 0 46500250 460a0250 20011736 20010205\n" +
        "   2.000000 CANFD   4 Rx        1C4D80A7x    Name_2     1 0 f 64" + data +
        " 1331984 11 0 46500250 460a0250 20011736 20010205\n" +
        "   3.000000 1  123x            Rx   d 40" + data + "\n");
    ASSERT_EQ(items.size(), 3U);
    ASSERT_EQ(items[0].status, ReadStatus::Frame) << items[0].error;
    EXPECT_TRUE(items[0].frame.fd());
    EXPECT_EQ(items[0].frame.flags & Frame::kBrs, 0);
    EXPECT_EQ(items[0].frame.len, 64);
    EXPECT_EQ(items[0].frame.data[63], 63);
    ASSERT_EQ(items[1].status, ReadStatus::Frame) << items[1].error;
    EXPECT_TRUE(items[1].frame.fd() && items[1].frame.extended());
    EXPECT_NE(items[1].frame.flags & Frame::kBrs, 0);
    EXPECT_EQ(items[1].ts_ns, kMidnight + 2'000'000'000LL);
    EXPECT_EQ(items[2].status, ReadStatus::Malformed);
    EXPECT_EQ(items[2].error.rfind("5: DLC 0x40 is not a CAN DLC (0 to F); a classic CAN frame "
                                   "carries at most 8 bytes, and CAN FD frames are CANFD events",
                                   0),
              0U)
        << items[2].error;
}

// Times are kept to the year 2255 (kMaxTraceTimeNs): a date plus an event time, or relative
// times summed, beyond it are named, not wrapped around.
TEST(DumpAsc, TimesPastTheYear2255AreNamed) {
    const auto absolute = read_trace("date Tue Nov 24 00:00:00 2200\n"
                                     "base hex  timestamps absolute\n"
                                     "   1.000000 1  181             Rx   d 1 05\n"
                                     "   8999999999.000000 1  181    Rx   d 1 05\n");
    ASSERT_EQ(absolute.size(), 2U);
    EXPECT_EQ(absolute[0].status, ReadStatus::Frame);
    EXPECT_EQ(absolute[1].error.rfind("4: the date plus this time is past the year 2255", 0), 0U)
        << absolute[1].error;
    std::string relative = "base hex  timestamps relative\n";
    for (int i = 0; i < 3; ++i) {
        relative += "   4000000000.000000 1  181    Rx   d 1 05\n";
    }
    const auto summed = read_trace(relative);
    ASSERT_EQ(summed.size(), 3U);
    EXPECT_EQ(summed[1].status, ReadStatus::Frame);
    EXPECT_EQ(summed[2].error.rfind("4: the relative times add up past the year 2255", 0), 0U)
        << summed[2].error;
}
