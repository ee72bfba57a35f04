// SPDX-License-Identifier: Apache-2.0
// An EMCY storm (one EMCY per millisecond from one node, inhibit time 0) while SYNC runs at
// 1 ms and SDO transfers go to every node: SYNC keeps its period and no transfer is starved.
#include "fault_rig.hpp"
#include "sdo_traffic.hpp"

#include <codrive/sync/consumer.hpp>
#include <codrive/sync/period_stats.hpp>
#include <codrive/sync/producer.hpp>

#include <gtest/gtest.h>

#include <cstdio>
#include <memory>

using namespace codrive;
using namespace codrive::integration;

TEST(FaultInjection, EmcyStormNeitherDisturbsSyncNorStarvesSdo) {
    constexpr int kNodes = 4;
    constexpr std::uint64_t kCycles = 5000;
    Rig rig(kNodes);
    rig.power_on_all();
    ASSERT_EQ(rig.boot_all(), 0);

    // SYNC producer (1 ms) on its own endpoint, and a consumer watching it on another.
    VirtualBus& sync_bus = rig.net.endpoint("sync-producer");
    sync::SyncProducer producer(sync_bus);
    ASSERT_TRUE(producer.configure({.period = milliseconds(1), .counter_overflow = 16}));
    VirtualBus& monitor_bus = rig.net.endpoint("sync-monitor");
    sync::SyncConsumer consumer;
    ASSERT_TRUE(consumer.configure({.node = 0,
                                    .cob_id = cob::kSync,
                                    .cycle_period = milliseconds(1),
                                    .counter_overflow = 16}));
    sync::PeriodStats interval_error; // received interval minus the 1 ms period
    std::uint64_t sync_events = 0;
    consumer.set_handler([&](const sync::SyncEvent& e) {
        ++sync_events;
        std::printf("  SYNC event: %s\n", e.text.c_str());
    });
    TimePoint last_rx{};
    consumer.set_hook([&](const sync::SyncReception& r) {
        if (r.count > 1) {
            interval_error.add((r.time - last_rx) - milliseconds(1));
        }
        last_rx = r.time;
    });
    monitor_bus.set_frame_handler(
        [&](const Frame& f, TimePoint now) { consumer.on_frame(f, now); });
    producer.start(rig.clock.now() + milliseconds(1));
    rig.extra_timed.push_back(&producer);
    rig.extra_timed.push_back(&consumer);

    // Node 1 floods: no inhibit time (1015h = 0), one EMCY every cycle.
    MiniDevice& noisy = rig.device(1);
    noisy.emcy().set_inhibit_time(0);

    std::vector<TrafficFigures> figures(kNodes);
    std::vector<std::unique_ptr<SdoTraffic>> traffic;
    for (auto& d : rig.devices) {
        traffic.push_back(std::make_unique<SdoTraffic>(rig.master.sdo().client(d->node()), *d,
                                                       full_plan(), figures[d->node() - 1U],
                                                       d->node() * 3U));
        traffic.back()->start();
    }
    const std::uint64_t emcy_before = rig.master.emcy().received();
    rig.run_cycles(kCycles, [&](std::uint64_t cycle) {
        (void)noisy.emcy().send(
            0x2310, 0x03,
            {static_cast<std::uint8_t>(cycle), 0, 0, 0, static_cast<std::uint8_t>(cycle >> 8)},
            rig.clock.now());
        for (auto& t : traffic) {
            t->poll();
        }
        return true;
    });
    for (auto& t : traffic) {
        t->stop();
    }
    rig.run_for(seconds(3));
    producer.stop();
    rig.run_for(milliseconds(1)); // the last SYNC is still on the wire
    const std::uint64_t emcy_received = rig.master.emcy().received() - emcy_before;

    std::printf("[EMCY storm] node 1 sends 1 EMCY/ms for %llu ms; SYNC 1 ms; SDO to 4 nodes\n",
                static_cast<unsigned long long>(kCycles));
    std::printf("  EMCY sent %llu, received by the master %llu, dropped by the producer %llu\n",
                static_cast<unsigned long long>(noisy.emcy().sent()),
                static_cast<unsigned long long>(emcy_received),
                static_cast<unsigned long long>(noisy.emcy().dropped()));
    std::printf("  SYNC sent %llu, received %llu; producer error %s; received interval error "
                "%s\n",
                static_cast<unsigned long long>(producer.sent()),
                static_cast<unsigned long long>(consumer.received()),
                producer.period_error().summary().c_str(), interval_error.summary().c_str());
    for (int n = 0; n < kNodes; ++n) {
        std::printf("  node %d: %llu transfers ok (%llu bytes), %llu failed\n", n + 1,
                    static_cast<unsigned long long>(figures[n].ok),
                    static_cast<unsigned long long>(figures[n].ok_bytes),
                    static_cast<unsigned long long>(figures[n].failed));
    }

    EXPECT_EQ(noisy.emcy().sent(), kCycles);
    EXPECT_EQ(noisy.emcy().dropped(), 0U);
    EXPECT_EQ(emcy_received, kCycles);
    // SYNC: every one sent and received, on time, counter in sequence, none missing.
    EXPECT_GE(producer.sent(), kCycles);
    EXPECT_EQ(producer.skipped(), 0U);
    EXPECT_EQ(consumer.received(), producer.sent());
    EXPECT_EQ(sync_events, 0U) << "SYNC missing or counter jump";
    EXPECT_LE(producer.period_error().max(), microseconds(10));
    EXPECT_LE(interval_error.max(), microseconds(100));
    EXPECT_GE(interval_error.min(), -microseconds(100));
    // SDO: every node, the flooding one included, keeps completing transfers, all of them.
    for (int n = 0; n < kNodes; ++n) {
        EXPECT_GT(figures[n].ok, 20U) << "node " << n + 1 << " starved";
        EXPECT_EQ(figures[n].failed, 0U) << "node " << n + 1;
        EXPECT_EQ(figures[n].wrong_data, 0U);
        EXPECT_TRUE(traffic[n]->idle());
    }
}
