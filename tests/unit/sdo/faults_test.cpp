// SPDX-License-Identifier: Apache-2.0
// Fault injection: every failure ends in success, abort or timeout, with the right sentence.
#include "sdo_harness.hpp"

#include <codrive/sdo/protocol.hpp>

#include <gtest/gtest.h>

namespace codrive::sdo::testing {
namespace {

bool is_block_segment_from(const std::string& sender, const std::string& who, const Frame& f,
                           std::uint32_t id) {
    return sender == who && f.id == id;
}

TEST(SdoClientFaults, DroppedRequestTimesOutWithSentence) {
    Harness h;
    h.net.set_fault_filter([](const std::string& sender, const Frame&) {
        FaultAction a;
        a.drop = sender == "master";
        return a;
    });
    const TimePoint start = h.clock.now();
    auto r = h.upload(0x6064, 0);
    EXPECT_EQ(message(r), "node 4: SDO upload 0x6064:00 timed out after 1000 ms (no response to "
                          "initiate request)");
    EXPECT_EQ(r->error().cause, make_error_code(SdoErrc::Timeout));
    EXPECT_GE(h.clock.now() - start, std::chrono::milliseconds(1000));
}

TEST(SdoClientFaults, DroppedExpeditedRequestIsRetried) {
    ClientConfig cc;
    cc.retries = 2;
    Harness h({}, cc);
    int dropped = 0;
    h.net.set_fault_filter([&](const std::string& sender, const Frame&) {
        FaultAction a;
        a.drop = sender == "master" && dropped++ < 2;
        return a;
    });
    auto r = h.upload(0x1018, 1);
    ASSERT_TRUE(r && *r) << message(r);
    EXPECT_EQ(h.client.stats().retries, 2U);
}

TEST(SdoClientFaults, DroppedResponseMidSegmentedUploadTimesOut) {
    Harness h;
    h.od.write(0x2100, 0, pattern(100));
    int responses = 0;
    h.net.set_fault_filter([&](const std::string& sender, const Frame&) {
        FaultAction a;
        a.drop = sender == "node" && ++responses == 3; // initiate, segment 1, [segment 2]
        return a;
    });
    auto r = h.upload(0x2100, 0);
    EXPECT_EQ(message(r), "node 4: SDO segmented upload 0x2100:00 timed out after 1000 ms (no "
                          "response to segment request after 7 of 100 bytes)");
    EXPECT_FALSE(h.server.busy()); // our abort 0x05040000 reset it
}

TEST(SdoClientFaults, CustomTimeoutIsReported) {
    Harness h;
    h.node.set_connected(false);
    TransferOptions o;
    o.timeout = std::chrono::milliseconds(250);
    auto r = h.download(0x2000, 0, {1, 2, 3, 4}, o);
    EXPECT_EQ(message(r), "node 4: SDO expedited download 0x2000:00 timed out after 250 ms (no "
                          "response to initiate request)");
}

TEST(SdoClientFaults, DroppedBlockDownloadSegmentIsRetransmitted) {
    Harness h;
    int seen = 0;
    h.net.set_fault_filter([&](const std::string& sender, const Frame& f) {
        FaultAction a;
        // Drop the 5th block segment of the first sub-block (frame 2 is the initiate request).
        a.drop = is_block_segment_from(sender, "master", f, 0x604) && ++seen == 6;
        return a;
    });
    TransferOptions o;
    o.mode = Mode::Block;
    const Bytes data = pattern(3000);
    auto w = h.download(0x2100, 0, data, o);
    ASSERT_TRUE(w && *w) << message(w);
    EXPECT_EQ(h.od.find(0x2100, 0)->value.bytes().size(), data.size());
    EXPECT_TRUE(std::equal(data.begin(), data.end(), h.od.find(0x2100, 0)->value.bytes().begin()));
    EXPECT_GT(h.client.stats().retransmitted_segments, 0U);
}

TEST(SdoClientFaults, DroppedLastSegmentOfSubBlockIsRecovered) {
    // The receiver never sees seqno == blksize: its gap timer acknowledges early.
    Harness h;
    int seen = 0;
    h.net.set_fault_filter([&](const std::string& sender, const Frame& f) {
        FaultAction a;
        a.drop = is_block_segment_from(sender, "master", f, 0x604) && ++seen == 128;
        return a;
    });
    TransferOptions o;
    o.mode = Mode::Block;
    const Bytes data = pattern(2000);
    auto w = h.download(0x2100, 0, data, o);
    ASSERT_TRUE(w && *w) << message(w);
    EXPECT_TRUE(std::equal(data.begin(), data.end(), h.od.find(0x2100, 0)->value.bytes().begin()));
}

TEST(SdoClientFaults, SegmentsDelayedPastAnEarlyAckAreNotAcceptedTwice) {
    // A slow sender: the server's gap timer acknowledges early, then the rest of the sub-block
    // arrives late (in order, as on a real bus). Those stale segments must be dropped, not
    // taken as the start of the next sub-block.
    Harness h;
    int seen = 0;
    h.net.set_fault_filter([&](const std::string& sender, const Frame& f) {
        FaultAction a;
        if (sender == "master" && f.id == 0x604 && ++seen > 50) {
            a.delay = std::chrono::milliseconds(150); // every later frame: order is kept
        }
        return a;
    });
    TransferOptions o;
    o.mode = Mode::Block;
    const Bytes data = pattern(4000);
    auto w = h.download(0x2100, 0, data, o);
    ASSERT_TRUE(w && *w) << message(w);
    EXPECT_GE(h.server.stats().early_acks, 1U);
    const auto stored = h.od.find(0x2100, 0)->value.bytes();
    ASSERT_EQ(stored.size(), data.size());
    EXPECT_TRUE(std::equal(data.begin(), data.end(), stored.begin()));
}

TEST(SdoClientFaults, SlowServerSubBlockIsNotAcceptedTwiceInUpload) {
    Harness h;
    const Bytes data = pattern(4000);
    h.od.write(0x2100, 0, data);
    int seen = 0;
    h.net.set_fault_filter([&](const std::string& sender, const Frame& f) {
        FaultAction a;
        if (sender == "node" && f.id == 0x584 && ++seen > 60) {
            a.delay = std::chrono::milliseconds(150);
        }
        return a;
    });
    TransferOptions o;
    o.mode = Mode::Block;
    auto r = h.upload(0x2100, 0, o);
    ASSERT_TRUE(r && *r) << message(r);
    EXPECT_EQ(r->value(), data);
    EXPECT_GE(h.client.stats().early_acks, 1U);
}

TEST(SdoClientFaults, DroppedBlockUploadSegmentIsRetransmitted) {
    Harness h;
    const Bytes data = pattern(5000);
    h.od.write(0x2100, 0, data);
    int seen = 0;
    h.net.set_fault_filter([&](const std::string& sender, const Frame& f) {
        FaultAction a;
        const bool segment = sender == "node" && f.id == 0x584;
        ++seen;
        a.drop = segment && (seen == 10 || seen == 130); // mid sub-block, and a sub-block's last
        return a;
    });
    TransferOptions o;
    o.mode = Mode::Block;
    auto r = h.upload(0x2100, 0, o);
    ASSERT_TRUE(r && *r) << message(r);
    EXPECT_EQ(r->value(), data);
}

TEST(SdoClientFaults, CorruptedCrcInBlockUploadIsRejectedByClient) {
    Harness h;
    h.od.write(0x2100, 0, pattern(100));
    h.server_bus.mutate = [](Frame& f) {
        if ((f.data[0] & 0xE3) == 0xC1) { // block upload end request
            f.data[1] ^= 0x01;
        }
        return true;
    };
    TransferOptions o;
    o.mode = Mode::Block;
    auto r = h.upload(0x2100, 0, o);
    ASSERT_TRUE(r && !*r);
    EXPECT_EQ(r->error().abort_code(), 0x05040004U);
    EXPECT_EQ(r->error().origin, AbortOrigin::Client);
    EXPECT_NE(message(r).find("node 4: SDO block upload 0x2100:00 aborted by client: 0x05040004 "
                              "CRC error (block mode only) (CRC 0x"),
              std::string::npos)
        << message(r);
    EXPECT_FALSE(h.server.busy());
}

TEST(SdoClientFaults, CorruptedCrcInBlockDownloadIsRejectedByServer) {
    Harness h;
    h.client_bus.mutate = [](Frame& f) {
        if (f.data[0] == 0xC1 || (f.data[0] & 0xE3) == 0xC1) { // block download end request
            f.data[2] ^= 0x80;
        }
        return true;
    };
    TransferOptions o;
    o.mode = Mode::Block;
    auto w = h.download(0x2100, 0, pattern(100), o);
    EXPECT_EQ(message(w), "node 4: SDO block download 0x2100:00 aborted by server: 0x05040004 "
                          "CRC error (block mode only)");
}

TEST(SdoClientFaults, CorruptedBlockDataIsCaughtByCrc) {
    Harness h;
    int seen = 0;
    h.client_bus.mutate = [&](Frame& f) {
        if (++seen == 4) { // a block segment: flip a data bit, keep the sequence number
            f.data[3] ^= 0x10;
        }
        return true;
    };
    TransferOptions o;
    o.mode = Mode::Block;
    auto w = h.download(0x2100, 0, pattern(100), o);
    ASSERT_TRUE(w && !*w);
    EXPECT_EQ(w->error().abort_code(), 0x05040004U);
}

// Every frame in both directions arrives twice (a CAN controller repeats a frame after an ACK
// error). Both sides recognise the copies (docs/sdo.md, "Duplicated, late and reordered
// responses"): every protocol completes byte-exact, nothing is aborted.
TEST(SdoClientFaults, EveryFrameDuplicatedStillCompletesEveryProtocolByteExact) {
    Harness h;
    h.net.set_fault_filter([](const std::string&, const Frame&) {
        FaultAction a;
        a.duplicates = 1;
        return a;
    });
    for (std::size_t size : {std::size_t{4}, std::size_t{100}, std::size_t{2000}}) {
        for (Mode mode : {Mode::Auto, Mode::Segmented, Mode::Block}) {
            TransferOptions o;
            o.mode = mode;
            const Bytes data = pattern(size, static_cast<std::uint8_t>(size));
            h.net.clear_recorded();
            h.net.set_recording(true);
            auto w = h.download(0x2100, 0, data, o);
            if (!(w && *w)) {
                for (const Frame& f : h.net.recorded()) {
                    std::printf("  %s\n", to_string(f).c_str());
                }
            }
            ASSERT_TRUE(w && *w) << size << " bytes: " << message(w);
            const auto stored = h.od.find(0x2100, 0)->value.bytes();
            EXPECT_TRUE(std::equal(data.begin(), data.end(), stored.begin(), stored.end()))
                << size << " bytes, download mode " << static_cast<int>(mode);
            auto r = h.upload(0x2100, 0, o);
            ASSERT_TRUE(r && *r) << size << " bytes: " << message(r);
            EXPECT_EQ(r->value(), data) << size << " bytes, upload mode " << static_cast<int>(mode);
        }
    }
    EXPECT_EQ(h.client.stats().failed, 0U);
    EXPECT_GT(h.client.stats().stale_responses, 0U);
    EXPECT_GT(h.server.stats().repeats_ignored, 0U);
    EXPECT_EQ(h.server.stats().aborts_sent, 0U);
}

// A late answer to an earlier transfer (here: to a read of another object whose response
// arrives while the next read waits) is ignored, not taken as the answer.
TEST(SdoClientFaults, LateResponseForAnotherObjectIsIgnoredAndTheRightAnswerTaken) {
    Harness h;
    VirtualBus& other = h.net.endpoint("other");
    int initiates = 0;
    h.net.set_fault_filter([&](const std::string& sender, const Frame& f) {
        FaultAction a;
        if (sender == "master" && f.id == 0x604 && f.data[0] == 0x40 && ++initiates == 1) {
            // A stale expedited answer for 0x1018:02 crosses the request on the bus.
            (void)other.send(Frame::make(0x584, {0x43, 0x18, 0x10, 0x02, 0xEE, 0xEE, 0xEE, 0xEE}));
        }
        return a;
    });
    auto r = h.upload(0x1018, 1);
    ASSERT_TRUE(r && *r) << message(r);
    EXPECT_EQ(r->value().size(), 4U);
    EXPECT_NE(r->value(), (Bytes{0xEE, 0xEE, 0xEE, 0xEE}));
    EXPECT_EQ(h.client.stats().stale_responses, 1U);
}

TEST(SdoClientFaults, WrongToggleFromServerAborts) {
    Harness h;
    h.od.write(0x2100, 0, pattern(30));
    int segments = 0;
    h.server_bus.mutate = [&](Frame& f) {
        if ((f.data[0] >> 5) == 0 && ++segments == 2) {
            f.data[0] ^= 0x10;
        }
        return true;
    };
    auto r = h.upload(0x2100, 0);
    EXPECT_EQ(message(r), "node 4: SDO segmented upload 0x2100:00 aborted by client: 0x05030000 "
                          "toggle bit not alternated (segment after 7 of 30 bytes had toggle 0, "
                          "expected 1)");
    EXPECT_FALSE(h.server.busy());
}

TEST(SdoClientFaults, WrongToggleInDownloadResponseAborts) {
    Harness h;
    h.server_bus.mutate = [](Frame& f) {
        if ((f.data[0] >> 5) == 1) {
            f.data[0] ^= 0x10;
        }
        return true;
    };
    auto w = h.download(0x2100, 0, pattern(20));
    ASSERT_TRUE(w && !*w);
    EXPECT_EQ(w->error().abort_code(), 0x05030000U);
}

TEST(SdoClientFaults, ServerAbortMidTransferIsReported) {
    Harness h;
    h.server.set_domain_upload(0x2200, 0, [](std::uint16_t, std::uint8_t) {
        DomainReader reader;
        reader.size = 1000;
        reader.read = [pos = std::size_t{0}](
                          std::span<std::uint8_t> out) mutable -> tl::expected<void, SdoAbort> {
            pos += out.size();
            if (pos > 50) {
                return tl::unexpected(SdoAbort::HardwareError);
            }
            return {};
        };
        return reader;
    });
    auto r = h.upload(0x2200, 0);
    EXPECT_EQ(message(r), "node 4: SDO segmented upload 0x2200:00 aborted by server: 0x06060000 "
                          "access failed due to a hardware error");
    TransferOptions o;
    o.mode = Mode::Block;
    auto b = h.upload(0x2200, 0, o);
    ASSERT_TRUE(b && !*b);
    EXPECT_EQ(b->error().abort_code(), 0x06060000U);
    EXPECT_EQ(b->error().origin, AbortOrigin::Server);
}

TEST(SdoClientFaults, NodeRebootDuringTransferEndsIt) {
    Harness h;
    h.od.write(0x2100, 0, pattern(1000));
    TransferOptions o;
    bool rebooted = false;
    o.progress = [&](std::size_t done, std::optional<std::size_t>) {
        if (done >= 21 && !rebooted) {
            rebooted = true;
            (void)h.node.send(Frame::make(0x704, {0x00}));
        }
    };
    auto r = h.upload(0x2100, 0, o);
    EXPECT_EQ(message(r), "node 4: SDO segmented upload 0x2100:00 failed: the node rebooted "
                          "during the transfer (boot-up message received after 21 of 1000 bytes)");
    EXPECT_EQ(r->error().cause, make_error_code(SdoErrc::NodeRebooted));
    // The next request works (the node is up again).
    auto next = h.upload(0x1018, 1);
    EXPECT_TRUE(next && *next) << message(next);
}

TEST(SdoClientFaults, ReplyForDifferentObjectAborts) {
    Harness h;
    h.server_bus.mutate = [](Frame& f) {
        if ((f.data[0] >> 5) == 2) {
            f.data[3] = 2; // answer for sub 2
        }
        return true;
    };
    h.net.set_recording(true);
    auto r = h.upload(0x1018, 1);
    EXPECT_EQ(message(r), "node 4: SDO upload 0x1018:01 failed: response for a different object "
                          "(server answered for 0x1018:02 instead of 0x1018:01)");
    EXPECT_EQ(r->error().cause, make_error_code(SdoErrc::WrongObject));
    ASSERT_FALSE(h.net.recorded().empty());
    EXPECT_EQ(h.net.recorded().back().data[0], 0x80); // the client aborted
}

TEST(SdoClientFaults, UnknownServerCommandAborts) {
    Harness h;
    h.server_bus.mutate = [](Frame& f) {
        f.data[0] = 0xE0;
        return true;
    };
    auto r = h.upload(0x1018, 1);
    ASSERT_TRUE(r && !*r);
    EXPECT_EQ(r->error().abort_code(), 0x05040001U);
    EXPECT_EQ(r->error().origin, AbortOrigin::Client);
}

TEST(SdoClientFaults, InvalidBlockSizeFromServerAborts) {
    Harness h;
    h.server_bus.mutate = [](Frame& f) {
        if (f.data[0] == 0xA4 || f.data[0] == 0xA0) { // block download initiate response
            f.data[4] = 0;
        }
        return true;
    };
    TransferOptions o;
    o.mode = Mode::Block;
    auto w = h.download(0x2100, 0, pattern(50), o);
    ASSERT_TRUE(w && !*w);
    EXPECT_EQ(w->error().abort_code(), 0x05040002U);
}

TEST(SdoClientFaults, InvalidAckSequenceFromServerAborts) {
    Harness h;
    h.server_bus.mutate = [](Frame& f) {
        if (f.data[0] == 0xA2) {
            f.data[1] = 100;
        }
        return true;
    };
    TransferOptions o;
    o.mode = Mode::Block;
    auto w = h.download(0x2100, 0, pattern(50), o);
    ASSERT_TRUE(w && !*w);
    EXPECT_EQ(w->error().abort_code(), 0x05040003U);
}

/// A block upload whose upload start (the client's second request, cs 5 / 0xA3) is lost once.
/// Returns the transfer's result and how often the client sent the start.
std::pair<std::optional<SdoResult<Bytes>>, int> upload_with_lost_start(ClientConfig config) {
    Harness h({}, config);
    const Bytes data = pattern(2000);
    h.od.write(0x2100, 0, data);
    int starts = 0;
    h.net.set_fault_filter([&](const std::string& sender, const Frame& f) {
        FaultAction a;
        if (sender == "master" && f.id == 0x604 && f.len >= 1 && f.data[0] == 0xA3) {
            a.drop = ++starts == 1;
        }
        return a;
    });
    TransferOptions o;
    o.mode = Mode::Block;
    auto r = h.upload(0x2100, 0, o);
    return {std::move(r), starts};
}

TEST(SdoClientFaults, ALostBlockUploadStartIsNotRepeatedUnlessAskedFor) {
    // CiA 301 §7.2.4.3.14: one start request per transfer. By default the client does not send
    // it again (a slow server would read the copy as its next request): the transfer times out
    // with its sentence.
    auto [r, starts] = upload_with_lost_start({});
    ASSERT_TRUE(r.has_value());
    ASSERT_FALSE(*r);
    EXPECT_EQ(starts, 1);
    EXPECT_NE(message(r).find("timed out"), std::string::npos) << message(r);
}

TEST(SdoClientFaults, ALostBlockUploadStartIsRepeatedWhenAskedFor) {
    ClientConfig config;
    config.repeat_block_responses = true; // a lossy link where a response itself may vanish
    auto [r, starts] = upload_with_lost_start(config);
    ASSERT_TRUE(r && *r) << message(r);
    EXPECT_EQ(r->value(), pattern(2000));
    EXPECT_EQ(starts, 2);
}

TEST(SdoClientFaults, RandomLossNeverHangs) {
    // Whatever is lost, every transfer ends within its timeouts.
    for (std::uint64_t seed = 1; seed <= 20; ++seed) {
        Harness h;
        FaultRates rates;
        rates.drop = 0.02;
        rates.seed = seed;
        h.net.set_fault_rates(rates);
        TransferOptions o;
        o.mode = seed % 2 == 0 ? Mode::Block : Mode::Auto;
        auto w = h.download(0x2100, 0, pattern(3000), o);
        ASSERT_TRUE(w.has_value()) << "seed " << seed;
        auto r = h.upload(0x2100, 0, o);
        ASSERT_TRUE(r.has_value()) << "seed " << seed;
        if (*w && *r) {
            EXPECT_EQ(r->value(), pattern(3000));
        }
        h.net.set_fault_rates({});
        h.run(std::chrono::seconds(5));
        EXPECT_FALSE(h.server.busy()) << "seed " << seed;
        EXPECT_FALSE(h.client.busy()) << "seed " << seed;
    }
}

} // namespace
} // namespace codrive::sdo::testing
