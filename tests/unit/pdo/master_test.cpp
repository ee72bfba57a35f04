// SPDX-License-Identifier: Apache-2.0
// PdoMaster: process image, RPDO production per transmission type, TPDO decoding and events.
#include "pdo_rig.hpp"

#include <gtest/gtest.h>

using namespace codrive;
using namespace codrive::pdo;
using namespace codrive::pdo::test;

namespace {

struct Bench {
    Bench() {
        peer.set_frame_handler([this](const Frame& f, TimePoint) { seen.push_back(f); });
        bus.set_frame_handler([this](const Frame& f, TimePoint t) { master.on_frame(f, t); });
        master.set_event_handler([this](const PdoEvent& e) { events.push_back(to_string(e)); });
    }
    void run(Duration d) { net.run_until(clock, clock.now() + d, {&master}); }
    void sync() {
        master.on_sync(cycle++, clock.now());
        run(microseconds(100));
    }
    void from_node(const Frame& f) {
        ASSERT_TRUE(peer.send(f));
        run(microseconds(100));
    }
    std::size_t count(std::uint32_t id) const {
        std::size_t n = 0;
        for (const auto& f : seen) {
            n += f.id == id ? 1 : 0;
        }
        return n;
    }

    FakeClock clock;
    VirtualNetwork net{clock, microseconds(10)};
    VirtualBus& bus = net.endpoint("master");
    VirtualBus& peer = net.endpoint("node");
    PdoMaster master{bus};
    std::vector<Frame> seen;
    std::vector<std::string> events;
    std::uint64_t cycle = 1;
};

std::vector<PdoConfig> csp_node() {
    return {rpdo(1, {entry(0x6040, 0, 16), entry(0x607A, 0, 32)}, 1),
            tpdo(1, {entry(0x6041, 0, 16), entry(0x6064, 0, 32)}, 1)};
}

} // namespace

TEST(PdoMaster, EncodesRpdoFromTheImageOnSync) {
    Bench b;
    auto image = b.master.add_node(2, csp_node());
    ASSERT_TRUE(image) << image.error().message;
    ProcessImage& img = **image;
    const Slot cw = *img.slot(0x6040, 0);
    const Slot target = *img.slot(0x607A, 0);
    img.set<std::uint16_t>(cw, 0x000F);
    img.set<std::int32_t>(target, -100000);
    b.sync();
    ASSERT_EQ(b.seen.size(), 1U);
    EXPECT_EQ(to_string(b.seen[0]), "202#0F006079FEFF");
    b.sync(); // type 1: every SYNC, changed or not
    EXPECT_EQ(b.count(0x202), 2U);
}

TEST(PdoMaster, DecodesTpdoIntoTheImageWithTimestamp) {
    Bench b;
    ProcessImage& img = **b.master.add_node(2, csp_node());
    const Slot sw = *img.slot(0x6041, 0);
    const Slot pos = *img.slot(0x6064, 0);
    b.from_node(Frame::make(0x182, {0x37, 0x06, 0xFE, 0xFF, 0xFF, 0xFF}));
    EXPECT_EQ(img.get<std::uint16_t>(sw), 0x0637);
    EXPECT_EQ(img.get<std::int32_t>(pos), -2);
    EXPECT_EQ(img.count(pos), 1U);
    EXPECT_EQ(img.rx_time(pos), b.clock.now() - microseconds(90));
}

TEST(PdoMaster, UnmappedObjectIsASentence) {
    Bench b;
    ProcessImage& img = **b.master.add_node(2, csp_node());
    auto s = img.slot(0x606C, 0);
    ASSERT_FALSE(s);
    EXPECT_EQ(s.error().message, "node 2: 0x606C:00 is not mapped in any PDO");
    EXPECT_FALSE(b.master.add_node(2, csp_node()));
}

TEST(PdoMaster, AcyclicSyncRpdoGoesOutOnlyAfterAChange) {
    Bench b;
    ProcessImage& img = **b.master.add_node(2, {rpdo(1, {entry(0x6040, 0, 16)}, 0)});
    const Slot cw = *img.slot(0x6040, 0);
    b.sync();
    EXPECT_EQ(b.count(0x202), 0U);
    img.set<std::uint16_t>(cw, 6);
    b.sync();
    b.sync();
    EXPECT_EQ(b.count(0x202), 1U);
    img.set<std::uint16_t>(cw, 6); // same value: no change
    b.sync();
    EXPECT_EQ(b.count(0x202), 1U);
    img.touch(cw);
    b.sync();
    EXPECT_EQ(b.count(0x202), 2U);
}

TEST(PdoMaster, CyclicRpdoGoesOutEveryNthSync) {
    Bench b;
    ASSERT_TRUE(b.master.add_node(2, {rpdo(2, {entry(0x6040, 0, 16)}, 4)}));
    for (int i = 0; i < 12; ++i) {
        b.sync();
    }
    EXPECT_EQ(b.count(0x302), 3U);
}

TEST(PdoMaster, EventRpdoRespectsInhibitTimeAndEventTimer) {
    Bench b;
    PdoConfig p = rpdo(1, {entry(0x6040, 0, 16)}, 255);
    p.comm.inhibit_time = 50; // 5 ms
    p.comm.event_timer = 20;  // refresh every 20 ms
    ProcessImage& img = **b.master.add_node(2, {p});
    const Slot cw = *img.slot(0x6040, 0);
    b.run(microseconds(100));
    EXPECT_EQ(b.count(0x202), 1U); // the event timer sends the first value at once
    for (std::uint16_t v = 1; v <= 4; ++v) {
        img.set<std::uint16_t>(cw, v);
        b.run(milliseconds(1));
    }
    EXPECT_EQ(b.count(0x202), 1U); // inhibited
    b.run(milliseconds(2));
    EXPECT_EQ(b.count(0x202), 2U);
    EXPECT_EQ(to_string(b.seen.back()), "202#0400");
    b.run(milliseconds(30)); // no change: the event timer repeats it once in 20 ms
    EXPECT_EQ(b.count(0x202), 3U);
}

TEST(PdoMaster, MissingTpdoAfterSyncIsReportedWithNodeAndNumber) {
    Bench b;
    ASSERT_TRUE(b.master.add_node(2, csp_node()));
    b.cycle = 1233;
    b.sync(); // 1233: window opens
    b.from_node(Frame::make(0x182, {0, 0, 0, 0, 0, 0}));
    b.sync(); // 1234: 1233 answered
    b.sync(); // 1235: 1234 not answered yet (may still come late)
    EXPECT_TRUE(b.events.empty());
    b.sync(); // 1236: 1234 and 1235 unanswered: 1234 is missing
    ASSERT_EQ(b.events.size(), 1U);
    EXPECT_EQ(b.events[0], "node 2: TPDO1 (0x182) missing after SYNC 1234 (expected every SYNC)");
    b.from_node(Frame::make(0x182, {0, 0, 0, 0, 0, 0}));
    ASSERT_EQ(b.events.size(), 2U);
    EXPECT_EQ(b.events[1], "node 2: TPDO1 (0x182) received again");
    EXPECT_EQ(b.master.stats().tpdos_missing, 1U);
}

TEST(PdoMaster, EveryNthSyncTpdoIsExpectedOncePerWindow) {
    Bench b;
    ASSERT_TRUE(b.master.add_node(4, {tpdo(2, {entry(0x6041, 0, 16)}, 3)}));
    for (int i = 0; i < 9; ++i) {
        b.sync();
        if (i % 3 == 1) {
            b.from_node(Frame::make(0x284, {1, 2}));
        }
    }
    b.sync();
    EXPECT_TRUE(b.events.empty());
    for (int i = 0; i < 6; ++i) {
        b.sync();
    }
    ASSERT_EQ(b.events.size(), 1U);
    EXPECT_EQ(b.events[0], "node 4: TPDO2 (0x284) missing after SYNC 10 (expected every 3rd SYNC)");
}

TEST(PdoMaster, TpdoOneSyncLateIsNotMissing) {
    Bench b;
    ASSERT_TRUE(b.master.add_node(2, csp_node()));
    b.sync();
    for (int i = 0; i < 20; ++i) {
        b.sync(); // the master ticks before it reads the answer to the previous SYNC
        b.from_node(Frame::make(0x182, {0, 0, 0, 0, 0, 0}));
    }
    EXPECT_TRUE(b.events.empty()) << b.events.front();
    b.sync();
    b.sync();
    ASSERT_EQ(b.events.size(), 1U);
    EXPECT_EQ(b.events[0], "node 2: TPDO1 (0x182) missing after SYNC 21 (expected every SYNC)");
}

TEST(PdoMaster, MissingToleranceZeroReportsAtTheNextSync) {
    Bench b;
    PdoMasterOptions o;
    o.missing_tolerance = 0;
    PdoMaster strict(b.bus, o);
    std::vector<std::string> events;
    strict.set_event_handler([&](const PdoEvent& e) { events.push_back(to_string(e)); });
    ASSERT_TRUE(strict.add_node(2, csp_node()));
    strict.on_sync(7, b.clock.now());
    strict.on_sync(8, b.clock.now());
    ASSERT_EQ(events.size(), 1U);
    EXPECT_EQ(events[0], "node 2: TPDO1 (0x182) missing after SYNC 7 (expected every SYNC)");
}

TEST(PdoMaster, ShortTpdoIsIgnoredAndReported) {
    Bench b;
    ProcessImage& img = **b.master.add_node(2, csp_node());
    b.from_node(Frame::make(0x182, {0x37, 0x06}));
    EXPECT_EQ(img.get<std::uint16_t>(*img.slot(0x6041, 0)), 0);
    ASSERT_EQ(b.events.size(), 1U);
    EXPECT_EQ(b.events[0], "node 2: TPDO1 (0x182) has 2 bytes but its mapping needs 6 (frame "
                           "ignored)");
}

TEST(PdoMaster, SilentEventTpdoIsReported) {
    Bench b;
    PdoConfig p = tpdo(3, {entry(0x6041, 0, 16)}, 255);
    p.comm.event_timer = 10;
    ASSERT_TRUE(b.master.add_node(2, {p}));
    b.run(milliseconds(5));
    b.from_node(Frame::make(0x382, {1, 0}));
    b.run(milliseconds(15));
    EXPECT_TRUE(b.events.empty());
    b.run(milliseconds(10));
    ASSERT_EQ(b.events.size(), 1U);
    EXPECT_EQ(b.events[0], "node 2: TPDO3 (0x382) silent for 20 ms (event timer 10 ms)");
}

TEST(PdoMaster, RtrRequestGoesToTheTpdoCobId) {
    Bench b;
    ASSERT_TRUE(b.master.add_node(2, csp_node()));
    ASSERT_TRUE(b.master.request(2, 1));
    b.run(microseconds(100));
    ASSERT_EQ(b.seen.size(), 1U);
    EXPECT_EQ(to_string(b.seen[0]), "182#R6");
    EXPECT_FALSE(b.master.request(2, 4));
    EXPECT_FALSE(b.master.request(9, 1));
}

TEST(PdoMaster, BitSlotsAndSignExtension) {
    Bench b;
    ProcessImage& img = **b.master.add_node(
        2, {rpdo(1, {entry(0x2002, 0, 1), entry(0x0001, 0, 3), entry(0x2003, 0, 12)}, 1),
            tpdo(1, {entry(0x2004, 0, 4), entry(0x2005, 0, 12)}, 1)});
    const Slot flag = *img.slot(0x2002, 0);
    const Slot twelve = *img.slot(0x2003, 0);
    EXPECT_EQ(twelve.bit_offset, 4);
    img.set<bool>(flag, true);
    img.set<std::uint16_t>(twelve, 0xABC);
    b.sync();
    ASSERT_EQ(b.seen.size(), 1U);
    EXPECT_EQ(to_string(b.seen[0]), "202#C1AB");
    b.from_node(Frame::make(0x182, {0xFF, 0x7F}));
    EXPECT_EQ(img.get<std::int8_t>(*img.slot(0x2004, 0)), -1);
    EXPECT_EQ(img.get<std::int16_t>(*img.slot(0x2005, 0)), 0x7FF);
    EXPECT_EQ(img.get<std::uint16_t>(*img.slot(0x2005, 0)), 0x7FFU);
}

TEST(PdoMaster, TpdoCobIdConflictBetweenNodesIsRefused) {
    Bench b;
    PdoConfig p = tpdo(1, {entry(0x6041, 0, 16)}, 1);
    p.comm.can_id = 0x190;
    ASSERT_TRUE(b.master.add_node(2, {p}));
    auto r = b.master.add_node(3, {p});
    ASSERT_FALSE(r);
    EXPECT_EQ(r.error().message, "node 3: TPDO1 COB-ID 0x190 is already used by another TPDO");
}

namespace {

/// Records how frames reach it: every send_many() call with its size, and which frames it took.
/// Takes at most `room` frames in total, then refuses with TxQueueFull (a full transmit queue).
class BatchBus final : public ICanBus {
public:
    VoidResult send(const Frame& f) override {
        ++single_sends;
        if (taken.size() >= room) {
            return fail(CoreErrc::TxQueueFull);
        }
        taken.push_back(f);
        return {};
    }
    std::size_t send_many(std::span<const Frame> frames) override {
        batches.push_back(frames.size());
        std::size_t n = 0;
        while (n < frames.size() && taken.size() < room) {
            taken.push_back(frames[n++]);
        }
        return n;
    }
    void set_frame_handler(FrameHandler) override {}
    void set_event_handler(EventHandler) override {}
    [[nodiscard]] std::size_t tx_pending() const override { return 0; }
    [[nodiscard]] const BusStats& stats() const override { return stats_; }
    [[nodiscard]] const std::string& name() const override { return name_; }
    std::size_t room = 1000;
    std::vector<std::size_t> batches;
    std::size_t single_sends = 0;
    std::vector<Frame> taken;

private:
    BusStats stats_;
    std::string name_ = "batch";
};

} // namespace

TEST(PdoMaster, ASyncCyclesRpdosGoToTheBusTogetherInOrder) {
    BatchBus bus;
    PdoMaster master(bus);
    for (NodeId n = 1; n <= 8; ++n) {
        ASSERT_TRUE(master.add_node(
            n, {rpdo(1, {entry(0x6040, 0, 16)}, 1), rpdo(2, {entry(0x607A, 0, 32)}, 1)}));
    }
    master.on_sync(1, TimePoint{});
    // 16 RPDOs due at this SYNC: one send_many() call, none alone, in node and PDO order.
    ASSERT_EQ(bus.batches, std::vector<std::size_t>{16});
    EXPECT_EQ(bus.single_sends, 0U);
    ASSERT_EQ(bus.taken.size(), 16U);
    for (NodeId n = 1; n <= 8; ++n) {
        EXPECT_EQ(bus.taken[2U * (n - 1U)].id, cob::rpdo(1, n));
        EXPECT_EQ(bus.taken[2U * (n - 1U) + 1].id, cob::rpdo(2, n));
    }
    EXPECT_EQ(master.stats().rpdos_sent, 16U);
    // A cycle with nothing due sends nothing.
    bus.batches.clear();
    PdoMaster idle(bus);
    idle.on_sync(1, TimePoint{});
    EXPECT_TRUE(bus.batches.empty());
}

TEST(PdoMaster, RpdosTheBusRefusesInABatchAreReportedOneByOne) {
    BatchBus bus;
    bus.room = 5;
    PdoMaster master(bus);
    std::vector<PdoEvent> events;
    master.set_event_handler([&](const PdoEvent& e) { events.push_back(e); });
    for (NodeId n = 1; n <= 4; ++n) {
        ASSERT_TRUE(master.add_node(
            n, {rpdo(1, {entry(0x6040, 0, 16)}, 1), rpdo(2, {entry(0x607A, 0, 32)}, 1)}));
    }
    master.on_sync(1, TimePoint{});
    // The bus took 5 of 8: the other 3 were each tried alone and each reported with the bus's
    // error, naming node and PDO.
    EXPECT_EQ(bus.taken.size(), 5U);
    EXPECT_EQ(bus.single_sends, 3U);
    EXPECT_EQ(master.stats().rpdos_sent, 5U);
    EXPECT_EQ(master.stats().send_errors, 3U);
    ASSERT_EQ(events.size(), 3U);
    EXPECT_EQ(events[0].kind, PdoEventKind::RpdoSendFailed);
    EXPECT_EQ(events[0].node, 3U);
    EXPECT_EQ(events[0].number, 2U);
    EXPECT_EQ(events[2].node, 4U);
    EXPECT_EQ(events[2].number, 2U);
    EXPECT_EQ(events[0].error, make_error_code(CoreErrc::TxQueueFull));
}
