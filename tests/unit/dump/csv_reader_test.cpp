// SPDX-License-Identifier: Apache-2.0
// CSV reader: columns found by header names (SavvyCAN, python-can, per-byte and single-column
// data, ';' separator), malformed rows.
#include "dump_test_util.hpp"

#include <gtest/gtest.h>

using namespace codrive;
using namespace codrive::dump;
using codrive::dump::testing::read_trace;

TEST(DumpCsv, SavvyCanMicrosecondsPerByteColumnsAndBus) {
    TraceFormat format{};
    const auto items = read_trace("Time Stamp,ID,Extended,Dir,Bus,LEN,D1,D2,D3,D4,D5,D6,D7,D8\n"
                                  "1500,00000181,false,Rx,0,2,37,06,,,,,,\n"
                                  "2500,18FF0001,true,Rx,1,3,01,02,03,00,00,00,00,00\n",
                                  &format);
    EXPECT_EQ(format, TraceFormat::Csv);
    ASSERT_EQ(items.size(), 2U);
    EXPECT_EQ(items[0].frame, Frame::make(0x181, {0x37, 0x06}));
    EXPECT_FALSE(items[0].frame.extended()) << "the Extended column decides, not the 8 digits";
    EXPECT_EQ(items[0].ts_ns, 1'500'000);
    EXPECT_EQ(items[0].iface, "can0");
    EXPECT_TRUE(items[1].frame.extended());
    EXPECT_EQ(items[1].frame.len, 3) << "bytes past LEN are padding";
    EXPECT_EQ(items[1].iface, "can1");
}

TEST(DumpCsv, PythonCanBase64DataRemoteAndErrorColumns) {
    const auto items = read_trace("timestamp,arbitration_id,extended,remote,error,dlc,data\n"
                                  "1700000000.250000,0x181,0,0,0,2,NwY=\n"
                                  "1700000000.260000,0x705,0,1,0,1,\n"
                                  "1700000000.270000,0x000,0,0,1,0,\n");
    ASSERT_EQ(items.size(), 3U);
    EXPECT_EQ(items[0].frame, Frame::make(0x181, {0x37, 0x06}));
    EXPECT_EQ(items[0].ts_ns, 1'700'000'000'250'000'000LL);
    EXPECT_EQ(items[1].frame, Frame::make_rtr(0x705, 1));
    EXPECT_TRUE(items[2].frame.error());
}

TEST(DumpCsv, SemicolonsMillisecondsHexDataAndCanFd) {
    const auto items = read_trace("Time [ms];ID (hex);DLC;Data (hex)\n"
                                  "12.5;181h;2;37 06\n"
                                  "13.0;123;12;0102030405060708090A0B0C\n");
    ASSERT_EQ(items.size(), 2U);
    EXPECT_EQ(items[0].frame, Frame::make(0x181, {0x37, 0x06}));
    EXPECT_EQ(items[0].ts_ns, 12'500'000);
    EXPECT_TRUE(items[1].frame.fd()) << "12 bytes can only be CAN FD";
    EXPECT_EQ(items[1].frame.data[11], 0x0C);
}

TEST(DumpCsv, MalformedRowsNameLineAndCause) {
    const auto items = read_trace("time,id,dlc,data\n"
                                  "0.1,181,2,37\n"
                                  "0.2,18G,1,05\n"
                                  "abc,181,1,05\n"
                                  "0.3,181,1,0X\n"
                                  "0.4,900,1,05\n"
                                  "0.5,181,1,05\n");
    ASSERT_EQ(items.size(), 6U);
    EXPECT_EQ(items[0].error, "2: fewer data bytes than the length says: '0.1,181,2,37'");
    EXPECT_EQ(items[1].error.rfind("3: bad CAN identifier", 0), 0U) << items[1].error;
    EXPECT_EQ(items[2].error.rfind("4: bad timestamp", 0), 0U) << items[2].error;
    EXPECT_EQ(items[3].error.rfind("5: bad data", 0), 0U) << items[3].error;
    EXPECT_EQ(items[4].frame.extended(), true) << "an id above 7FF without a column is 29-bit";
    EXPECT_EQ(items[5].status, ReadStatus::Frame);
}

// HMS/IXXAT export layout (CANnector Log user manual, section 6.1): Bus, No, Time (abs) as
// s.ms.µs.ns, State, ID (hex), Length, Data (hex), ASCII.
TEST(DumpCsv, IxxatLayoutDottedTimeBusAndAsciiColumn) {
    TraceFormat format{};
    const auto items = read_trace("Bus;No;Time (abs);State;ID (hex);Length;Data (hex);ASCII\r\n"
                                  "2;1;3605.250.000.123;;181;2;37 06;7.\r\n"
                                  "2;2;3605.250.100;;1ABCDEF0;1;3B;;\r\n"
                                  "2;3;3605.25.000;;181;1;05;.\r\n"
                                  "2;4;3605.1.2.3.4;;181;1;05;.\r\n"
                                  "2;5;3605.300.000.000;;181;1;05;.\r\n",
                                  &format);
    EXPECT_EQ(format, TraceFormat::Csv);
    ASSERT_EQ(items.size(), 5U);
    ASSERT_EQ(items[0].status, ReadStatus::Frame) << items[0].error;
    EXPECT_EQ(items[0].frame, Frame::make(0x181, {0x37, 0x06}));
    EXPECT_EQ(items[0].ts_ns, 3'605'250'000'123LL) << "seconds, ms, µs, ns";
    EXPECT_EQ(items[0].iface, "can2");
    ASSERT_EQ(items[1].status, ReadStatus::Frame) << items[1].error;
    EXPECT_EQ(items[1].ts_ns, 3'605'250'100'000LL) << "groups left out are zero";
    EXPECT_TRUE(items[1].frame.extended());
    EXPECT_EQ(items[1].frame.data[0], 0x3B) << "a ';' in the ASCII column is past the last column";
    EXPECT_EQ(items[2].error, "4: bad timestamp: '2;3;3605.25.000;;181;1;05;.'")
        << "groups have three digits";
    EXPECT_EQ(items[3].error.rfind("5: bad timestamp", 0), 0U) << "at most ms, µs and ns";
    EXPECT_EQ(items[4].status, ReadStatus::Frame) << "reading goes on";
}

// SavvyCAN's "Generic ID/Data CSV" (its examples/GenericID_Log.csv): two columns, every id written
// with 8 digits, a trailing space after the data. SavvyCAN reads an id above 7FF as 29-bit, so
// 8 digits alone do not make one here (they do in other CSV files, see the 29-bit column rule).
TEST(DumpCsv, SavvyCanGenericIdDataColumnsWithEightDigitIds) {
    TraceFormat format{};
    const auto items = read_trace("ID,Data Bytes\n"
                                  "0000021A,FE 36 12 FE 69 05 07 AD \n"
                                  "0000048C,00 \n"
                                  "18FEF100,01 02 \n",
                                  &format);
    EXPECT_EQ(format, TraceFormat::Csv);
    ASSERT_EQ(items.size(), 3U);
    for (const auto& i : items) {
        ASSERT_EQ(i.status, ReadStatus::Frame) << i.error;
        EXPECT_FALSE(i.has_ts);
    }
    EXPECT_EQ(items[0].frame, Frame::make(0x21A, {0xFE, 0x36, 0x12, 0xFE, 0x69, 0x05, 0x07, 0xAD}));
    EXPECT_EQ(items[1].frame, Frame::make(0x48C, {0x00}));
    EXPECT_TRUE(items[2].frame.extended());
    EXPECT_EQ(items[2].frame.id, 0x18FEF100U);
}

// With several time columns the first that is not an interval gives the time, in its own unit: a
// "Time Delta (ms)" after it neither overwrites the time nor changes its unit.
TEST(DumpCsv, TheFirstTimeColumnThatIsNotAnIntervalGivesTheTime) {
    auto items = read_trace("Time Delta (ms),Timestamp (us),Time (rel),ID,Data\n"
                            "0.000,1500,0.0,181,37 06\n"
                            "1.000,2500,1.0,181,37 07\n");
    ASSERT_EQ(items.size(), 2U);
    EXPECT_EQ(items[0].status, ReadStatus::Frame) << items[0].error;
    EXPECT_EQ(items[0].ts_ns, 1'500'000);
    EXPECT_EQ(items[1].ts_ns, 2'500'000);
    items = read_trace("Time,Time Stamp (ms),ID,Data\n1.5,7,181,37 06\n");
    ASSERT_EQ(items.size(), 1U);
    EXPECT_EQ(items[0].ts_ns, 1'500'000'000) << "the first, in seconds";
}
