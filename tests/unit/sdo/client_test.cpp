// SPDX-License-Identifier: Apache-2.0
// SDO client: queueing, typed API, cancellation, unrelated frames, many nodes in parallel.
#include "sdo_harness.hpp"

#include <codrive/sdo/client_manager.hpp>

#include <gtest/gtest.h>

#include <fmt/format.h>
#include <memory>

namespace codrive::sdo::testing {
namespace {

TEST(SdoClient, TypedReadDecodesLittleEndian) {
    Harness h;
    std::optional<SdoResult<std::uint32_t>> vendor;
    h.client.read<std::uint32_t>(0x1018, 1, [&](SdoResult<std::uint32_t> r) { vendor = r; });
    std::optional<SdoResult<std::string>> name;
    h.client.read<std::string>(0x1008, 0, [&](SdoResult<std::string> r) { name = r; });
    h.run();
    ASSERT_TRUE(vendor && *vendor);
    EXPECT_EQ(**vendor, 0x12345678U);
    ASSERT_TRUE(name && *name);
    EXPECT_EQ(**name, "codrive test");
}

TEST(SdoClient, TypedReadOfWrongSizeFails) {
    Harness h;
    std::optional<SdoResult<std::uint16_t>> r;
    h.client.read<std::uint16_t>(0x1018, 1, [&](SdoResult<std::uint16_t> x) { r = x; });
    h.run();
    ASSERT_TRUE(r && !*r);
    EXPECT_EQ(r->error().cause, make_error_code(SdoErrc::SizeMismatch));
    EXPECT_EQ(r->error().to_string(),
              "node 4: SDO upload 0x1018:01 failed: the object size does not match the requested "
              "type (object has 4 bytes, the requested type 2)");
}

TEST(SdoClient, TypedWriteEncodesLittleEndian) {
    Harness h;
    std::optional<SdoResult<void>> w;
    h.client.write<std::uint32_t>(0x2000, 0, 0xCAFEBABEU, [&](SdoResult<void> r) { w = r; });
    std::optional<SdoResult<void>> s;
    h.client.write<std::string>(0x2100, 0, std::string("hello domain"),
                                [&](SdoResult<void> r) { s = r; });
    h.run();
    ASSERT_TRUE(w && *w) << message(w);
    EXPECT_EQ(h.od.get<std::uint32_t>(0x2000, 0), 0xCAFEBABEU);
    ASSERT_TRUE(s && *s) << message(s);
    EXPECT_EQ(h.od.find(0x2100, 0)->value.size(), 12U);
}

TEST(SdoClient, QueuedRequestsRunOneAtATimeInOrder) {
    Harness h;
    h.net.set_recording(true);
    std::vector<int> order;
    for (int i = 0; i < 5; ++i) {
        h.client.upload(0x1018, 1, [&order, i](SdoResult<Bytes> r) {
            EXPECT_TRUE(r.has_value());
            order.push_back(i);
        });
    }
    EXPECT_EQ(h.client.queued(), 4U);
    h.run();
    EXPECT_EQ(order, (std::vector<int>{0, 1, 2, 3, 4}));
    // Strict request/response alternation: never two requests in flight.
    const auto& frames = h.net.recorded();
    ASSERT_EQ(frames.size(), 10U);
    for (std::size_t i = 0; i < frames.size(); ++i) {
        EXPECT_EQ(frames[i].id, i % 2 == 0 ? 0x604U : 0x584U);
    }
}

TEST(SdoClient, CallbackMaySubmitTheNextRequest) {
    Harness h;
    std::optional<SdoResult<Bytes>> second;
    h.client.upload(0x1018, 1, [&](SdoResult<Bytes>) {
        h.client.upload(0x1018, 2, [&](SdoResult<Bytes> r) { second = std::move(r); });
    });
    h.run();
    ASSERT_TRUE(second && *second);
    EXPECT_EQ(second->value(), (Bytes{2, 0, 0, 0}));
}

TEST(SdoClient, CancelQueuedAndRunningTransfers) {
    Harness h;
    h.node.set_connected(false);
    std::optional<SdoResult<Bytes>> a;
    std::optional<SdoResult<Bytes>> b;
    const auto ida = h.client.upload(0x1018, 1, [&](SdoResult<Bytes> r) { a = std::move(r); });
    const auto idb = h.client.upload(0x1018, 2, [&](SdoResult<Bytes> r) { b = std::move(r); });
    EXPECT_TRUE(h.client.cancel(idb));
    ASSERT_TRUE(b && !*b);
    EXPECT_EQ(b->error().cause, make_error_code(SdoErrc::Cancelled));
    EXPECT_TRUE(h.client.cancel(ida));
    ASSERT_TRUE(a && !*a);
    EXPECT_FALSE(h.client.cancel(ida));
    EXPECT_FALSE(h.client.busy());
}

TEST(SdoClient, CancelAllEndsEveryTransferOnceAndStartsNone) {
    Harness h;
    h.node.set_connected(false); // the node never answers
    h.net.set_recording(true);
    std::vector<std::string> ended;
    auto note = [&ended](const SdoError& e) { ended.push_back(e.to_string()); };
    h.client.upload(0x1018, 1, [&](SdoResult<Bytes> r) {
        ASSERT_FALSE(r);
        note(r.error());
        // An application that submits again from its callback: ended too, never sent.
        h.client.upload(0x1018, 4, [&](SdoResult<Bytes> r2) {
            ASSERT_FALSE(r2);
            note(r2.error());
        });
    });
    h.client.write<std::uint32_t>(0x2000, 0, 7U, [&](SdoResult<void> r) {
        ASSERT_FALSE(r);
        EXPECT_EQ(r.error().cause, make_error_code(SdoErrc::Cancelled));
        note(r.error());
    });
    h.run(std::chrono::milliseconds(1));
    ASSERT_EQ(h.net.recorded().size(), 1U) << "one request out, the second queued";
    EXPECT_EQ(h.client.cancel_all("the controller shut down before the node answered"), 3U);
    EXPECT_EQ(ended, (std::vector<std::string>{
                         "node 4: SDO upload 0x1018:01 failed: cancelled (the controller shut down "
                         "before the node answered)",
                         "node 4: SDO download 0x2000:00 failed: cancelled (the controller shut "
                         "down before the node answered)",
                         "node 4: SDO upload 0x1018:04 failed: cancelled (the controller shut down "
                         "before the node answered)"}));
    EXPECT_FALSE(h.client.busy());
    EXPECT_EQ(h.client.queued(), 0U);
    EXPECT_EQ(h.client.next_deadline(), kNever);
    h.run(std::chrono::seconds(2)); // far past the timeout: no callback runs twice
    EXPECT_EQ(ended.size(), 3U);
    const auto& frames = h.net.recorded();
    ASSERT_EQ(frames.size(), 2U) << "the running request and its abort; nothing else started";
    EXPECT_EQ(frames[1].id, 0x604U);
    EXPECT_EQ(frames[1].data[0], 0x80U);
    EXPECT_EQ(get_le<std::uint32_t>(frames[1].data.data() + 4), 0x08000000U);
    // The client goes on afterwards.
    h.node.set_connected(true);
    auto r = h.upload(0x1018, 1);
    EXPECT_TRUE(r && *r) << message(r);
}

TEST(SdoClient, CountsUnrelatedAndLateFrames) {
    Harness h;
    VirtualBus& other = h.net.endpoint("other");
    (void)other.send(Frame::make(0x181, {1, 2}));
    (void)other.send(Frame::make(0x584, {0x60, 0, 0, 0, 0, 0, 0, 0})); // nothing running
    h.run(std::chrono::milliseconds(1));
    EXPECT_EQ(h.client.stats().frames_ignored, 1U);
    EXPECT_EQ(h.client.stats().unexpected_responses, 1U);
    auto r = h.upload(0x1018, 1);
    EXPECT_TRUE(r && *r);
}

TEST(SdoClient, ToleratesUnrelatedFramesDuringTransfer) {
    Harness h;
    h.od.write(0x2100, 0, pattern(300));
    VirtualBus& other = h.net.endpoint("other");
    TransferOptions o;
    o.progress = [&](std::size_t, std::optional<std::size_t>) {
        (void)other.send(Frame::make(0x185, {1, 2, 3}));
        (void)other.send(Frame::make(0x080, {}));
    };
    auto r = h.upload(0x2100, 0, o);
    ASSERT_TRUE(r && *r) << message(r);
    EXPECT_EQ(r->value(), pattern(300));
    EXPECT_GT(h.client.stats().frames_ignored, 10U);
}

TEST(SdoClientManager, NodesRunInParallelWithAQueueEach) {
    FakeClock clock;
    VirtualNetwork net(clock, std::chrono::milliseconds(1));
    VirtualBus& master = net.endpoint("master");
    std::vector<std::unique_ptr<ObjectDictionary>> ods;
    std::vector<std::unique_ptr<SdoServer>> servers;
    std::vector<ITimed*> timed;
    for (NodeId n = 1; n <= 3; ++n) {
        VirtualBus& ep = net.endpoint(fmt::format("node{}", n));
        ods.push_back(std::make_unique<ObjectDictionary>());
        add_test_objects(*ods.back());
        ServerConfig sc;
        sc.node = n;
        servers.push_back(std::make_unique<SdoServer>(*ods.back(), ep, sc));
        SdoServer* s = servers.back().get();
        ep.set_frame_handler([s](const Frame& f, TimePoint t) { s->on_frame(f, t); });
        timed.push_back(s);
    }
    SdoClientManager manager(master, clock);
    master.set_frame_handler([&](const Frame& f, TimePoint t) { manager.on_frame(f, t); });
    timed.push_back(&manager);

    int done = 0;
    const TimePoint start = clock.now();
    for (NodeId n = 1; n <= 3; ++n) {
        for (int i = 0; i < 4; ++i) {
            manager.client(n).write<std::uint32_t>(0x2000, 0, 100U * n + static_cast<unsigned>(i),
                                                   [&](SdoResult<void> r) {
                                                       EXPECT_TRUE(r.has_value());
                                                       ++done;
                                                   });
        }
    }
    EXPECT_TRUE(manager.busy());
    net.run_until(clock, clock.now() + std::chrono::seconds(1), timed);
    EXPECT_EQ(done, 12);
    EXPECT_FALSE(manager.busy());
    for (NodeId n = 1; n <= 3; ++n) {
        EXPECT_EQ(ods[n - 1]->get<std::uint32_t>(0x2000, 0), 100U * n + 3);
    }
    (void)start;
}

TEST(SdoClientManager, TimeoutOfOneNodeDoesNotDelayOthers) {
    FakeClock clock;
    VirtualNetwork net(clock);
    VirtualBus& master = net.endpoint("master");
    VirtualBus& ep = net.endpoint("node2");
    ObjectDictionary od;
    add_test_objects(od);
    ServerConfig sc;
    sc.node = 2;
    SdoServer server(od, ep, sc);
    ep.set_frame_handler([&](const Frame& f, TimePoint t) { server.on_frame(f, t); });
    SdoClientManager manager(master, clock);
    master.set_frame_handler([&](const Frame& f, TimePoint t) { manager.on_frame(f, t); });
    std::optional<SdoResult<Bytes>> dead;
    std::optional<TimePoint> alive_at;
    manager.client(9).upload(0x1000, 0, [&](SdoResult<Bytes> r) { dead = std::move(r); });
    manager.client(2).upload(0x1000, 0, [&](SdoResult<Bytes>) { alive_at = clock.now(); });
    const TimePoint start = clock.now();
    net.run_until(clock, start + std::chrono::seconds(2), {&manager, &server});
    ASSERT_TRUE(alive_at.has_value());
    EXPECT_EQ(*alive_at, start);
    ASSERT_TRUE(dead && !*dead);
    EXPECT_EQ(dead->error().node, 9);
}

TEST(SdoClient, CancelAllEndsWhenACallbackResubmitsOnEveryFailure) {
    Harness h;
    h.node.set_connected(false);
    int failures = 0;
    std::function<void(SdoResult<Bytes>)> again = [&](SdoResult<Bytes> r) {
        if (!r) {
            ++failures;
            h.client.upload(0x1018, 1, again); // a retry loop written the simple way
        }
    };
    h.client.upload(0x1018, 1, again);
    EXPECT_EQ(h.client.cancel_all("shut down"), 65U) << "the transfer and 64 resubmitted ones";
    EXPECT_EQ(failures, 65);
    EXPECT_EQ(h.client.queued(), 1U) << "the 65th resubmission waits for the next tick";
    EXPECT_LE(h.client.next_deadline(), h.clock.now());
    EXPECT_EQ(h.client.cancel_all("shut down"), 65U);
}

TEST(SdoClientManager, CancelAllEndsTheTransfersOfEveryNode) {
    FakeClock clock;
    VirtualNetwork net(clock);
    VirtualBus& master = net.endpoint("master");
    SdoClientManager manager(master, clock);
    int ended = 0;
    for (NodeId n : {NodeId{3}, NodeId{9}}) {
        for (int i = 0; i < 2; ++i) {
            manager.client(n).upload(0x1000, 0, [&ended](SdoResult<Bytes> r) {
                EXPECT_EQ(r.error().cause, make_error_code(SdoErrc::Cancelled));
                ++ended;
            });
        }
    }
    EXPECT_EQ(manager.cancel_all("shut down"), 4U);
    EXPECT_EQ(ended, 4);
    EXPECT_FALSE(manager.busy());
    EXPECT_EQ(manager.next_deadline(), kNever);
}

} // namespace
} // namespace codrive::sdo::testing
