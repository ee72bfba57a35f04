// SPDX-License-Identifier: Apache-2.0
// The cyclic paths of both engines allocate nothing: counted with a replaced operator new.
#include "pdo_rig.hpp"

#include <gtest/gtest.h>

#include <atomic>
#include <cstdlib>
#include <new>
#include <string>
#include <vector>

#include <codrive/testing/counting_new.hpp>

// One program-wide counting operator new (included once per program).
using codrive::testing::AllocationScope;

using namespace codrive;
using namespace codrive::pdo;
using namespace codrive::pdo::test;

namespace {

/// A bus that only counts: the engines' sends cost nothing here.
class CountingBus final : public ICanBus {
public:
    VoidResult send(const Frame& f) override {
        ++sent;
        last = f;
        return {};
    }
    void set_frame_handler(FrameHandler) override {}
    void set_event_handler(EventHandler) override {}
    [[nodiscard]] std::size_t tx_pending() const override { return 0; }
    [[nodiscard]] const BusStats& stats() const override { return stats_; }
    [[nodiscard]] const std::string& name() const override { return name_; }
    std::uint64_t sent = 0;
    Frame last;

private:
    BusStats stats_;
    std::string name_ = "counting";
};

} // namespace

namespace {
struct alignas(64) Aligned {
    std::uint8_t bytes[64];
};
} // namespace

// The counter must see what it claims to see, also at -O2 (run in the Release build too): a
// new-expression whose result is unused may be elided by the optimiser, so the pointers escape
// through a volatile, and the replaceable functions are also called directly.
TEST(PdoAllocation, CountingScopeSeesEveryFormOfAllocation) {
    AllocationScope scope;
    void* volatile sink = ::operator new(sizeof(int));
    ::operator delete(sink);
    EXPECT_EQ(scope.count(), 1U) << "operator new(size)";
    auto* volatile one = new int(3);
    delete one;
    auto* volatile many = new int[5];
    delete[] many;
    EXPECT_EQ(scope.count(), 3U) << "new, new[]";
    auto* volatile aligned = new Aligned;
    delete aligned;
    sink = ::operator new (16, std::align_val_t{64});
    ::operator delete (sink, std::align_val_t{64});
    EXPECT_EQ(scope.count(), 5U) << "align_val_t forms";
    sink = ::operator new(8, std::nothrow);
    ::operator delete(sink);
    auto* volatile nothrow_aligned = new (std::nothrow) Aligned;
    delete nothrow_aligned;
    EXPECT_EQ(scope.count(), 7U) << "nothrow forms";
    std::vector<int> v(100);
    std::string long_text(100, 'x');
    EXPECT_EQ(scope.count(), 9U) << "library allocations (" << v.size() + long_text.size() << ")";
}

TEST(PdoAllocation, MasterCyclicPathAllocatesNothing) {
    CountingBus bus;
    PdoMaster master(bus);
    std::vector<Slot> outs;
    std::vector<Slot> ins;
    std::vector<ProcessImage*> images;
    for (NodeId n = 1; n <= 16; ++n) {
        PdoConfig ev = rpdo(2, {entry(0x60FF, 0, 32)}, 255);
        ev.comm.inhibit_time = 10;
        PdoConfig t2 = tpdo(2, {entry(0x606C, 0, 32)}, 255);
        t2.comm.event_timer = 5;
        ProcessImage* img =
            *master.add_node(n, {rpdo(1, {entry(0x6040, 0, 16), entry(0x607A, 0, 32)}, 1), ev,
                                 tpdo(1, {entry(0x6041, 0, 16), entry(0x6064, 0, 32)}, 1), t2});
        images.push_back(img);
        outs.push_back(*img->slot(0x607A, 0));
        outs.push_back(*img->slot(0x60FF, 0));
        ins.push_back(*img->slot(0x6064, 0));
    }
    std::vector<std::string> events;
    master.set_event_handler([&](const PdoEvent&) { /* no allocation here either */ });
    TimePoint now = TimePoint{} + std::chrono::hours(1);
    std::int64_t sum = 0;
    {
        AllocationScope scope;
        for (std::uint64_t k = 1; k <= 1000; ++k) {
            for (std::size_t i = 0; i < images.size(); ++i) {
                images[i]->set<std::int32_t>(outs[2 * i], static_cast<std::int32_t>(k));
                images[i]->set<std::int32_t>(outs[2 * i + 1], static_cast<std::int32_t>(k % 7));
            }
            master.on_sync(k, now);
            master.flush(now);
            for (NodeId n = 1; n <= 16; ++n) {
                Frame f = Frame::make(cob::tpdo(1, n), {0x37, 0x06, 1, 2, 3, 4});
                master.on_frame(f, now);
                if (k % 3 == 0) {
                    master.on_frame(Frame::make(cob::tpdo(2, n), {1, 2, 3, 4}), now);
                }
            }
            for (std::size_t i = 0; i < images.size(); ++i) {
                sum += images[i]->get<std::int32_t>(ins[i]);
            }
            if (master.next_deadline() <= now) {
                master.on_tick(now);
            }
            now += milliseconds(1);
        }
        EXPECT_EQ(scope.count(), 0U);
    }
    EXPECT_GT(bus.sent, 16000U);
    EXPECT_NE(sum, 0);
}

TEST(PdoAllocation, DeviceCyclicPathAllocatesNothing) {
    CountingBus bus;
    ObjectDictionary od;
    fill_drive_od(od, 2, quirks::standard());
    DevicePdoOptions opt;
    opt.node = 2;
    DevicePdo device(od, bus, opt);
    auto apply = [&](const PdoConfig& p) {
        for (const auto& w : configuration_writes(2, p, quirks::standard())) {
            ASSERT_TRUE(od.write(w.index, w.subindex, w.data)) << to_string(w);
        }
    };
    apply(rpdo(1, {entry(0x6040, 0, 16), entry(0x607A, 0, 32)}, 1));
    apply(rpdo(2, {entry(0x60FF, 0, 32)}, 255));
    apply(tpdo(1, {entry(0x6041, 0, 16), entry(0x6064, 0, 32)}, 1));
    PdoConfig t2 = tpdo(2, {entry(0x606C, 0, 32)}, 255);
    t2.comm.inhibit_time = 10;
    t2.comm.event_timer = 3;
    apply(t2);
    TimePoint now = TimePoint{} + std::chrono::hours(1);
    device.set_operational(true, now);
    device.on_tick(now);
    {
        AllocationScope scope;
        for (std::uint32_t k = 1; k <= 1000; ++k) {
            device.on_frame(Frame::make(0x202, {0x0F, 0, static_cast<std::uint8_t>(k), 0, 0, 0}),
                            now);
            device.on_frame(Frame::make(0x302, {static_cast<std::uint8_t>(k), 0, 0, 0}), now);
            device.on_frame(Frame::make(0x80, {}), now);
            od.set<std::int32_t>(0x6064, 0, static_cast<std::int32_t>(k));
            od.set<std::int32_t>(0x606C, 0, static_cast<std::int32_t>(k / 5));
            device.notify_changed();
            if (device.next_deadline() <= now) {
                device.on_tick(now);
            }
            now += milliseconds(1);
        }
        EXPECT_EQ(scope.count(), 0U);
    }
    EXPECT_EQ(device.received(1), 1000U); // each RPDO1 arrives before its SYNC
    EXPECT_EQ(device.sent(1), 1000U);
    EXPECT_GT(device.sent(2), 150U);
}
