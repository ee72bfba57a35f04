// SPDX-License-Identifier: Apache-2.0
// HandoffTransport allocates nothing on either thread: queueing an access and delivering its
// completion (the requesting side), starting it on the wrapped transport and handing its result
// back (the executing side) move callbacks, data and results through slots allocated at
// construction. Runs in the Release build too (tests/run-all.sh, stage `release`), where the
// optimiser could remove an allocation only the Debug build makes.
#include "../../../controller/src/handoff_transport.hpp"

#include <codrive/testing/no_cyclic_transport.hpp>

#include <gtest/gtest.h>

#include <array>
#include <string>
#include <vector>

// One program-wide counting operator new (included once per program).
#include <codrive/testing/counting_new.hpp>

namespace codrive::controller {
namespace {

using codrive::testing::g_allocations;
using codrive::testing::g_counting;

/// The executing side's transport: keeps each access's callback in a fixed array and completes
/// them all on process(), answering reads with byte vectors built before the count starts (so
/// what is counted is the hand-off, not this fake's own allocations).
class FixedTransport final : public codrive::testing::NoCyclicTransport {
public:
    static constexpr std::size_t kMax = HandoffTransport::kSlots;
    explicit FixedTransport(std::size_t answers) {
        for (std::size_t i = 0; i < answers; ++i) {
            answers_.push_back(drives::Bytes{0x92, 0x01, 0x02, static_cast<std::uint8_t>(i)});
        }
    }
    [[nodiscard]] std::string name() const override { return "slave 3"; }
    void read(std::uint16_t, std::uint8_t, ReadDone done) override {
        reads_[n_reads_++] = std::move(done);
    }
    void write(std::uint16_t, std::uint8_t, drives::Bytes data, WriteDone done) override {
        written_bytes_ += data.size();
        writes_[n_writes_++] = std::move(done);
    }
    void process() {
        for (std::size_t i = 0; i < n_reads_; ++i) {
            reads_[i](std::move(answers_[next_answer_++]));
            reads_[i] = nullptr;
        }
        for (std::size_t i = 0; i < n_writes_; ++i) {
            writes_[i](drives::DriveVoid{});
            writes_[i] = nullptr;
        }
        n_reads_ = 0;
        n_writes_ = 0;
    }
    [[nodiscard]] std::size_t written_bytes() const { return written_bytes_; }

private:
    std::vector<drives::Bytes> answers_;
    std::size_t next_answer_ = 0;
    std::array<ReadDone, kMax> reads_{};
    std::array<WriteDone, kMax> writes_{};
    std::size_t n_reads_ = 0;
    std::size_t n_writes_ = 0;
    std::size_t written_bytes_ = 0;
};

/// Counts what the calling thread allocates inside `fn`.
template <typename Fn>
std::uint64_t allocations_in(Fn&& fn) {
    const std::uint64_t before = g_allocations.load();
    g_counting = true;
    fn();
    g_counting = false;
    return g_allocations.load() - before;
}

TEST(HandoffAllocation, BothSidesQueueRunAndCompleteAccessesWithoutAllocating) {
    constexpr int kCycles = 1000;
    FixedTransport inner(kCycles);
    HandoffTransport handoff(inner, "acyclic thread");
    // The write data of every cycle, built before counting: the caller owns that allocation,
    // the hand-off only moves the vector along.
    std::vector<drives::Bytes> data(kCycles, drives::Bytes{0x08, 0x00, 0x00, 0x00});
    int reads_ok = 0;
    int writes_ok = 0;
    std::uint8_t last_byte = 0;
    std::uint64_t requesting = 0;
    std::uint64_t executing = 0;
    for (int cycle = 0; cycle < kCycles; ++cycle) {
        requesting += allocations_in([&] {
            handoff.read(0x1018, 1, [&](drives::DriveResult<drives::Bytes> r) {
                if (r && r->size() == 4) {
                    ++reads_ok;
                    last_byte = (*r)[3];
                }
            });
            handoff.write(0x6060, 0, std::move(data[static_cast<std::size_t>(cycle)]),
                          [&writes_ok](drives::DriveVoid r) { writes_ok += r ? 1 : 0; });
        });
        executing += allocations_in([&] {
            handoff.pump_requests();
            inner.process();
        });
        requesting += allocations_in([&] { handoff.deliver_completions(); });
    }
    EXPECT_EQ(reads_ok, kCycles);
    EXPECT_EQ(writes_ok, kCycles);
    EXPECT_EQ(last_byte, static_cast<std::uint8_t>(kCycles - 1));
    EXPECT_EQ(inner.written_bytes(), 4U * kCycles);
    EXPECT_EQ(requesting, 0U);
    EXPECT_EQ(executing, 0U);
}

TEST(HandoffAllocation, SixtyFifthOutstandingAccessIsRefusedWithItsSentence) {
    FixedTransport inner(0);
    HandoffTransport handoff(inner, "acyclic thread");
    int refused = 0;
    std::string why;
    for (std::size_t i = 0; i <= HandoffTransport::kSlots; ++i) {
        handoff.write(0x6060, 0, drives::Bytes{}, [&](drives::DriveVoid r) {
            if (!r) {
                ++refused;
                why = r.error().message;
            }
        });
    }
    // Refused at once, inside the call, with the device and the reason.
    EXPECT_EQ(refused, 1);
    EXPECT_EQ(why, "slave 3: too many object accesses waiting for the acyclic thread (64)");
    // Started, completed and delivered, the slots are free again.
    EXPECT_EQ(handoff.pump_requests(), HandoffTransport::kSlots);
    inner.process();
    EXPECT_EQ(handoff.deliver_completions(), HandoffTransport::kSlots);
    handoff.write(0x6060, 0, drives::Bytes{}, [&](drives::DriveVoid r) { refused += r ? 0 : 1; });
    EXPECT_EQ(handoff.pump_requests(), 1U);
    EXPECT_EQ(refused, 1);
}

} // namespace
} // namespace codrive::controller
