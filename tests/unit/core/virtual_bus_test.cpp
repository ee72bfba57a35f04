// SPDX-License-Identifier: Apache-2.0
// The in-process virtual network: ordering, latency, fault injection, bus-off.
#include <codrive/core/virtual_bus.hpp>

#include <gtest/gtest.h>

#include <vector>

using namespace codrive;

namespace {
struct Harness {
    FakeClock clock;
    VirtualNetwork net{clock, std::chrono::microseconds(100)};
    VirtualBus& a = net.endpoint("a");
    VirtualBus& b = net.endpoint("b");
    VirtualBus& c = net.endpoint("c");
    std::vector<Frame> got_b, got_c;
    std::vector<TimePoint> times_b;
    Harness() {
        b.set_frame_handler([this](const Frame& f, TimePoint t) {
            got_b.push_back(f);
            times_b.push_back(t);
        });
        c.set_frame_handler([this](const Frame& f, TimePoint) { got_c.push_back(f); });
    }
};
} // namespace

TEST(VirtualBus, DeliversToEveryOtherEndpointInOrderAfterLatency) {
    Harness h;
    for (std::uint8_t i = 0; i < 10; ++i) {
        ASSERT_TRUE(h.a.send(Frame::make(0x100, {i})));
    }
    EXPECT_EQ(h.net.deliver(), 0U) << "latency not yet elapsed";
    h.clock.advance(std::chrono::microseconds(100));
    EXPECT_EQ(h.net.deliver(), 10U);
    ASSERT_EQ(h.got_b.size(), 10U);
    ASSERT_EQ(h.got_c.size(), 10U);
    for (std::uint8_t i = 0; i < 10; ++i) {
        EXPECT_EQ(h.got_b[i].data[0], i);
    }
    EXPECT_EQ(h.a.stats().tx_frames, 10U);
    EXPECT_EQ(h.b.stats().rx_frames, 10U);
}

TEST(VirtualBus, SenderDoesNotSeeItsOwnFrameUnlessLoopback) {
    Harness h;
    std::vector<Frame> got_a;
    h.a.set_frame_handler([&](const Frame& f, TimePoint) { got_a.push_back(f); });
    ASSERT_TRUE(h.a.send(Frame::make(0x1, {})));
    h.clock.advance(std::chrono::milliseconds(1));
    h.net.deliver();
    EXPECT_TRUE(got_a.empty());
    h.a.set_loopback(true);
    ASSERT_TRUE(h.a.send(Frame::make(0x1, {})));
    h.clock.advance(std::chrono::milliseconds(1));
    h.net.deliver();
    EXPECT_EQ(got_a.size(), 1U);
}

TEST(VirtualBus, RepliesSentFromHandlersAreDeliveredInTheSamePass) {
    FakeClock clock;
    VirtualNetwork net(clock);
    auto& server = net.endpoint("server");
    auto& client = net.endpoint("client");
    server.set_frame_handler([&](const Frame& f, TimePoint) {
        (void)server.send(Frame::make(0x580 + (f.id & 0x7F), {0x60}));
    });
    int replies = 0;
    client.set_frame_handler([&](const Frame&, TimePoint) { ++replies; });
    ASSERT_TRUE(client.send(Frame::make(0x605, {0x40})));
    EXPECT_EQ(net.deliver(), 2U);
    EXPECT_EQ(replies, 1);
}

TEST(VirtualBus, FaultFilterDropsDelaysDuplicatesAndCorrupts) {
    Harness h;
    h.net.set_fault_filter([](const std::string& sender, const Frame& f) {
        FaultAction a;
        EXPECT_EQ(sender, "a");
        if (f.data[0] == 1) {
            a.drop = true;
        } else if (f.data[0] == 2) {
            a.delay = std::chrono::milliseconds(5);
        } else if (f.data[0] == 3) {
            a.duplicates = 2;
        } else if (f.data[0] == 4) {
            a.corrupt = true;
        }
        return a;
    });
    for (std::uint8_t i = 0; i <= 4; ++i) {
        ASSERT_TRUE(h.a.send(Frame::make(0x200, {i, 0, 0, 0})));
    }
    h.net.run_until(h.clock, h.clock.now() + std::chrono::milliseconds(10));
    ASSERT_EQ(h.got_b.size(), 6U); // 0, 3, 3, 3, corrupted 4, then the delayed 2
    EXPECT_EQ(h.got_b[0].data[0], 0);
    EXPECT_EQ(h.got_b[1].data[0], 3);
    EXPECT_EQ(h.got_b[3].data[0], 3);
    EXPECT_NE(h.got_b[4], Frame::make(0x200, {4, 0, 0, 0})) << "one bit flipped";
    EXPECT_EQ(h.got_b[5].data[0], 2) << "the delayed frame is overtaken";
    EXPECT_EQ(h.net.frames_dropped(), 1U);
}

TEST(VirtualBus, RandomRatesAreRepeatableForASeed) {
    auto run = [](std::uint64_t seed) {
        Harness h;
        FaultRates r;
        r.drop = 0.1;
        r.duplicate = 0.1;
        r.seed = seed;
        h.net.set_fault_rates(r);
        for (int i = 0; i < 1000; ++i) {
            (void)h.a.send(Frame::make(0x300, {static_cast<std::uint8_t>(i)}));
        }
        h.net.run_until(h.clock, h.clock.now() + std::chrono::milliseconds(1));
        return h.got_b.size();
    };
    EXPECT_EQ(run(7), run(7));
    const auto n = run(7);
    EXPECT_GT(n, 850U);
    EXPECT_LT(n, 1150U);
    EXPECT_NE(n, 1000U);
}

TEST(VirtualBus, BusOffFailsSendsAndReportsEvents) {
    Harness h;
    std::vector<BusEvent> events;
    h.b.set_event_handler([&](const BusEvent& e) { events.push_back(e); });
    h.net.set_bus_off(true);
    auto r = h.a.send(Frame::make(0x1, {}));
    ASSERT_FALSE(r);
    EXPECT_EQ(r.error(), CoreErrc::BusOff);
    ASSERT_EQ(events.size(), 1U);
    EXPECT_EQ(events[0].state, BusState::BusOff);
    EXPECT_EQ(to_string(events[0]), "bus state bus-off");
    h.net.set_bus_off(false);
    ASSERT_EQ(events.size(), 3U);
    EXPECT_EQ(events[1].kind, BusEvent::Kind::Restarted);
    EXPECT_EQ(events[2].state, BusState::ErrorActive);
    EXPECT_TRUE(h.a.send(Frame::make(0x1, {})));
}

TEST(VirtualBus, DisconnectedEndpointNeitherSendsNorReceives) {
    Harness h;
    h.b.set_connected(false);
    ASSERT_TRUE(h.a.send(Frame::make(0x1, {})));
    h.clock.advance(std::chrono::milliseconds(1));
    h.net.deliver();
    EXPECT_TRUE(h.got_b.empty());
    EXPECT_EQ(h.got_c.size(), 1U);
    EXPECT_EQ(h.b.send(Frame::make(0x1, {})).error(), CoreErrc::InterfaceDown);
}

TEST(VirtualBus, InvalidFrameIsRefused) {
    Harness h;
    Frame f;
    f.id = 0x900;
    EXPECT_EQ(h.a.send(f).error(), CoreErrc::InvalidFrame);
}
