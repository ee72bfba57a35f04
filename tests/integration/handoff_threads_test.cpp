// SPDX-License-Identifier: Apache-2.0
// HandoffTransport between two real threads (run under ThreadSanitizer too, tests/run-all.sh
// stage `tsan`): every object access a requesting thread queues is carried out once on the
// executing thread and its own result comes back to the requesting thread, none lost or mixed up.
#include "../../controller/src/handoff_transport.hpp"

#include <codrive/testing/no_cyclic_transport.hpp>

#include <gtest/gtest.h>

#include <atomic>
#include <cstdint>
#include <deque>
#include <thread>

namespace codrive::controller {
namespace {

/// The executing thread's transport: answers a read of index i, sub s with the bytes
/// {i low, i high, s}, accepts every write and records its data.
class EchoTransport final : public codrive::testing::NoCyclicTransport {
public:
    [[nodiscard]] std::string name() const override { return "node 5"; }
    void read(std::uint16_t index, std::uint8_t subindex, ReadDone done) override {
        pending_.push_back([index, subindex, d = std::move(done)] {
            d(drives::Bytes{static_cast<std::uint8_t>(index & 0xFF),
                            static_cast<std::uint8_t>(index >> 8), subindex});
        });
    }
    void write(std::uint16_t, std::uint8_t, drives::Bytes data, WriteDone done) override {
        written_sum_ += data.empty() ? 0 : data[0];
        pending_.push_back([d = std::move(done)] { d(drives::DriveVoid{}); });
    }
    /// Completes the oldest access, as a bus would some time later.
    bool complete_one() {
        if (pending_.empty()) {
            return false;
        }
        auto fn = std::move(pending_.front());
        pending_.pop_front();
        fn();
        return true;
    }
    [[nodiscard]] std::uint64_t written_sum() const { return written_sum_; }

private:
    std::deque<std::function<void()>> pending_;
    std::uint64_t written_sum_ = 0;
};

TEST(HandoffThreads, TwoThreadsCarryFiftyThousandAccessesEachToItsOwnCompletion) {
    constexpr int kAccesses = 50000;
    EchoTransport inner;
    HandoffTransport handoff(inner, "acyclic thread");
    std::atomic<bool> requester_done{false};
    // Executing thread: starts what was queued, completes one access per turn (so accesses pile
    // up in flight and the slots run out now and then).
    std::thread executor([&] {
        while (!requester_done.load(std::memory_order_acquire)) {
            handoff.pump_requests();
            if (!inner.complete_one()) {
                std::this_thread::yield();
            }
        }
    });
    int sent = 0;
    int completed = 0;
    int wrong = 0;
    int refused = 0;
    std::uint64_t written = 0;
    while (completed < kAccesses) {
        if (sent < kAccesses) {
            const int k = sent;
            bool ok = true;
            if (k % 2 == 0) {
                const auto index = static_cast<std::uint16_t>(0x2000 + k % 0x1000);
                const auto sub = static_cast<std::uint8_t>(k % 200);
                handoff.read(index, sub, [&, index, sub](drives::DriveResult<drives::Bytes> r) {
                    if (!r) {
                        ok = false;
                        return;
                    }
                    ++completed;
                    if (r->size() != 3 || (*r)[0] != (index & 0xFF) || (*r)[1] != (index >> 8) ||
                        (*r)[2] != sub) {
                        ++wrong;
                    }
                });
            } else {
                const auto byte = static_cast<std::uint8_t>(k % 251);
                handoff.write(0x6060, 0, drives::Bytes{byte}, [&, byte](drives::DriveVoid r) {
                    if (!r) {
                        ok = false;
                        return;
                    }
                    ++completed;
                    written += byte;
                });
            }
            if (ok) {
                ++sent;
            } else {
                ++refused; // all slots in use: try again after the next deliveries
            }
        }
        if (handoff.deliver_completions() == 0 && sent == kAccesses) {
            std::this_thread::yield();
        }
    }
    requester_done.store(true, std::memory_order_release);
    executor.join();
    EXPECT_EQ(completed, kAccesses);
    EXPECT_EQ(wrong, 0);
    EXPECT_EQ(written, inner.written_sum());
    std::printf("hand-off, 2 threads: %d accesses, %d refused while all %zu slots were in use\n",
                kAccesses, refused, HandoffTransport::kSlots);
}

} // namespace
} // namespace codrive::controller
