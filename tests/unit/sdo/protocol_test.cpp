// SPDX-License-Identifier: Apache-2.0
// SDO frame layout, CRC and error sentences.
#include <codrive/sdo/crc16.hpp>
#include <codrive/sdo/error.hpp>
#include <codrive/sdo/protocol.hpp>

#include <gtest/gtest.h>

#include <string_view>

namespace codrive::sdo {
namespace {

std::span<const std::uint8_t> bytes(std::string_view s) {
    return {reinterpret_cast<const std::uint8_t*>(s.data()), s.size()};
}

TEST(SdoCrc16, MatchesTheCcittCheckValue) {
    EXPECT_EQ(crc16_ccitt(bytes("123456789")), 0x31C3);
    EXPECT_EQ(crc16_ccitt({}), 0x0000);
}

TEST(SdoCrc16, CanBeComputedInPieces) {
    const auto whole = crc16_ccitt(bytes("123456789"));
    EXPECT_EQ(crc16_ccitt(bytes("6789"), crc16_ccitt(bytes("12345"))), whole);
}

TEST(SdoProtocol, ExpeditedDownloadRequestRoundTrips) {
    const std::uint8_t data[] = {0xAA, 0xBB};
    const Payload p = make_initiate_download_expedited(0x6040, 0x00, data);
    EXPECT_EQ(p[0], 0x2B); // ccs 1, n 2, e 1, s 1
    const FrameInfo info = parse_frame(p, Sender::Client);
    EXPECT_EQ(info.kind, FrameKind::InitiateDownloadRequest);
    EXPECT_EQ(info.index, 0x6040);
    EXPECT_TRUE(info.expedited);
    EXPECT_EQ(info.data_len, 2);
    EXPECT_EQ(info.data[1], 0xBB);
}

TEST(SdoProtocol, SegmentFieldsRoundTrip) {
    const std::uint8_t data[] = {1, 2, 3};
    const FrameInfo info = parse_frame(make_upload_segment(true, true, data), Sender::Server);
    EXPECT_EQ(info.kind, FrameKind::UploadSegmentResponse);
    EXPECT_TRUE(info.toggle);
    EXPECT_TRUE(info.last);
    EXPECT_EQ(info.unused, 4);
    EXPECT_EQ(info.data_len, 3);
}

TEST(SdoProtocol, BlockFramesParseByState) {
    const std::uint8_t data[] = {9, 9, 9, 9, 9, 9, 9};
    const Payload seg = make_block_segment(5, true, data);
    EXPECT_EQ(seg[0], 0x85);
    const FrameInfo in_block = parse_frame(seg, Sender::Client, true);
    EXPECT_EQ(in_block.kind, FrameKind::BlockSegment);
    EXPECT_EQ(in_block.seqno, 5);
    EXPECT_TRUE(in_block.last);
    // An abort inside a sub-block is still an abort.
    const FrameInfo abort = parse_frame(make_abort(0x1000, 0, 0x05040000), Sender::Client, true);
    EXPECT_EQ(abort.kind, FrameKind::Abort);
    EXPECT_EQ(abort.abort_code, 0x05040000U);

    const FrameInfo ack = parse_frame(make_block_download_ack(17, 40), Sender::Server);
    EXPECT_EQ(ack.kind, FrameKind::BlockDownloadAck);
    EXPECT_EQ(ack.seqno, 17);
    EXPECT_EQ(ack.block_size, 40);
    const FrameInfo end = parse_frame(make_block_upload_end(3, 0xBEEF), Sender::Server);
    EXPECT_EQ(end.kind, FrameKind::BlockUploadEndRequest);
    EXPECT_EQ(end.unused, 3);
    EXPECT_EQ(end.crc_value, 0xBEEF);
    const FrameInfo up =
        parse_frame(make_block_upload_initiate(0x1F50, 1, true, 127, 21), Sender::Client);
    EXPECT_EQ(up.kind, FrameKind::BlockUploadInitiateRequest);
    EXPECT_TRUE(up.crc);
    EXPECT_EQ(up.block_size, 127);
    EXPECT_EQ(up.pst, 21);
}

TEST(SdoProtocol, DescribesFramesForDecoders) {
    EXPECT_EQ(describe(parse_frame(make_initiate_upload(0x1018, 1), Sender::Client)),
              "initiate upload request 0x1018:01");
    EXPECT_EQ(describe(parse_frame(make_abort(0x1000, 0, 0x06020000), Sender::Server)),
              "abort 0x1000:00 0x06020000 object does not exist in the object dictionary");
    EXPECT_EQ(parse_frame(std::span<const std::uint8_t>{}, Sender::Server).kind,
              FrameKind::Invalid);
    const std::uint8_t reserved[] = {0xE0, 0, 0, 0, 0, 0, 0, 0};
    EXPECT_EQ(parse_frame(reserved, Sender::Client).kind, FrameKind::Invalid);
}

TEST(SdoError, TimeoutReadsAsOneSentence) {
    SdoError e;
    e.node = 4;
    e.index = 0x6064;
    e.direction = Direction::Upload;
    e.cause = make_error_code(SdoErrc::Timeout);
    e.timeout = std::chrono::milliseconds(1000);
    e.detail = "no response to initiate request";
    EXPECT_EQ(e.to_string(),
              "node 4: SDO upload 0x6064:00 timed out after 1000 ms (no response to initiate "
              "request)");
    EXPECT_FALSE(e.abort_code().has_value());
}

TEST(SdoError, ServerAbortNamesCodeAndText) {
    SdoError e;
    e.node = 4;
    e.index = 0x6064;
    e.direction = Direction::Upload;
    e.protocol = Protocol::Expedited;
    e.cause = make_error_code(SdoAbort::NoObject);
    e.origin = AbortOrigin::Server;
    EXPECT_EQ(e.to_string(), "node 4: SDO expedited upload 0x6064:00 aborted by server: "
                             "0x06020000 object does not exist in the object dictionary");
    EXPECT_EQ(e.abort_code(), 0x06020000U);
}

} // namespace
} // namespace codrive::sdo
