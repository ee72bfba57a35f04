// SPDX-License-Identifier: Apache-2.0
// SDO server: dictionary checks give the CiA 301 abort codes; protocol errors are rejected.
#include "sdo_harness.hpp"

#include <codrive/sdo/crc16.hpp>
#include <codrive/sdo/protocol.hpp>

#include <gtest/gtest.h>

namespace codrive::sdo::testing {
namespace {

std::uint32_t abort_of(const std::optional<SdoResult<void>>& r) {
    return r && !*r ? r->error().abort_code().value_or(0) : 0;
}
std::uint32_t abort_of(const std::optional<SdoResult<Bytes>>& r) {
    return r && !*r ? r->error().abort_code().value_or(0) : 0;
}

TEST(SdoServer, UnknownObjectAbortsWithObjectDoesNotExist) {
    Harness h;
    auto r = h.upload(0x6064, 0);
    EXPECT_EQ(message(r), "node 4: SDO upload 0x6064:00 aborted by server: 0x06020000 object "
                          "does not exist in the object dictionary");
}

TEST(SdoServer, UnknownSubindexAborts) {
    Harness h;
    EXPECT_EQ(abort_of(h.upload(0x1018, 9)), 0x06090011U);
    EXPECT_EQ(abort_of(h.download(0x1018, 9, {1, 2, 3, 4})), 0x06090011U);
}

TEST(SdoServer, AccessRightsAreEnforced) {
    Harness h;
    EXPECT_EQ(abort_of(h.upload(0x2001, 0)), 0x06010001U);
    EXPECT_EQ(abort_of(h.download(0x1000, 0, {1, 2, 3, 4})), 0x06010002U);
    auto r = h.download(0x1008, 0, {'x'});
    EXPECT_EQ(message(r), "node 4: SDO expedited download 0x1008:00 aborted by server: "
                          "0x06010002 attempt to write a read only object");
}

TEST(SdoServer, LengthMismatchesAbort) {
    Harness h;
    EXPECT_EQ(abort_of(h.download(0x2000, 0, {1, 2})), 0x06070013U);
    EXPECT_EQ(abort_of(h.download(0x2000, 0, {1, 2, 3, 4, 5})), 0x06070012U);
    TransferOptions block;
    block.mode = Mode::Block;
    EXPECT_EQ(abort_of(h.download(0x2000, 0, pattern(9), block)), 0x06070012U);
}

TEST(SdoServer, ValueRangeIsEnforced) {
    Harness h;
    EXPECT_EQ(abort_of(h.download(0x2002, 0, {200, 0})), 0x06090031U);
    EXPECT_EQ(abort_of(h.download(0x2002, 0, {1, 0})), 0x06090032U);
    auto ok = h.download(0x2002, 0, {50, 0});
    EXPECT_TRUE(ok && *ok) << message(ok);
    EXPECT_EQ(h.od.get<std::uint16_t>(0x2002, 0), 50);
}

TEST(SdoServer, WriteHookCanRefuseAndSeesData) {
    Harness h;
    std::vector<std::uint8_t> seen;
    h.od.on_write(0x2000,
                  [&](std::uint16_t, std::uint8_t,
                      std::span<const std::uint8_t> d) -> tl::expected<void, SdoAbort> {
                      seen.assign(d.begin(), d.end());
                      if (d[0] == 0xFF) {
                          return tl::unexpected(SdoAbort::InvalidValue);
                      }
                      return {};
                  });
    auto ok = h.download(0x2000, 0, {1, 0, 0, 0});
    EXPECT_TRUE(ok && *ok) << message(ok);
    EXPECT_EQ(seen, (Bytes{1, 0, 0, 0}));
    EXPECT_EQ(abort_of(h.download(0x2000, 0, {0xFF, 0, 0, 0})), 0x06090030U);
}

TEST(SdoServer, AccessHookRefusesInThePresentState) {
    Harness h;
    h.server.set_access_hook(
        [](std::uint16_t index, std::uint8_t, Direction d) -> std::optional<SdoAbort> {
            if (index == 0x2000 && d == Direction::Download) {
                return SdoAbort::DataTransferState;
            }
            return std::nullopt;
        });
    EXPECT_EQ(abort_of(h.download(0x2000, 0, {1, 0, 0, 0})), 0x08000022U);
    auto r = h.upload(0x2000, 0);
    EXPECT_TRUE(r && *r) << message(r);
}

/// Raw frames to the server from a scripted client endpoint.
struct RawClient {
    explicit RawClient(ServerConfig config = {}) : h(config), raw(h.net.endpoint("raw")) {
        raw.set_frame_handler([this](const Frame& f, TimePoint) {
            if (f.id == 0x584) {
                responses.push_back(f);
            }
        });
    }
    void send(std::initializer_list<std::uint8_t> bytes) {
        (void)raw.send(Frame::make(0x604, bytes));
        h.net.run_until(h.clock, h.clock.now() + std::chrono::milliseconds(1), {&h.server});
    }
    void send(const Payload& p) {
        (void)raw.send(Frame::make(0x604, p));
        h.net.run_until(h.clock, h.clock.now() + std::chrono::milliseconds(1), {&h.server});
    }
    /// A client that takes its time (python-canopen in a loaded guest: over 100 ms).
    void wait(Duration d) { h.net.run_until(h.clock, h.clock.now() + d, {&h.server}); }
    [[nodiscard]] std::uint32_t last_abort() const {
        if (responses.empty() || responses.back().data[0] != 0x80) {
            return 0;
        }
        return get_le<std::uint32_t>(responses.back().data.data() + 4);
    }
    Harness h;
    VirtualBus& raw;
    std::vector<Frame> responses;
};

TEST(SdoServer, UnknownCommandSpecifierAborts) {
    RawClient c;
    c.send({0xE0, 0x00, 0x10, 0x00, 0, 0, 0, 0});
    EXPECT_EQ(c.last_abort(), 0x05040001U);
    c.send(make_upload_segment_request(false)); // no transfer running
    EXPECT_EQ(c.last_abort(), 0x05040001U);
    EXPECT_FALSE(c.h.server.busy());
}

TEST(SdoServer, WrongToggleInDownloadAborts) {
    RawClient c;
    c.send(make_initiate_download_segmented(0x2100, 0, 14));
    ASSERT_EQ(c.responses.back().data[0], 0x60);
    const std::uint8_t seg[] = {1, 2, 3, 4, 5, 6, 7};
    c.send(make_download_segment(true, false, seg)); // first segment must have t=0
    EXPECT_EQ(c.last_abort(), 0x05030000U);
    EXPECT_FALSE(c.h.server.busy());
}

TEST(SdoServer, WrongToggleInUploadAborts) {
    RawClient c;
    c.h.od.write(0x2100, 0, pattern(30));
    c.send(make_initiate_upload(0x2100, 0));
    c.send(make_upload_segment_request(false));
    c.send(make_upload_segment_request(true));
    c.send(make_upload_segment_request(false));
    c.send(make_upload_segment_request(false)); // a byte-identical repeat: ignored
    EXPECT_EQ(c.h.server.stats().repeats_ignored, 1U);
    EXPECT_EQ(c.h.server.stats().aborts_sent, 0U);
    c.send(make_initiate_upload(0x2100, 0));
    c.send(make_upload_segment_request(true)); // the first segment must have t=0
    EXPECT_EQ(c.last_abort(), 0x05030000U);
}

TEST(SdoServer, RepeatedRequestsAreIgnoredNotAborted) {
    RawClient c;
    c.h.od.write(0x2100, 0, pattern(30));
    c.send(make_block_upload_initiate(0x2100, 0, true, 127, 0));
    c.send(make_block_upload_start());
    const std::size_t after_start = c.responses.size();
    c.send(make_block_upload_start()); // repeated: no second sub-block, no abort
    EXPECT_EQ(c.responses.size(), after_start);
    c.send(make_block_upload_ack(5, 127)); // all 30 bytes acknowledged: end frame
    ASSERT_EQ(c.responses.back().data[0] & 0xE3, 0xC1);
    c.send(make_block_upload_ack(5, 127)); // a late or repeated ack after the last sub-block
    EXPECT_EQ(c.responses.back().data[0] & 0xE3, 0xC1) << "no abort";
    c.send(make_block_upload_end_response());
    EXPECT_FALSE(c.h.server.busy());
    EXPECT_EQ(c.h.server.stats().repeats_ignored, 2U);
    EXPECT_EQ(c.h.server.stats().aborts_sent, 0U);
}

TEST(SdoServer, InvalidBlockSizeAborts) {
    RawClient c;
    c.h.od.write(0x2100, 0, pattern(30));
    c.send(make_block_upload_initiate(0x2100, 0, true, 0, 0));
    EXPECT_EQ(c.last_abort(), 0x05040002U);
    c.send(make_block_upload_initiate(0x2100, 0, true, 128, 0));
    EXPECT_EQ(c.last_abort(), 0x05040002U);
}

TEST(SdoServer, InvalidSequenceNumberAborts) {
    RawClient c;
    c.send(make_block_download_initiate(0x2100, 0, true, 30));
    ASSERT_EQ(c.responses.back().data[0] & 0xE3, 0xA0);
    const std::uint8_t seg[7] = {};
    c.send(make_block_segment(0, false, seg));
    EXPECT_EQ(c.last_abort(), 0x05040003U);
}

TEST(SdoServer, InvalidAcknowledgedSequenceAborts) {
    RawClient c;
    c.h.od.write(0x2100, 0, pattern(30));
    c.send(make_block_upload_initiate(0x2100, 0, true, 127, 0));
    c.send(make_block_upload_start());
    c.send(make_block_upload_ack(9, 127)); // only 5 segments were sent
    EXPECT_EQ(c.last_abort(), 0x05040003U);
}

TEST(SdoServer, WrongCrcInBlockDownloadAborts) {
    RawClient c;
    c.send(make_block_download_initiate(0x2100, 0, true, 7));
    const std::uint8_t seg[7] = {1, 2, 3, 4, 5, 6, 7};
    c.send(make_block_segment(1, true, seg));
    EXPECT_EQ(c.responses.back().data[0], 0xA2);
    EXPECT_EQ(c.responses.back().data[1], 1);
    c.send(make_block_download_end(0, 0x1234));
    EXPECT_EQ(c.last_abort(), 0x05040004U);
    EXPECT_FALSE(c.h.server.busy());
}

TEST(SdoServer, SilentClientTimesOutAndServerRecovers) {
    RawClient c;
    c.h.od.write(0x2100, 0, pattern(30));
    c.send(make_initiate_upload(0x2100, 0));
    EXPECT_TRUE(c.h.server.busy());
    c.h.net.run_until(c.h.clock, c.h.clock.now() + std::chrono::seconds(2), {&c.h.server});
    EXPECT_EQ(c.last_abort(), 0x05040000U);
    EXPECT_FALSE(c.h.server.busy());
    EXPECT_EQ(c.h.server.stats().timeouts, 1U);
    c.send(make_initiate_upload(0x1018, 1));
    EXPECT_EQ(c.responses.back().data[0], 0x43);
}

TEST(SdoServer, ClientAbortEndsTransferQuietly) {
    RawClient c;
    c.h.od.write(0x2100, 0, pattern(30));
    c.send(make_initiate_upload(0x2100, 0));
    const auto before = c.responses.size();
    c.send(make_abort(0x2100, 0, 0x08000000));
    EXPECT_EQ(c.responses.size(), before);
    EXPECT_FALSE(c.h.server.busy());
}

// python-canopen against codrive-sim: a block download whose client sent its first segment 117 ms
// after the initiate response got the response twice (the server repeated it after 100 ms), took
// the copy for the sub-block acknowledgement and aborted with 05040001h, 3 times in 40 transfers.
// CiA 301 §7.2.4.3.9-10: one response per step, whatever the client's pace.
TEST(SdoServer, SlowBlockDownloadClientGetsEachResponseOnce) {
    ServerConfig config;
    config.block_size = 2; // two sub-blocks for 21 bytes: an acknowledgement to wait after too
    RawClient c(config);
    c.send(make_block_download_initiate(0x2100, 0, true, 21));
    ASSERT_EQ(c.responses.size(), 1U);
    EXPECT_EQ(c.responses[0].data[0], 0xA4); // CRC supported
    c.wait(std::chrono::milliseconds(300));
    EXPECT_EQ(c.responses.size(), 1U) << "the initiate response was sent again";
    const Bytes data = pattern(21);
    const std::span<const std::uint8_t> all(data);
    c.send(make_block_segment(1, false, all.subspan(0, 7)));
    c.send(make_block_segment(2, false, all.subspan(7, 7)));
    ASSERT_EQ(c.responses.size(), 2U);
    EXPECT_EQ(c.responses[1].data[0], 0xA2);
    EXPECT_EQ(c.responses[1].data[1], 2);
    c.wait(std::chrono::milliseconds(300));
    EXPECT_EQ(c.responses.size(), 2U) << "the sub-block acknowledgement was sent again";
    c.send(make_block_segment(1, true, all.subspan(14, 7)));
    ASSERT_EQ(c.responses.size(), 3U);
    EXPECT_EQ(c.responses[2].data[0], 0xA2);
    EXPECT_EQ(c.responses[2].data[1], 1);
    c.send(make_block_download_end(0, crc16_ccitt(all)));
    ASSERT_EQ(c.responses.size(), 4U);
    EXPECT_EQ(c.responses[3].data[0], 0xA1);
    const auto stored = c.h.od.read(0x2100, 0);
    ASSERT_TRUE(stored);
    EXPECT_EQ(Bytes(stored->begin(), stored->end()), data);
    EXPECT_FALSE(c.h.server.busy());
}

TEST(SdoServer, BlockResponsesAreRepeatedOnlyWhenAskedFor) {
    ServerConfig config;
    config.repeat_block_responses = true; // lossy links where a response itself may vanish
    RawClient c(config);
    c.send(make_block_download_initiate(0x2100, 0, true, 14));
    c.wait(std::chrono::milliseconds(150));
    ASSERT_EQ(c.responses.size(), 2U);
    EXPECT_EQ(c.responses[1].data, c.responses[0].data);
}

TEST(SdoServer, IgnoresFramesForOtherChannels) {
    RawClient c;
    (void)c.raw.send(Frame::make(0x605, {0x40, 0x00, 0x10, 0x00, 0, 0, 0, 0}));
    c.h.net.run_until(c.h.clock, c.h.clock.now() + std::chrono::milliseconds(1), {&c.h.server});
    EXPECT_TRUE(c.responses.empty());
}

} // namespace
} // namespace codrive::sdo::testing
