// SPDX-License-Identifier: Apache-2.0
// Frame construction, validity and candump text.
#include <codrive/core/frame.hpp>

#include <gtest/gtest.h>

using namespace codrive;

TEST(Frame, MakeCopiesBytesAndCutsAtEight) {
    const std::uint8_t bytes[10] = {1, 2, 3, 4, 5, 6, 7, 8, 9, 10};
    const Frame f = Frame::make(0x181, bytes);
    EXPECT_EQ(f.len, 8);
    EXPECT_EQ(f.data[7], 8);
    EXPECT_TRUE(f.valid());
}

TEST(Frame, ValidityChecksIdWidthAndLength) {
    Frame f = Frame::make(0x800, {});
    EXPECT_FALSE(f.valid()) << "11-bit id above 0x7FF";
    f.flags = Frame::kExtended;
    EXPECT_TRUE(f.valid());
    f.id = 0x2000'0000;
    EXPECT_FALSE(f.valid()) << "29-bit id overflow";
    Frame fd;
    fd.flags = Frame::kFd;
    fd.len = 12;
    EXPECT_TRUE(fd.valid());
    fd.len = 13;
    EXPECT_FALSE(fd.valid()) << "13 is not a CAN FD length";
    fd.len = 64;
    EXPECT_TRUE(fd.valid());
    Frame classic;
    classic.len = 9;
    EXPECT_FALSE(classic.valid());
}

TEST(Frame, FdDlcMapping) {
    EXPECT_EQ(fd_len_to_dlc(8), 8);
    EXPECT_EQ(fd_len_to_dlc(9), 9);
    EXPECT_EQ(fd_len_to_dlc(33), 14);
    EXPECT_EQ(fd_dlc_to_len(15), 64U);
}

TEST(Frame, CandumpText) {
    EXPECT_EQ(to_string(Frame::make(0x123, {0x11, 0x22, 0x33, 0x44})), "123#11223344");
    EXPECT_EQ(to_string(Frame::make_rtr(0x701, 1)), "701#R1");
    Frame ext = Frame::make(0x1234567, {0xAB});
    ext.flags = Frame::kExtended;
    EXPECT_EQ(to_string(ext), "01234567#AB");
    Frame fd;
    fd.id = 0x10;
    fd.flags = Frame::kFd | Frame::kBrs;
    fd.len = 2;
    fd.data[0] = 0xAA;
    fd.data[1] = 0xBB;
    EXPECT_EQ(to_string(fd), "010##1AABB");
}

TEST(Frame, EqualityIgnoresBytesPastLength) {
    Frame a = Frame::make(0x100, {1, 2});
    Frame b = a;
    b.data[5] = 0xFF;
    EXPECT_EQ(a, b);
    b.data[1] = 3;
    EXPECT_NE(a, b);
}

TEST(Frame, ParsesCandumpTextAndRoundTrips) {
    for (const char* text :
         {"123#11223344", "701#R1", "01234567#AB", "010##1AABB", "7FF#", "080#"}) {
        Frame f;
        ASSERT_TRUE(parse_frame(text, f)) << text;
        EXPECT_EQ(to_string(f), text);
    }
    Frame dotted;
    ASSERT_TRUE(parse_frame("123#11.22.33", dotted));
    EXPECT_EQ(dotted.len, 3);
}

TEST(Frame, RejectsMalformedText) {
    Frame f = Frame::make(0x1, {0x55});
    for (const char* text : {"", "#", "12#00", "123", "123#1", "123#GG", "123#112233445566778899",
                             "800#", "1234#00", "123#R9", "123##"}) {
        EXPECT_FALSE(parse_frame(text, f)) << text;
    }
    EXPECT_EQ(f, Frame::make(0x1, {0x55})) << "a failed parse leaves the output alone";
}
