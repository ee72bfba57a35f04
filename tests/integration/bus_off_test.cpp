// SPDX-License-Identifier: Apache-2.0
// Bus-off on the virtual bus while SDO transfers run: transfers fail cleanly or carry on after
// the restart, nothing completes with wrong data, and the master reports the bus events.
#include "fault_rig.hpp"
#include "sdo_traffic.hpp"

#include <gtest/gtest.h>

#include <cstdio>
#include <memory>
#include <string>

using namespace codrive;
using namespace codrive::integration;

TEST(FaultInjection, BusOffDuringTransfersFailsOrResumesCleanlyAndIsReported) {
    constexpr int kNodes = 4;
    master::MasterConfig config;
    config.sdo.timeout = milliseconds(200);
    Rig rig(kNodes, config);
    rig.power_on_all();
    ASSERT_EQ(rig.boot_all(), 0);

    TrafficFigures figures;
    std::vector<std::unique_ptr<SdoTraffic>> traffic;
    for (auto& d : rig.devices) {
        traffic.push_back(std::make_unique<SdoTraffic>(rig.master.sdo().client(d->node()), *d,
                                                       full_plan(), figures, d->node() * 5U));
        traffic.back()->start();
    }
    auto poll = [&](std::uint64_t) {
        for (auto& t : traffic) {
            t->poll();
        }
        return true;
    };

    rig.run_cycles(500, poll);
    const std::uint64_t ok_before = figures.ok;
    const std::uint64_t failed_before = figures.failed;

    // 300 ms of bus-off: every controller is off the bus, frames in flight are lost.
    rig.net.set_bus_off(true);
    rig.run_cycles(300, poll);
    const std::uint64_t failed_during = figures.failed - failed_before;
    rig.net.set_bus_off(false);

    rig.run_cycles(3000, poll);
    for (auto& t : traffic) {
        t->stop();
    }
    rig.run_for(seconds(5));

    std::printf("[bus-off] 4 nodes, 300 ms bus-off during SDO traffic\n");
    std::printf("  before: %llu ok, %llu failed; during bus-off: %llu failed; after restart: "
                "%llu ok\n",
                static_cast<unsigned long long>(ok_before),
                static_cast<unsigned long long>(failed_before),
                static_cast<unsigned long long>(failed_during),
                static_cast<unsigned long long>(figures.ok - ok_before));
    print_figures("  results:", figures);
    std::string bus_texts;
    for (const auto& e : rig.events) {
        if (e.kind == master::MasterEventKind::BusEvent) {
            std::printf("  master event: %s\n", e.text.c_str());
            bus_texts += e.text + "\n";
        }
    }
    std::printf(
        "  heartbeat losses %llu, recovered %llu\n",
        static_cast<unsigned long long>(rig.count(master::MasterEventKind::HeartbeatLost)),
        static_cast<unsigned long long>(rig.count(master::MasterEventKind::HeartbeatRecovered)));

    // The master reports bus-off and the restart.
    EXPECT_NE(bus_texts.find("bus state bus-off"), std::string::npos) << bus_texts;
    EXPECT_NE(bus_texts.find("controller restarted after bus-off"), std::string::npos) << bus_texts;
    EXPECT_NE(bus_texts.find("bus state error-active"), std::string::npos) << bus_texts;
    // Transfers caught by the bus-off ended with a sentence; none delivered wrong data.
    EXPECT_GT(failed_during, 0U);
    EXPECT_EQ(figures.wrong_data, 0U);
    EXPECT_EQ(figures.bad_sentences, 0U);
    EXPECT_EQ(figures.double_callbacks, 0U);
    EXPECT_EQ(figures.callbacks, figures.submitted);
    for (auto& t : traffic) {
        EXPECT_TRUE(t->idle());
    }
    // Traffic resumed after the restart.
    EXPECT_GT(figures.ok, ok_before + 10);
    // Nodes were not rebooted by a bus-off; their heartbeats came back.
    EXPECT_EQ(rig.count(master::MasterEventKind::NodeRebooted), 0U);
    for (auto& d : rig.devices) {
        EXPECT_FALSE(rig.master.node(d->node())->heartbeat_lost()) << "node " << int(d->node());
        EXPECT_EQ(d->state(), nmt::NmtState::Operational);
    }
}
