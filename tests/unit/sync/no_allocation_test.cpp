// SPDX-License-Identifier: Apache-2.0
// The SYNC cyclic path (on_tick + hook + statistics) must not allocate.
#include <codrive/core/virtual_bus.hpp>
#include <codrive/sync/producer.hpp>

#include <gtest/gtest.h>

#include <atomic>
#include <cstdlib>
#include <memory>
#include <new>

#include <codrive/testing/counting_new.hpp>

// One program-wide counting operator new (included once per program).
using codrive::testing::AllocationScope;

namespace codrive::sync {
namespace {

/// A sink bus: accepts frames without queueing them anywhere (the virtual network would
/// allocate for its in-flight queue, which is not the producer's doing).
class NullBus final : public ICanBus {
public:
    VoidResult send(const Frame&) override {
        ++sent;
        return {};
    }
    void set_frame_handler(FrameHandler) override {}
    void set_event_handler(EventHandler) override {}
    [[nodiscard]] std::size_t tx_pending() const override { return 0; }
    [[nodiscard]] const BusStats& stats() const override { return stats_; }
    [[nodiscard]] const std::string& name() const override { return name_; }
    std::uint64_t sent = 0;

private:
    BusStats stats_;
    std::string name_ = "null";
};

TEST(SyncAllocation, CounterSeesAnAllocationAlsoWhenOptimised) {
    AllocationScope scope;
    auto* volatile p = new std::uint64_t(1);
    delete p;
    EXPECT_EQ(scope.count(), 1U);
}

TEST(SyncAllocation, ProducerCyclicPathAllocatesNothing) {
    NullBus bus;
    SyncProducer producer(bus);
    ASSERT_TRUE(producer.configure({milliseconds(1), 16, 0x80}));
    std::uint64_t hooks = 0;
    producer.set_hook([&hooks](const SyncInfo&) { ++hooks; });
    FakeClock clock;
    producer.start(clock.now());
    AllocationScope scope;
    for (int k = 0; k < 10000; ++k) {
        clock.set(producer.next_deadline() + microseconds(k % 700));
        producer.on_tick(clock.now());
    }
    scope.stop();
    EXPECT_EQ(scope.count(), 0U);
    EXPECT_EQ(hooks, 10000U);
    EXPECT_EQ(bus.sent, 10000U);
}

} // namespace
} // namespace codrive::sync
