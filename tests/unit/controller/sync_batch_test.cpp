// SPDX-License-Identifier: Apache-2.0
// The controller's CAN cycle as it wires SYNC and PDOs (controller.cpp: SyncProducer's sender ->
// PdoMaster::on_sync with the SYNC frame): one send_many() per cycle carrying the SYNC and, right
// behind it, the RPDOs due at it (CiA 301 §7.2.2.2 / §7.2.5: synchronous RPDOs ride in the
// synchronous window the SYNC opens and are actuated at the next SYNC). In-process virtual bus,
// fake clock.
#include <codrive/core/virtual_bus.hpp>
#include <codrive/pdo/master.hpp>
#include <codrive/sync/producer.hpp>

#include <gtest/gtest.h>

#include <vector>

namespace codrive {
namespace {

/// Forwards to a virtual bus endpoint and records how frames were handed over: send() calls and
/// the size of every send_many() call. Takes at most `room` frames (a full transmit queue).
class RecordingBus final : public ICanBus {
public:
    explicit RecordingBus(ICanBus& inner) : inner_(inner) {}
    VoidResult send(const Frame& f) override {
        ++single_sends;
        if (taken >= room) {
            return fail(CoreErrc::TxQueueFull);
        }
        ++taken;
        return inner_.send(f);
    }
    std::size_t send_many(std::span<const Frame> frames) override {
        batches.push_back(frames.size());
        std::size_t n = 0;
        while (n < frames.size() && taken < room && inner_.send(frames[n])) {
            ++taken;
            ++n;
        }
        return n;
    }
    void set_frame_handler(FrameHandler h) override { inner_.set_frame_handler(std::move(h)); }
    void set_event_handler(EventHandler h) override { inner_.set_event_handler(std::move(h)); }
    [[nodiscard]] std::size_t tx_pending() const override { return inner_.tx_pending(); }
    [[nodiscard]] const BusStats& stats() const override { return inner_.stats(); }
    [[nodiscard]] const std::string& name() const override { return inner_.name(); }

    std::size_t room = 1000;
    std::size_t taken = 0;
    std::size_t single_sends = 0;
    std::vector<std::size_t> batches;

private:
    ICanBus& inner_;
};

struct Cycle {
    FakeClock clock;
    VirtualNetwork net{clock};
    VirtualBus& master_end = net.endpoint("master");
    VirtualBus& drive_end = net.endpoint("drives");
    RecordingBus bus{master_end};
    pdo::PdoMaster pdos{bus};
    sync::SyncProducer sync{bus};
    std::vector<Frame> wire; ///< what the drives received, in order

    Cycle() {
        drive_end.set_frame_handler([this](const Frame& f, TimePoint) { wire.push_back(f); });
        // Two drives, each with a synchronous RPDO (type 1: every SYNC) and an event RPDO that
        // never changes (type 255: not sent at a SYNC).
        for (NodeId n : {NodeId{2}, NodeId{3}}) {
            EXPECT_TRUE(pdos.add_node(
                n, {pdo::rpdo(1, {{0x6040, 0, 16}, {0x607A, 0, 32}}, 1),
                    pdo::rpdo(2, {{0x6060, 0, 8}}, pdo::transmission::kEventProfile)}));
        }
        sync::SyncConfig sc;
        sc.period = milliseconds(2);
        sc.counter_overflow = 4;
        EXPECT_TRUE(sync.configure(sc));
        // As controller.cpp wires it (the cycle callback and the axes would run before the
        // PdoMaster call; they only write the images).
        sync.set_sender([this](const Frame& f, const sync::SyncInfo& s) {
            return pdos.on_sync(s.cycle, s.actual, f);
        });
        sync.start(clock.now());
    }
    void run_cycles(int n) {
        for (int i = 0; i < n; ++i) {
            sync.on_tick(clock.now());
            net.deliver();
            clock.advance(milliseconds(2));
        }
    }
};

TEST(SyncBatch, EachCycleSendsItsSyncAndThenItsRpdosInOneBatch) {
    Cycle c;
    c.run_cycles(3);
    // One send_many() per cycle, three frames each, nothing sent alone.
    EXPECT_EQ(c.bus.batches, (std::vector<std::size_t>{3, 3, 3}));
    EXPECT_EQ(c.bus.single_sends, 0U);
    ASSERT_EQ(c.wire.size(), 9U);
    for (std::size_t k = 0; k < 3; ++k) {
        // SYNC first (COB-ID 80h, counter 1, 2, 3), then the RPDO1s of nodes 2 and 3.
        EXPECT_EQ(c.wire[3 * k].id, 0x080U) << "cycle " << k;
        EXPECT_EQ(c.wire[3 * k].len, 1U);
        EXPECT_EQ(c.wire[3 * k].data[0], k + 1);
        EXPECT_EQ(c.wire[3 * k + 1].id, 0x202U) << "cycle " << k;
        EXPECT_EQ(c.wire[3 * k + 2].id, 0x203U) << "cycle " << k;
    }
    EXPECT_EQ(c.sync.sent(), 3U);
    EXPECT_EQ(c.sync.send_errors(), 0U);
    EXPECT_EQ(c.pdos.stats().rpdos_sent, 6U);
}

TEST(SyncBatch, ARefusedSyncIsASendErrorAndTheRpdosBehindItAreReportedEach) {
    Cycle c;
    std::vector<pdo::PdoEvent> events;
    c.pdos.set_event_handler([&](const pdo::PdoEvent& e) { events.push_back(e); });
    c.bus.room = 0; // the transmit queue is full
    c.run_cycles(1);
    EXPECT_TRUE(c.wire.empty());
    EXPECT_EQ(c.sync.sent(), 0U);
    EXPECT_EQ(c.sync.send_errors(), 1U);
    // Each RPDO is tried alone to learn its own error, and reported.
    EXPECT_EQ(c.bus.single_sends, 2U);
    ASSERT_EQ(events.size(), 2U);
    EXPECT_EQ(events[0].kind, pdo::PdoEventKind::RpdoSendFailed);
    EXPECT_EQ(events[0].node, 2U);
    EXPECT_EQ(events[1].node, 3U);
    // The next cycle goes out whole again, its SYNC counter not advanced by the refused one.
    c.bus.room = 1000;
    c.run_cycles(1);
    ASSERT_EQ(c.wire.size(), 3U);
    EXPECT_EQ(c.wire[0].id, 0x080U);
    EXPECT_EQ(c.wire[0].data[0], 1U);
}

} // namespace
} // namespace codrive
