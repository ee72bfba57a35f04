// SPDX-License-Identifier: Apache-2.0
// Client <-> server on the virtual bus: every protocol, both directions, byte-exact, many sizes.
#include "sdo_harness.hpp"

#include <gtest/gtest.h>

#include <vector>

#include <fmt/format.h>

namespace codrive::sdo::testing {
namespace {

struct Case {
    Mode mode;
    std::size_t size;
};

std::string case_name(const ::testing::TestParamInfo<Case>& info) {
    const char* mode = info.param.mode == Mode::Auto        ? "Auto"
                       : info.param.mode == Mode::Segmented ? "Segmented"
                                                            : "Block";
    return fmt::format("{}_{}", mode, info.param.size);
}

class SdoRoundTrip : public ::testing::TestWithParam<Case> {
protected:
    static ServerConfig server_config() {
        ServerConfig c;
        // Segmented mode must segment even small uploads: the server decides that.
        c.expedited_upload = GetParam().mode != Mode::Segmented;
        return c;
    }
    static TransferOptions options() {
        TransferOptions o;
        o.mode = GetParam().mode;
        return o;
    }
};

TEST_P(SdoRoundTrip, DownloadThenUploadIsByteExact) {
    Harness h(server_config());
    const Bytes data = pattern(GetParam().size);
    auto w = h.download(0x2100, 0, data, options());
    ASSERT_TRUE(w.has_value());
    ASSERT_TRUE(w->has_value()) << message(w);
    const SubObject* sub = h.od.find(0x2100, 0);
    ASSERT_NE(sub, nullptr);
    EXPECT_TRUE(
        std::equal(sub->value.bytes().begin(), sub->value.bytes().end(), data.begin(), data.end()));
    auto r = h.upload(0x2100, 0, options());
    ASSERT_TRUE(r.has_value());
    ASSERT_TRUE(r->has_value()) << message(r);
    EXPECT_EQ(r->value().size(), data.size());
    EXPECT_TRUE(r->value() == data);
    EXPECT_FALSE(h.server.busy());
    EXPECT_FALSE(h.client.busy());
    EXPECT_EQ(h.server.stats().aborts_sent, 0U);
}

TEST_P(SdoRoundTrip, StreamedUploadAndDownloadAreByteExact) {
    Harness h(server_config());
    const Bytes data = pattern(GetParam().size, 7);
    std::optional<SdoResult<void>> w;
    h.client.download(
        0x2100, 0, bytes_source(data), [&](SdoResult<void> r) { w = r; }, options());
    h.run();
    ASSERT_TRUE(w && *w) << message(w);
    Bytes got;
    std::optional<std::size_t> announced;
    UploadSink sink;
    sink.begin = [&](std::optional<std::size_t> size) {
        announced = size;
        return true;
    };
    sink.write = [&](std::span<const std::uint8_t> d) {
        got.insert(got.end(), d.begin(), d.end());
        return true;
    };
    std::optional<SdoResult<void>> r;
    h.client.upload(
        0x2100, 0, sink, [&](SdoResult<void> x) { r = x; }, options());
    h.run();
    ASSERT_TRUE(r && *r) << message(r);
    EXPECT_TRUE(got == data);
    ASSERT_TRUE(announced.has_value());
    EXPECT_EQ(*announced, data.size());
}

INSTANTIATE_TEST_SUITE_P(
    AllProtocols, SdoRoundTrip, ::testing::ValuesIn([] {
        std::vector<Case> cases;
        for (Mode m : {Mode::Auto, Mode::Segmented, Mode::Block}) {
            for (std::size_t n : {0UL, 1UL, 4UL, 5UL, 7UL, 8UL, 889UL, 65536UL, 1048576UL}) {
                cases.push_back({m, n});
            }
        }
        return cases;
    }()),
    case_name);

TEST(SdoRoundTrip, ExpeditedDownloadIsOneRequestAndOneResponse) {
    Harness h;
    h.net.set_recording(true);
    auto w = h.download(0x2000, 0, {1, 2, 3, 4});
    ASSERT_TRUE(w && *w) << message(w);
    ASSERT_EQ(h.net.recorded().size(), 2U);
    EXPECT_EQ(h.net.recorded()[0].data[0], 0x23); // ccs 1, n 0, e 1, s 1
    EXPECT_EQ(h.net.recorded()[1].data[0], 0x60);
    EXPECT_EQ(h.od.get<std::uint32_t>(0x2000, 0), 0x04030201U);
}

TEST(SdoRoundTrip, ExpeditedUploadIsOneRequestAndOneResponse) {
    Harness h;
    h.net.set_recording(true);
    auto r = h.upload(0x1018, 1);
    ASSERT_TRUE(r && *r) << message(r);
    ASSERT_EQ(h.net.recorded().size(), 2U);
    EXPECT_EQ(h.net.recorded()[1].data[0], 0x43); // scs 2, n 0, e 1, s 1
    EXPECT_EQ(r->value(), (Bytes{0x78, 0x56, 0x34, 0x12}));
}

TEST(SdoRoundTrip, BlockUploadBelowSwitchThresholdFallsBackToSegmented) {
    Harness h;
    h.od.write(0x2100, 0, pattern(20));
    h.net.set_recording(true);
    TransferOptions o;
    o.mode = Mode::Block;
    o.pst = 32;
    auto r = h.upload(0x2100, 0, o);
    ASSERT_TRUE(r && *r) << message(r);
    EXPECT_EQ(r->value(), pattern(20));
    // initiate (block) → initiate upload response (scs 2, segmented) → 3 segment exchanges.
    EXPECT_EQ(h.net.recorded().size(), 8U);
    EXPECT_EQ(h.net.recorded()[1].data[0] >> 5, 2);
}

TEST(SdoRoundTrip, BlockTransferUsesNegotiatedBlockSize) {
    ServerConfig sc;
    sc.block_size = 10;
    Harness h(sc);
    h.net.set_recording(true);
    TransferOptions o;
    o.mode = Mode::Block;
    const Bytes data = pattern(200);
    auto w = h.download(0x2100, 0, data, o);
    ASSERT_TRUE(w && *w) << message(w);
    // 200 bytes = 29 segments. The server asks for 9 and 10 segments in turn (two successive
    // acknowledgements always differ, so a repeated one is recognised): sub-blocks of 10, 9, 10.
    std::vector<int> asked;
    for (const Frame& f : h.net.recorded()) {
        if (f.id == 0x584 && f.data[0] == 0xA2) {
            asked.push_back(f.data[2]);
        }
    }
    EXPECT_EQ(asked, (std::vector<int>{9, 10, 9}));
    o.block_size = 5;
    h.net.clear_recorded();
    auto r = h.upload(0x2100, 0, o);
    ASSERT_TRUE(r && *r) << message(r);
    EXPECT_EQ(r->value(), data);
    std::size_t uploads_acks = 0;
    for (const Frame& f : h.net.recorded()) {
        if (f.id == 0x604 && f.data[0] == 0xA2) {
            ++uploads_acks;
        }
    }
    EXPECT_EQ(uploads_acks, 7U); // 29 segments in sub-blocks of 5, 4, 5, 4, 5, 4, 2
}

TEST(SdoRoundTrip, SixteenMebibyteDomainStreamsThroughHooksInBlockMode) {
    Harness h;
    constexpr std::size_t kSize = 16U * 1024U * 1024U;
    // The server generates the domain on the fly; nothing holds 16 MiB.
    h.server.set_domain_upload(0x2200, 0, [](std::uint16_t, std::uint8_t) {
        DomainReader reader;
        reader.size = kSize;
        reader.read = [pos = std::size_t{0}](
                          std::span<std::uint8_t> out) mutable -> tl::expected<void, SdoAbort> {
            for (auto& b : out) {
                b = static_cast<std::uint8_t>((pos * 13U) >> 3);
                ++pos;
            }
            return {};
        };
        return reader;
    });
    std::size_t received = 0;
    bool intact = true;
    UploadSink sink;
    sink.write = [&](std::span<const std::uint8_t> d) {
        for (const std::uint8_t b : d) {
            intact = intact && b == static_cast<std::uint8_t>((received * 13U) >> 3);
            ++received;
        }
        return true;
    };
    TransferOptions o;
    o.mode = Mode::Block;
    std::optional<SdoResult<void>> r;
    h.client.upload(
        0x2200, 0, sink, [&](SdoResult<void> x) { r = x; }, o);
    h.run();
    ASSERT_TRUE(r && *r) << message(r);
    EXPECT_EQ(received, kSize);
    EXPECT_TRUE(intact);
}

TEST(SdoRoundTrip, DomainDownloadHookReceivesDataInPieces) {
    Harness h;
    std::size_t pieces = 0;
    Bytes got;
    bool finished = false;
    h.server.set_domain_download(
        0x2300, 0,
        [&](std::uint16_t, std::uint8_t,
            std::optional<std::size_t> size) -> tl::expected<DomainWriter, SdoAbort> {
            EXPECT_EQ(size, 5000U);
            DomainWriter w;
            w.write = [&](std::span<const std::uint8_t> d) -> tl::expected<void, SdoAbort> {
                ++pieces;
                got.insert(got.end(), d.begin(), d.end());
                return {};
            };
            w.finish = [&]() -> tl::expected<void, SdoAbort> {
                finished = true;
                return {};
            };
            return w;
        });
    TransferOptions o;
    o.mode = Mode::Block;
    auto w = h.download(0x2300, 0, pattern(5000), o);
    ASSERT_TRUE(w && *w) << message(w);
    EXPECT_TRUE(finished);
    EXPECT_EQ(got, pattern(5000));
    EXPECT_GT(pieces, 1U);
}

} // namespace
} // namespace codrive::sdo::testing
