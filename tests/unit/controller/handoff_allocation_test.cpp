// SPDX-License-Identifier: Apache-2.0
// HandoffTransport's cyclic side (queueing an object access, delivering its completion) moves
// into and out of preallocated ring slots: it allocates nothing itself. (The request's callback
// and data are built by the caller; a callback that fits std::function's inline storage and an
// empty byte vector allocate nothing either.)
#include "../../../controller/src/handoff_transport.hpp"

#include <gtest/gtest.h>

#include <deque>

// One program-wide counting operator new (included once per program).
#include <codrive/testing/counting_new.hpp>

namespace codrive::controller {
namespace {

using codrive::testing::g_allocations;
using codrive::testing::g_counting;

/// The acyclic side's transport: completes every access on process() (no bus).
class ImmediateTransport final : public drives::DriveTransport {
public:
    [[nodiscard]] std::string name() const override { return "slave 0"; }
    void read(std::uint16_t, std::uint8_t, ReadDone done) override {
        reads_.push_back(std::move(done));
    }
    void write(std::uint16_t, std::uint8_t, drives::Bytes, WriteDone done) override {
        writes_.push_back(std::move(done));
    }
    [[nodiscard]] drives::CyclicHandle output(std::uint16_t, std::uint8_t) const override {
        return {};
    }
    [[nodiscard]] drives::CyclicHandle input(std::uint16_t, std::uint8_t) const override {
        return {};
    }
    void set_raw(drives::CyclicHandle, std::uint64_t) override {}
    [[nodiscard]] std::optional<std::uint64_t> get_raw(drives::CyclicHandle) const override {
        return std::nullopt;
    }
    void process() {
        for (auto& d : reads_) {
            d(drives::Bytes{});
        }
        for (auto& d : writes_) {
            d(drives::DriveVoid{});
        }
        reads_.clear();
        writes_.clear();
    }

private:
    std::deque<ReadDone> reads_;
    std::deque<WriteDone> writes_;
};

/// Counts what the calling (cyclic) thread allocates inside `fn`.
template <typename Fn>
std::uint64_t allocations_in(Fn&& fn) {
    const std::uint64_t before = g_allocations.load();
    g_counting = true;
    fn();
    g_counting = false;
    return g_allocations.load() - before;
}

TEST(HandoffAllocation, CyclicSideQueuesAndCompletesAccessesWithoutAllocating) {
    ImmediateTransport inner;
    HandoffTransport handoff(inner);
    int reads_done = 0;
    int writes_done = 0;
    std::uint64_t cyclic = 0;
    for (int cycle = 0; cycle < 1000; ++cycle) {
        // Cyclic thread: start one read and one write (callbacks capture one pointer).
        cyclic += allocations_in([&] {
            handoff.read(0x6041, 0, [&reads_done](drives::DriveResult<drives::Bytes> r) {
                reads_done += r ? 1 : 0;
            });
            handoff.write(0x6060, 0, drives::Bytes{},
                          [&writes_done](drives::DriveVoid r) { writes_done += r ? 1 : 0; });
        });
        // Acyclic thread: run them (allocates freely: SDO, queues).
        handoff.pump_requests();
        inner.process();
        // Cyclic thread, next cycle: the completions.
        cyclic += allocations_in([&] { handoff.deliver_completions(); });
    }
    EXPECT_EQ(reads_done, 1000);
    EXPECT_EQ(writes_done, 1000);
    EXPECT_EQ(cyclic, 0U);
}

} // namespace
} // namespace codrive::controller
