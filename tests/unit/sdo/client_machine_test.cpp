// SPDX-License-Identifier: Apache-2.0
// SdoClientMachine on its own: the requests it makes and the replies it takes, with CAN's
// framing and with what CoE adds (normal transfer data past the 8 bytes, long segments,
// complete access; ETG.1000.6 §5.6.2).
#include <codrive/sdo/client_machine.hpp>
#include <codrive/sdo/transfer.hpp>

#include <gtest/gtest.h>

#include <numeric>

namespace codrive::sdo {
namespace {

using Step = SdoClientMachine::Step;

/// In-memory data side: what an upload wrote, what a download reads.
class Buffer final : public ISdoData {
public:
    explicit Buffer(Bytes source = {}) : source_(std::move(source)) {}
    bool begin(std::optional<std::size_t> size) override {
        announced = size;
        return accept_size;
    }
    bool write(std::span<const std::uint8_t> d) override {
        written.insert(written.end(), d.begin(), d.end());
        return true;
    }
    bool read(std::span<std::uint8_t> out) override {
        if (out.size() > source_.size() - pos_) {
            return false;
        }
        std::copy_n(source_.begin() + static_cast<long>(pos_), out.size(), out.begin());
        pos_ += out.size();
        return true;
    }
    std::optional<std::size_t> announced;
    bool accept_size = true;
    Bytes written;

private:
    Bytes source_;
    std::size_t pos_ = 0;
};

Bytes counting(std::size_t n) {
    Bytes b(n);
    std::iota(b.begin(), b.end(), std::uint8_t{1});
    return b;
}

FrameInfo server(const Payload& p) {
    return parse_frame(p, Sender::Server);
}

FrameInfo client_frame(const SdoClientMachine& m) {
    return parse_frame(m.request(), Sender::Client);
}

TEST(SdoClientMachine, CanSegmentedDownloadSendsSevenBytesASegmentWithAlternatingToggles) {
    Buffer data(counting(10));
    SdoClientMachine m(data, SdoFraming{}, 0x2000, 0);
    ASSERT_EQ(m.begin_download(10, true), Step::Send);
    EXPECT_EQ(client_frame(m).kind, FrameKind::InitiateDownloadRequest);
    EXPECT_EQ(client_frame(m).size, 10U);
    EXPECT_TRUE(m.request_extra().empty());
    ASSERT_EQ(m.on_reply(server(make_initiate_download_response(0x2000, 0))), Step::Send);
    auto seg = client_frame(m);
    EXPECT_EQ(seg.kind, FrameKind::DownloadSegmentRequest);
    EXPECT_FALSE(seg.toggle);
    EXPECT_FALSE(seg.last);
    EXPECT_EQ(seg.data_len, 7);
    ASSERT_EQ(m.on_reply(server(make_download_segment_response(false))), Step::Send);
    seg = client_frame(m);
    EXPECT_TRUE(seg.toggle);
    EXPECT_TRUE(seg.last);
    EXPECT_EQ(seg.data_len, 3);
    EXPECT_EQ(m.on_reply(server(make_download_segment_response(true))), Step::Done);
    EXPECT_EQ(m.done(), 10U);
}

TEST(SdoClientMachine, CoeNormalTransferCarriesTheDataInTheInitiateRequest) {
    Buffer data(counting(20));
    SdoFraming coe;
    coe.initiate_room = 100;
    coe.segment_room = 100;
    SdoClientMachine m(data, coe, 0x1C12, 0);
    ASSERT_EQ(m.begin_download(20, true), Step::Send);
    EXPECT_EQ(client_frame(m).size, 20U);
    ASSERT_EQ(m.request_extra().size(), 20U);
    EXPECT_EQ(m.request_extra()[19], 20);
    EXPECT_EQ(m.on_reply(server(make_initiate_download_response(0x1C12, 0))), Step::Done);
}

TEST(SdoClientMachine, CoeSegmentsCarryTheMailboxRoomAfterTheFrame) {
    Buffer data(counting(50));
    SdoFraming coe;
    coe.initiate_room = 10;
    coe.segment_room = 30;
    SdoClientMachine m(data, coe, 0x2100, 0);
    ASSERT_EQ(m.begin_download(50, true), Step::Send);
    EXPECT_EQ(m.request_extra().size(), 10U);
    ASSERT_EQ(m.on_reply(server(make_initiate_download_response(0x2100, 0))), Step::Send);
    EXPECT_EQ(client_frame(m).data_len, 7);
    EXPECT_EQ(client_frame(m).data[0], 11);
    EXPECT_EQ(m.request_extra().size(), 23U); // 30 in all: 7 in the frame, 23 after it
    EXPECT_FALSE(client_frame(m).last);
    ASSERT_EQ(m.on_reply(server(make_download_segment_response(false))), Step::Send);
    EXPECT_TRUE(client_frame(m).last);
    EXPECT_EQ(client_frame(m).data_len, 7);
    EXPECT_EQ(m.request_extra().size(), 3U);
    EXPECT_EQ(m.request_extra().back(), 50);
    EXPECT_EQ(m.on_reply(server(make_download_segment_response(true))), Step::Done);
}

TEST(SdoClientMachine, CoeUploadTakesTheWholeDataFromTheInitiateResponseAndDropsPadding) {
    Buffer data;
    SdoClientMachine m(data, SdoFraming{}, 0x1008, 0);
    ASSERT_EQ(m.begin_upload(), Step::Send);
    const Bytes after = {'A', 'K', 'D', '2', 'G', 0, 0, 0}; // 5 bytes + mailbox padding
    EXPECT_EQ(m.on_reply(server(make_initiate_upload_segmented(0x1008, 0, 5)), after), Step::Done);
    EXPECT_EQ(data.written, Bytes({'A', 'K', 'D', '2', 'G'}));
    EXPECT_EQ(data.announced, 5U);
}

TEST(SdoClientMachine, CoeUploadSegmentLongerThanSevenBytesCountsEveryByte) {
    Buffer data;
    SdoClientMachine m(data, SdoFraming{}, 0x2100, 0);
    ASSERT_EQ(m.begin_upload(), Step::Send);
    ASSERT_EQ(m.on_reply(server(make_initiate_upload_segmented(0x2100, 0, 12))), Step::Send);
    const Bytes first7 = counting(7);
    const Bytes rest = {8, 9, 10, 11, 12};
    EXPECT_EQ(m.on_reply(server(make_upload_segment(false, true, first7)), rest), Step::Done);
    EXPECT_EQ(data.written, counting(12));
}

TEST(SdoClientMachine, CompleteAccessSetsItsBitAndTakesTheAnswerFromSubIndexZero) {
    Buffer data;
    SdoFraming coe;
    coe.complete_access = true;
    SdoClientMachine m(data, coe, 0x1C12, 1);
    ASSERT_EQ(m.begin_upload(), Step::Send);
    EXPECT_EQ(m.request()[0] & kCompleteAccessBit, kCompleteAccessBit);
    const std::array<std::uint8_t, 2> v = {0x00, 0x16};
    EXPECT_EQ(m.on_reply(server(make_initiate_upload_expedited(0x1C12, 0, v))), Step::Done);
}

TEST(SdoClientMachine, ASinkThatRefusesTheSizeAbortsWithDataTransfer) {
    Buffer data;
    data.accept_size = false;
    SdoClientMachine m(data, SdoFraming{}, 0x2100, 0);
    ASSERT_EQ(m.begin_upload(), Step::Send);
    EXPECT_EQ(m.on_reply(server(make_initiate_upload_segmented(0x2100, 0, 1000))), Step::Failed);
    ASSERT_TRUE(m.failure().abort);
    EXPECT_EQ(*m.failure().abort, 0x08000020U);
    EXPECT_EQ(m.request(), make_abort(0x2100, 0, 0x08000020U));
    EXPECT_EQ(m.failure().detail, "the local data sink refused the size");
}

TEST(SdoClientMachine, ASourceThatFailsBeforeAnythingWasSentAbortsNothing) {
    Buffer data(counting(2)); // says 4, has 2
    SdoClientMachine m(data, SdoFraming{}, 0x2000, 0);
    EXPECT_EQ(m.begin_download(4, true), Step::Failed);
    EXPECT_FALSE(m.failure().abort);
    EXPECT_EQ(m.failure().cause, make_error_code(SdoErrc::LocalTransferError));
}

TEST(SdoClientMachine, AnAbortCodeZeroIsAProtocolErrorNotSuccess) {
    Buffer data;
    SdoClientMachine m(data, SdoFraming{}, 0x2000, 0);
    ASSERT_EQ(m.begin_upload(), Step::Send);
    EXPECT_EQ(m.on_reply(server(make_abort(0x2000, 0, 0))), Step::Failed);
    EXPECT_EQ(m.failure().cause, make_error_code(SdoErrc::ProtocolError));
    EXPECT_EQ(m.failure().origin, AbortOrigin::Server);
}

TEST(SdoClientMachine, RepliesAfterTheEndAreIgnored) {
    Buffer data;
    SdoClientMachine m(data, SdoFraming{}, 0x2000, 0);
    ASSERT_EQ(m.begin_upload(), Step::Send);
    const std::array<std::uint8_t, 1> v = {7};
    ASSERT_EQ(m.on_reply(server(make_initiate_upload_expedited(0x2000, 0, v))), Step::Done);
    EXPECT_EQ(m.on_reply(server(make_initiate_upload_expedited(0x2000, 0, v))), Step::Ignore);
    EXPECT_EQ(data.written, Bytes({7}));
}

} // namespace
} // namespace codrive::sdo
