// SPDX-License-Identifier: Apache-2.0
// Datagram and frame codec, working-counter rules per command (ETG.1000.4 §5.3-5.4).
#include <codrive/ethercat/datagram.hpp>
#include <codrive/ethercat/error.hpp>

#include <gtest/gtest.h>

namespace codrive::ethercat {
namespace {

TEST(EcatDatagram, EncodesHeaderLengthsAndMoreBitThenDecodesBack) {
    std::vector<Datagram> in{Datagram::physical(Command::Fprd, 0x1001, 0x0130, 6),
                             Datagram::logical(Command::Lrw, 0x00010000, 20)};
    in[0].index = 7;
    in[1].index = 7;
    in[1].data[3] = 0xAB;
    auto frame = encode_frame(in);
    ASSERT_TRUE(frame);
    EXPECT_EQ((*frame)[12], 0x88);
    EXPECT_EQ((*frame)[13], 0xA4);
    const auto ecat = static_cast<std::uint16_t>((*frame)[14] | ((*frame)[15] << 8));
    EXPECT_EQ(ecat & 0x07FF, 12 + 6 + 12 + 20);
    EXPECT_EQ(ecat >> 12, 1);
    // First datagram: M bit set; last one: clear.
    EXPECT_NE((*frame)[16 + 7] & 0x80, 0);
    auto out = decode_frame(*frame);
    ASSERT_TRUE(out);
    ASSERT_EQ(out->size(), 2U);
    EXPECT_EQ((*out)[0].command, Command::Fprd);
    EXPECT_EQ((*out)[0].adp(), 0x1001);
    EXPECT_EQ((*out)[0].ado(), 0x0130);
    EXPECT_EQ((*out)[1].address, 0x00010000U);
    EXPECT_EQ((*out)[1].data[3], 0xAB);
}

TEST(EcatDatagram, ShortFramesArePaddedToSixtyBytes) {
    std::vector<Datagram> in{Datagram::physical(Command::Brd, 0, 0, 2)};
    auto frame = encode_frame(in);
    ASSERT_TRUE(frame);
    EXPECT_EQ(frame->size(), kMinFrameSize);
    auto out = decode_frame(*frame);
    ASSERT_TRUE(out);
    EXPECT_EQ(out->size(), 1U);
}

TEST(EcatDatagram, TooManyBytesForOneFrameIsRefused) {
    std::vector<Datagram> in{Datagram::logical(Command::Lrw, 0, kMaxDatagramData + 1)};
    auto frame = encode_frame(in);
    ASSERT_FALSE(frame);
    EXPECT_EQ(frame.error(), EcatErrc::FrameTooLarge);
    std::vector<Datagram> fits{Datagram::logical(Command::Lrw, 0, kMaxDatagramData)};
    EXPECT_TRUE(encode_frame(fits));
}

TEST(EcatDatagram, MalformedFramesAreRejectedNotTrusted) {
    std::vector<Datagram> in{Datagram::physical(Command::Aprd, 0, 0x0130, 2)};
    auto frame = *encode_frame(in);
    auto wrong_type = frame;
    wrong_type[13] = 0x00;
    EXPECT_FALSE(decode_frame(wrong_type));
    auto bad_len = frame;
    bad_len[16 + 6] = 0xFF; // datagram length past the end
    bad_len[16 + 7] = 0x07;
    EXPECT_FALSE(decode_frame(bad_len));
    auto bad_cmd = frame;
    bad_cmd[16] = 0x42;
    EXPECT_FALSE(decode_frame(bad_cmd));
    EXPECT_FALSE(decode_frame(std::span<const std::uint8_t>(frame).first(15)));
}

TEST(EcatDatagram, DecodeIntoRefusesAnotherFramesAnswer) {
    std::vector<Datagram> a{Datagram::physical(Command::Fprd, 1, 0x0130, 2)};
    a[0].index = 3;
    auto frame = *encode_frame(a);
    std::vector<Datagram> b{Datagram::physical(Command::Fprd, 1, 0x0130, 4)};
    b[0].index = 3;
    EXPECT_FALSE(decode_frame_into(frame, b));
    EXPECT_TRUE(decode_frame_into(frame, a));
}

TEST(EcatWkc, ReadWriteAndReadWriteCommandsCountAsTheStandardSays) {
    EXPECT_EQ(wkc_increment(Command::Aprd, true, false), 1);
    EXPECT_EQ(wkc_increment(Command::Fpwr, false, true), 1);
    EXPECT_EQ(wkc_increment(Command::Fpwr, false, false), 0);
    EXPECT_EQ(wkc_increment(Command::Lrw, true, true), 3);
    EXPECT_EQ(wkc_increment(Command::Lrw, true, false), 1);
    EXPECT_EQ(wkc_increment(Command::Lrw, false, true), 2);
    EXPECT_EQ(wkc_increment(Command::Brw, true, true), 3);
    EXPECT_EQ(wkc_increment(Command::Armw, true, false), 1);
    EXPECT_EQ(wkc_increment(Command::Frmw, false, true), 1);
    EXPECT_EQ(wkc_increment(Command::Nop, true, true), 0);
    EXPECT_EQ(expected_wkc(Command::Lrw, 3), 9);
    EXPECT_EQ(expected_wkc(Command::Brd, 4), 4);
}

TEST(EcatDatagram, InPlaceViewAddressesDataAndWkc) {
    std::vector<Datagram> in{Datagram::physical(Command::Aprd, 0, 0x0010, 2),
                             Datagram::physical(Command::Aprd, 0xFFFF, 0x0010, 2)};
    auto frame = *encode_frame(in);
    int seen = 0;
    ASSERT_TRUE(for_each_datagram(frame, [&](DatagramRef& d) {
        d.set_adp(static_cast<std::uint16_t>(d.adp() + 1));
        d.set_wkc(static_cast<std::uint16_t>(d.wkc() + 1));
        d.data[0] = 0x5A;
        ++seen;
    }));
    EXPECT_EQ(seen, 2);
    auto out = *decode_frame(frame);
    EXPECT_EQ(out[0].adp(), 1);
    EXPECT_EQ(out[1].adp(), 0);
    EXPECT_EQ(out[0].wkc, 1);
    EXPECT_EQ(out[1].data[0], 0x5A);
    EXPECT_EQ(to_string(Command::Lrw), "LRW");
}

} // namespace
} // namespace codrive::ethercat
