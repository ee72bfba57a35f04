// SPDX-License-Identifier: Apache-2.0
// Master engine ↔ device engine over the virtual bus, configured over SDO.
#include "pdo_rig.hpp"

#include <gtest/gtest.h>

using namespace codrive;
using namespace codrive::pdo;
using namespace codrive::pdo::test;

namespace {

std::vector<PdoConfig> loopback_config() {
    PdoConfig event_status = tpdo(2, {entry(0x6041, 0, 16), entry(0x6064, 0, 32)}, 255);
    event_status.comm.inhibit_time = 20; // 2 ms
    event_status.comm.event_timer = 10;
    return {rpdo(1, {entry(0x2000, 0, 32), entry(0x6040, 0, 16)}, 1),
            rpdo(2, {entry(0x607A, 0, 32)}, 255),
            tpdo(1, {entry(0x2001, 0, 32), entry(0x6061, 0, 8)}, 1), event_status};
}

} // namespace

TEST(PdoEndToEnd, ConfiguredOverSdoThenExchangesEverySyncWithNothingMissing) {
    Rig rig(5);
    const auto cfg = loopback_config();
    auto configured = rig.configure(cfg);
    ASSERT_TRUE(configured) << configured.error().message;

    // The device echoes 2000h into 2001h and reports the target position as actual position.
    rig.device->set_rpdo_hook([&](unsigned n, TimePoint) {
        if (n == 1) {
            rig.od.set<std::uint32_t>(0x2001, 0, *rig.od.get<std::uint32_t>(0x2000, 0));
        } else {
            rig.od.set<std::int32_t>(0x6064, 0, *rig.od.get<std::int32_t>(0x607A, 0));
            rig.device->notify_changed();
        }
    });
    rig.device->set_operational(true, rig.clock.now());

    ProcessImage& img = **rig.master->add_node(5, cfg);
    const Slot out_counter = *img.slot(0x2000, 0);
    const Slot cw = *img.slot(0x6040, 0);
    const Slot target = *img.slot(0x607A, 0);
    const Slot echo = *img.slot(0x2001, 0);
    const Slot actual = *img.slot(0x6064, 0);
    std::vector<std::string> events;
    rig.master->set_event_handler([&](const PdoEvent& e) { events.push_back(to_string(e)); });

    std::uint32_t mismatches = 0;
    constexpr std::uint32_t kCycles = 1000;
    for (std::uint32_t k = 1; k <= kCycles; ++k) {
        img.set<std::uint32_t>(out_counter, k);
        img.set<std::uint16_t>(cw, 0x000F);
        if (k % 100 == 0) {
            img.set<std::int32_t>(target, static_cast<std::int32_t>(k) * 10);
        }
        ASSERT_TRUE(rig.master_bus.send(Frame::make(0x80, {})));
        rig.master->on_sync(k, rig.clock.now());
        rig.run(milliseconds(1));
        // TPDO1 at SYNC k carries what RPDO1 delivered after SYNC k−1 (applied at SYNC k).
        if (k > 1 && img.get<std::uint32_t>(echo) != k - 1) {
            ++mismatches;
        }
    }
    rig.run(milliseconds(5)); // past TPDO2's inhibit time
    EXPECT_EQ(mismatches, 0U);
    EXPECT_TRUE(events.empty()) << events.front();
    EXPECT_EQ(rig.device->received(1), kCycles - 1); // the last RPDO1 waits for its SYNC
    EXPECT_EQ(img.count(echo), kCycles);
    EXPECT_EQ(img.get<std::int32_t>(actual), 10000);
    EXPECT_EQ(rig.od.get<std::uint16_t>(0x6040, 0), 0x000F);
    // Event TPDO2: sent on each of the 10 target changes plus its 10 ms event timer.
    EXPECT_GE(img.count(actual), 100U);
    EXPECT_LE(img.count(actual), 112U);
}

TEST(PdoEndToEnd, DeviceGoingSilentIsReportedAfterTheSync) {
    Rig rig(5);
    const auto cfg = loopback_config();
    ASSERT_TRUE(rig.configure(cfg));
    rig.device->set_operational(true, rig.clock.now());
    ASSERT_TRUE(rig.master->add_node(5, cfg));
    std::vector<std::string> events;
    rig.master->set_event_handler([&](const PdoEvent& e) { events.push_back(to_string(e)); });
    for (std::uint64_t k = 1; k <= 10; ++k) {
        if (k == 6) {
            rig.device->set_operational(false); // e.g. NMT stop
        }
        ASSERT_TRUE(rig.master_bus.send(Frame::make(0x80, {})));
        rig.master->on_sync(k, rig.clock.now());
        rig.run(milliseconds(1));
    }
    ASSERT_FALSE(events.empty());
    EXPECT_EQ(events.front(), "node 5: TPDO1 (0x185) missing after SYNC 6 (expected every SYNC)");
}
