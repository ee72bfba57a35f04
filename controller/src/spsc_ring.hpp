// SPDX-License-Identifier: Apache-2.0
// A fixed-capacity single-producer single-consumer ring: the lock-free hand-off between the
// cyclic thread and the acyclic thread (no allocation after construction, no locks, no waits).
#pragma once

#include <array>
#include <atomic>
#include <cstddef>
#include <optional>
#include <utility>

namespace codrive::controller {

/// One thread push()es, one other thread pop()s. Slots are allocated up front; push/pop move
/// values in and out. Acquire/release on the indexes publishes the slot contents.
template <typename T, std::size_t N>
class SpscRing {
    static_assert(N >= 2 && (N & (N - 1)) == 0, "capacity must be a power of two");

public:
    /// False when full (the value is left untouched).
    bool push(T& value) {
        const std::size_t head = head_.load(std::memory_order_relaxed);
        if (head - tail_.load(std::memory_order_acquire) == N) {
            return false;
        }
        slots_[head & (N - 1)] = std::move(value);
        head_.store(head + 1, std::memory_order_release);
        return true;
    }
    bool pop(T& out) {
        const std::size_t tail = tail_.load(std::memory_order_relaxed);
        if (head_.load(std::memory_order_acquire) == tail) {
            return false;
        }
        out = std::move(slots_[tail & (N - 1)]);
        slots_[tail & (N - 1)] = T{};
        tail_.store(tail + 1, std::memory_order_release);
        return true;
    }
    [[nodiscard]] bool empty() const {
        return head_.load(std::memory_order_acquire) == tail_.load(std::memory_order_acquire);
    }

private:
    std::array<T, N> slots_{};
    alignas(64) std::atomic<std::size_t> head_{0};
    alignas(64) std::atomic<std::size_t> tail_{0};
};

} // namespace codrive::controller
