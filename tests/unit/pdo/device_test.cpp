// SPDX-License-Identifier: Apache-2.0
// DevicePdo: write checks with their abort codes, every transmission type, inhibit and timers.
#include "pdo_rig.hpp"

#include <gtest/gtest.h>

using namespace codrive;
using namespace codrive::pdo;
using namespace codrive::pdo::test;

namespace {

/// Applies a configuration with local OD writes (the hooks run as for SDO writes).
void setup(Rig& rig, const PdoConfig& p) {
    for (const auto& w : configuration_writes(rig.node, p, rig.quirks)) {
        auto ok = rig.od.write(w.index, w.subindex, w.data);
        ASSERT_TRUE(ok) << to_string(w) << " aborted 0x" << std::hex
                        << static_cast<std::uint32_t>(ok.error());
    }
}

std::uint32_t abort_of(const tl::expected<void, SdoAbort>& r) {
    return r ? 0U : static_cast<std::uint32_t>(r.error());
}

template <typename T>
std::uint32_t write(Rig& rig, std::uint16_t index, std::uint8_t sub, T v) {
    std::uint8_t b[sizeof(T)];
    put_le<T>(b, v);
    return abort_of(rig.od.write(index, sub, {b, sizeof(T)}));
}

void sync(Rig& rig, std::uint8_t counter = 0) {
    if (counter == 0) {
        ASSERT_TRUE(rig.master_bus.send(Frame::make(0x80, {})));
    } else {
        ASSERT_TRUE(rig.master_bus.send(Frame::make(0x80, {counter})));
    }
    rig.run(microseconds(100));
}

std::size_t count_id(const Rig& rig, std::uint32_t id) {
    std::size_t n = 0;
    for (const auto& f : rig.rx) {
        n += f.id == id && !f.rtr() ? 1 : 0;
    }
    return n;
}

} // namespace

TEST(DevicePdoWrites, MappingWhileValidIsRefusedWithDeviceState) {
    Rig rig(3);
    // TPDO1 is valid by default (predefined COB-ID, bit 31 clear).
    EXPECT_EQ(write<std::uint8_t>(rig, 0x1A00, 0, 0), 0x08000022U);
    EXPECT_EQ(write<std::uint32_t>(rig, 0x1800, 1, 0xC0000183), 0U);
    EXPECT_EQ(write<std::uint8_t>(rig, 0x1A00, 0, 0), 0U);
}

TEST(DevicePdoWrites, EntriesOnlyWhileCountIsZero) {
    Rig rig(3);
    setup(rig, tpdo(1, {entry(0x6041, 0, 16)}, 1));
    EXPECT_EQ(write<std::uint32_t>(rig, 0x1800, 1, 0xC0000183), 0U);
    EXPECT_EQ(write<std::uint32_t>(rig, 0x1A00, 2, 0x60640020), 0x08000022U);
}

TEST(DevicePdoWrites, UnmappableEntriesAndOverlongMappingsAreRefused) {
    Rig rig(3);
    EXPECT_EQ(write<std::uint32_t>(rig, 0x1800, 1, 0xC0000183), 0U);
    EXPECT_EQ(write<std::uint8_t>(rig, 0x1A00, 0, 0), 0U);
    EXPECT_EQ(write<std::uint32_t>(rig, 0x1A00, 1, 0x607A0020), 0x06040041U); // RPDO-only
    EXPECT_EQ(write<std::uint32_t>(rig, 0x1A00, 1, 0x60620020), 0x06040041U); // not mappable
    EXPECT_EQ(write<std::uint32_t>(rig, 0x1A00, 1, 0x60410020), 0x06040041U); // wrong length
    EXPECT_EQ(write<std::uint32_t>(rig, 0x1A00, 1, 0x60640020), 0U);
    EXPECT_EQ(write<std::uint32_t>(rig, 0x1A00, 2, 0x606C0020), 0U);
    EXPECT_EQ(write<std::uint32_t>(rig, 0x1A00, 3, 0x60410010), 0U);
    EXPECT_EQ(write<std::uint8_t>(rig, 0x1A00, 0, 3), 0x06040042U);  // 80 bits
    EXPECT_EQ(write<std::uint8_t>(rig, 0x1A00, 0, 65), 0x06090030U); // more than entries
    EXPECT_EQ(write<std::uint8_t>(rig, 0x1A00, 0, 2), 0U);
}

TEST(DevicePdoWrites, CommunicationParameterRules) {
    Rig rig(3);
    // COB-ID change of a valid PDO, restricted id, reserved and RPDO-RTR types.
    EXPECT_EQ(write<std::uint32_t>(rig, 0x1800, 1, 0x40000190), 0x06090030U);
    EXPECT_EQ(write<std::uint32_t>(rig, 0x1800, 1, 0x40000601), 0x06090030U);
    EXPECT_EQ(write<std::uint8_t>(rig, 0x1800, 2, 245), 0x06090030U);
    EXPECT_EQ(write<std::uint8_t>(rig, 0x1400, 2, 252), 0x06090030U);
    // Inhibit time and SYNC start value only while invalid.
    EXPECT_EQ(write<std::uint16_t>(rig, 0x1800, 3, 10), 0x06090030U);
    EXPECT_EQ(write<std::uint8_t>(rig, 0x1800, 6, 2), 0x06090030U);
    EXPECT_EQ(write<std::uint16_t>(rig, 0x1800, 5, 10), 0U); // event timer: any time
    EXPECT_EQ(write<std::uint32_t>(rig, 0x1800, 1, 0xC0000190), 0U);
    EXPECT_EQ(write<std::uint16_t>(rig, 0x1800, 3, 10), 0U);
    EXPECT_EQ(write<std::uint32_t>(rig, 0x1800, 1, 0x40000190), 0U);
}

TEST(DevicePdoWrites, DsBvsCobIdIsReadOnlyAndMappingOnlyInPreOperational) {
    Rig rig(1, quirks::ds_bvs());
    EXPECT_EQ(write<std::uint32_t>(rig, 0x1800, 1, 0xC0000181), 0x06010002U);
    EXPECT_EQ(write<std::uint8_t>(rig, 0x1800, 2, 253), 0x06090030U); // no RTR
    rig.device->set_operational(true);
    EXPECT_EQ(write<std::uint8_t>(rig, 0x1A00, 0, 0), 0x08000022U);
    rig.device->set_operational(false);
    EXPECT_EQ(write<std::uint8_t>(rig, 0x1A00, 0, 0), 0U);
}

TEST(DevicePdoTransmission, Type1SendsOnEverySync) {
    Rig rig(3);
    setup(rig, tpdo(1, {entry(0x6041, 0, 16), entry(0x6064, 0, 32)}, 1));
    rig.od.set<std::uint16_t>(0x6041, 0, 0x0637);
    rig.od.set<std::int32_t>(0x6064, 0, -2);
    rig.device->set_operational(true);
    for (int i = 0; i < 5; ++i) {
        sync(rig);
    }
    EXPECT_EQ(count_id(rig, 0x183), 5U);
    EXPECT_EQ(to_string(rig.rx.back()), "183#3706FEFFFFFF");
}

TEST(DevicePdoTransmission, TypeNSendsOnEveryNthSync) {
    Rig rig(3);
    setup(rig, tpdo(2, {entry(0x6041, 0, 16)}, 3));
    rig.device->set_operational(true);
    for (int i = 0; i < 9; ++i) {
        sync(rig);
    }
    EXPECT_EQ(count_id(rig, 0x283), 3U);
}

TEST(DevicePdoTransmission, SyncStartValueDelaysTheFirstTransmission) {
    Rig rig(3);
    PdoConfig p = tpdo(1, {entry(0x6041, 0, 16)}, 2);
    p.comm.sync_start = 3;
    setup(rig, p);
    rig.device->set_operational(true);
    std::vector<int> sent_at;
    for (std::uint8_t c = 1; c <= 8; ++c) {
        const auto before = count_id(rig, 0x183);
        sync(rig, c);
        if (count_id(rig, 0x183) > before) {
            sent_at.push_back(c);
        }
    }
    EXPECT_EQ(sent_at, (std::vector<int>{3, 5, 7}));
}

TEST(DevicePdoTransmission, Type0SendsOnTheSyncAfterAChange) {
    Rig rig(3);
    setup(rig, tpdo(1, {entry(0x6041, 0, 16)}, 0));
    rig.device->set_operational(true);
    sync(rig); // initial value
    sync(rig);
    sync(rig);
    EXPECT_EQ(count_id(rig, 0x183), 1U);
    rig.od.set<std::uint16_t>(0x6041, 0, 7);
    rig.run(milliseconds(1));
    EXPECT_EQ(count_id(rig, 0x183), 1U); // not before the SYNC
    sync(rig);
    EXPECT_EQ(count_id(rig, 0x183), 2U);
    rig.device->trigger(1, rig.clock.now()); // application event without a change
    sync(rig);
    EXPECT_EQ(count_id(rig, 0x183), 3U);
}

TEST(DevicePdoTransmission, Type252SamplesAtSyncAndAnswersRtr) {
    Rig rig(3);
    PdoConfig p = tpdo(1, {entry(0x6041, 0, 16)}, 252);
    p.comm.rtr_allowed = true;
    setup(rig, p);
    rig.device->set_operational(true);
    rig.od.set<std::uint16_t>(0x6041, 0, 0x1111);
    sync(rig);
    EXPECT_EQ(count_id(rig, 0x183), 0U);
    rig.od.set<std::uint16_t>(0x6041, 0, 0x2222);
    ASSERT_TRUE(rig.master->add_node(3, std::vector<PdoConfig>{p}));
    ASSERT_TRUE(rig.master->request(3, 1));
    rig.run(milliseconds(1));
    ASSERT_EQ(count_id(rig, 0x183), 1U);
    EXPECT_EQ(to_string(rig.rx.back()), "183#1111"); // the value sampled at the SYNC
}

TEST(DevicePdoTransmission, Type253SendsCurrentDataOnRtrOnly) {
    Rig rig(3);
    PdoConfig p = tpdo(1, {entry(0x6041, 0, 16)}, 253);
    p.comm.rtr_allowed = true;
    setup(rig, p);
    rig.device->set_operational(true);
    sync(rig);
    rig.od.set<std::uint16_t>(0x6041, 0, 0x3333);
    rig.run(milliseconds(5));
    EXPECT_EQ(count_id(rig, 0x183), 0U);
    ASSERT_TRUE(rig.master_bus.send(Frame::make_rtr(0x183, 2)));
    rig.run(milliseconds(1));
    ASSERT_EQ(count_id(rig, 0x183), 1U);
    EXPECT_EQ(to_string(rig.rx.back()), "183#3333");
}

TEST(DevicePdoTransmission, RtrIsRefusedWhenCobIdForbidsIt) {
    Rig rig(3);
    setup(rig, tpdo(1, {entry(0x6041, 0, 16)}, 1)); // bit 30 set
    rig.device->set_operational(true);
    std::vector<std::string> events;
    rig.device->set_event_handler(
        [&](const DevicePdoEvent& e) { events.push_back(to_string(e, 3)); });
    ASSERT_TRUE(rig.master_bus.send(Frame::make_rtr(0x183, 2)));
    rig.run(milliseconds(1));
    EXPECT_EQ(count_id(rig, 0x183), 0U);
    ASSERT_EQ(events.size(), 1U);
    EXPECT_EQ(events[0], "node 3: TPDO1 (0x183) requested by RTR, but its COB-ID forbids RTR "
                         "(bit 30)");
}

TEST(DevicePdoTransmission, EventDrivenHonoursInhibitTime) {
    Rig rig(3);
    PdoConfig p = tpdo(1, {entry(0x6041, 0, 16)}, 255);
    p.comm.inhibit_time = 100; // 10 ms
    setup(rig, p);
    rig.device->set_operational(true);
    const TimePoint first = rig.clock.now();
    rig.run(microseconds(100));
    ASSERT_EQ(count_id(rig, 0x183), 1U); // initial transmission
    for (int i = 1; i <= 5; ++i) {       // a change every ms
        rig.od.set<std::uint16_t>(0x6041, 0, static_cast<std::uint16_t>(i));
        rig.device->notify_changed();
        rig.run(milliseconds(1));
    }
    EXPECT_EQ(count_id(rig, 0x183), 1U); // held back
    rig.run(milliseconds(6));
    ASSERT_EQ(count_id(rig, 0x183), 2U);
    EXPECT_EQ(to_string(rig.rx.back()), "183#0500"); // the latest value, once
    EXPECT_GE(rig.clock.now() - first, milliseconds(10));
    rig.run(milliseconds(50));
    EXPECT_EQ(count_id(rig, 0x183), 2U); // nothing changed, no event timer
}

TEST(DevicePdoTransmission, EventTimerSendsPeriodically) {
    Rig rig(3);
    PdoConfig p = tpdo(1, {entry(0x6041, 0, 16)}, 254);
    p.comm.event_timer = 10;
    setup(rig, p);
    rig.device->set_operational(true);
    rig.run(milliseconds(95));
    // t=0 (initial), then every 10 ms: 10, 20, ..., 90.
    EXPECT_EQ(count_id(rig, 0x183), 10U);
}

TEST(DevicePdoTransmission, NothingIsSentOutsideOperational) {
    Rig rig(3);
    setup(rig, tpdo(1, {entry(0x6041, 0, 16)}, 1));
    sync(rig);
    sync(rig);
    EXPECT_EQ(count_id(rig, 0x183), 0U);
}

TEST(DevicePdoReception, SynchronousRpdoIsAppliedAtTheNextSync) {
    Rig rig(3);
    setup(rig, rpdo(1, {entry(0x6040, 0, 16), entry(0x607A, 0, 32)}, 1));
    rig.device->set_operational(true);
    unsigned hooked = 0;
    rig.device->set_rpdo_hook([&](unsigned n, TimePoint) { hooked += n; });
    ASSERT_TRUE(rig.master_bus.send(Frame::make(0x203, {0x0F, 0x00, 0x10, 0x27, 0, 0})));
    rig.run(milliseconds(1));
    EXPECT_EQ(rig.od.get<std::int32_t>(0x607A, 0), 0);
    sync(rig);
    EXPECT_EQ(rig.od.get<std::uint16_t>(0x6040, 0), 0x000F);
    EXPECT_EQ(rig.od.get<std::int32_t>(0x607A, 0), 10000);
    EXPECT_EQ(hooked, 1U);
}

TEST(DevicePdoReception, EventRpdoIsAppliedAtOnceAndShortFramesAreReported) {
    Rig rig(3);
    setup(rig, rpdo(1, {entry(0x6040, 0, 16), entry(0x0005, 0, 8), entry(0x2002, 0, 1)}, 255));
    rig.device->set_operational(true);
    std::vector<std::string> events;
    rig.device->set_event_handler(
        [&](const DevicePdoEvent& e) { events.push_back(to_string(e, 3)); });
    ASSERT_TRUE(rig.master_bus.send(Frame::make(0x203, {0x06, 0x00, 0xAA, 0x01})));
    rig.run(milliseconds(1));
    EXPECT_EQ(rig.od.get<std::uint16_t>(0x6040, 0), 6);
    EXPECT_EQ(rig.od.get<std::uint8_t>(0x2002, 0), 1); // a BOOLEAN mapped as one bit
    ASSERT_TRUE(rig.master_bus.send(Frame::make(0x203, {0x07})));
    rig.run(milliseconds(1));
    EXPECT_EQ(rig.od.get<std::uint16_t>(0x6040, 0), 6);
    ASSERT_EQ(events.size(), 1U);
    EXPECT_EQ(events[0], "node 3: RPDO1 (0x203) has 1 bytes but its mapping needs 4 (frame "
                         "ignored, EMCY 8210h)");
}
