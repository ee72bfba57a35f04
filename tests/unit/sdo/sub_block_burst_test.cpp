// SPDX-License-Identifier: Apache-2.0
// Block transfers hand each sub-block to the bus in bursts (ICanBus::send_many(): one
// sendmmsg() per burst on SocketCAN), and a segment the bus refuses is named or recovered.
#include "sdo_harness.hpp"

#include <gtest/gtest.h>

namespace codrive::sdo::testing {
namespace {

constexpr std::size_t kBytes = 64 * 1024;
constexpr std::size_t kSegments = (kBytes + 6) / 7; // 9,363 segments of 7 bytes
// The receiver asks for 127 and 126 segments in turn (BlockReceiver::next_block_size), so at
// most this many sub-blocks, each in at most 4 bursts of up to 32 segments.
constexpr std::size_t kSubBlocks = (kSegments + 125) / 126;
constexpr std::size_t kBurstsPerSubBlock = 4;

TransferOptions block() {
    TransferOptions o;
    o.mode = Mode::Block;
    return o;
}

TEST(SdoSubBlockBurst, ADownloadHandsEachSubBlockToTheBusInBursts) {
    Harness h;
    const Bytes data = pattern(kBytes);
    auto w = h.download(0x2100, 0, data, block());
    ASSERT_TRUE(w && *w) << message(w);
    // Every segment went out in a burst; what went out alone is the initiate and end requests.
    EXPECT_EQ(h.client_bus.burst_frames, kSegments);
    EXPECT_LE(h.client_bus.bursts, kSubBlocks * kBurstsPerSubBlock);
    EXPECT_EQ(h.client_bus.single_sends, 2U);
    auto r = h.upload(0x2100, 0, block());
    ASSERT_TRUE(r && *r) << message(r);
    EXPECT_EQ(r->value(), data);
}

TEST(SdoSubBlockBurst, AnUploadHandsEachSubBlockToTheBusInBursts) {
    Harness h;
    const Bytes data = pattern(kBytes, 7);
    auto w = h.download(0x2100, 0, data);
    ASSERT_TRUE(w && *w) << message(w);
    h.server_bus.bursts = 0;
    h.server_bus.burst_frames = 0;
    auto r = h.upload(0x2100, 0, block());
    ASSERT_TRUE(r && *r) << message(r);
    EXPECT_EQ(r->value(), data);
    // The server's responses of one request leave together: the sub-block's segments (and each
    // single response) in bursts, never a segment on its own.
    EXPECT_GE(h.server_bus.burst_frames, kSegments);
    EXPECT_LE(h.server_bus.bursts, kSubBlocks * kBurstsPerSubBlock + kSubBlocks + 4);
    EXPECT_EQ(h.server_bus.single_sends, 0U);
}

TEST(SdoSubBlockBurst, ASegmentTheBusRefusesFailsTheDownloadNamingIt) {
    Harness h;
    // The 41st request frame: the initiate request, then segments 1..40 of the first sub-block.
    std::size_t requests = 0;
    h.client_bus.refuse = [&](const Frame&) { return ++requests == 41; };
    auto w = h.download(0x2100, 0, pattern(kBytes), block());
    ASSERT_TRUE(w);
    ASSERT_FALSE(*w);
    EXPECT_NE(message(w).find("block segment 40 refused by the bus"), std::string::npos)
        << message(w);
    EXPECT_EQ(w->error().cause, make_error_code(SdoErrc::SendFailed)) << message(w);
}

TEST(SdoSubBlockBurst, ASegmentTheServerCouldNotSendIsRepeatedAndTheUploadArrivesWhole) {
    Harness h;
    const Bytes data = pattern(kBytes, 3);
    auto w = h.download(0x2100, 0, data);
    ASSERT_TRUE(w && *w) << message(w);
    // One segment in the middle of the first burst finds the transmit queue full: the frames
    // after it still go out, the client acknowledges up to the gap and the server repeats.
    std::size_t responses = 0;
    std::size_t refused = 0;
    h.server_bus.refuse = [&](const Frame&) {
        const bool no = ++responses == 10;
        refused += no ? 1 : 0;
        return no;
    };
    auto r = h.upload(0x2100, 0, block());
    ASSERT_TRUE(r && *r) << message(r);
    EXPECT_EQ(r->value(), data);
    EXPECT_EQ(refused, 1U);
}

} // namespace
} // namespace codrive::sdo::testing
