// SPDX-License-Identifier: Apache-2.0
// A single-writer sequence lock: the cyclic thread publishes a small trivially copyable value
// (its statistics) lock-free and without allocation; any thread reads a consistent copy.
#pragma once

#include <array>
#include <atomic>
#include <cstdint>
#include <cstring>
#include <type_traits>

namespace codrive::controller {

/// One writer thread calls store(); any number of threads call load(). The writer never waits
/// (wait-free, no allocation, no system call); a reader retries while a store is in progress, so
/// it never returns a torn value (e.g. half of a 64-bit counter on a 32-bit CPU). The value is
/// kept in 32-bit atomic words, which are lock-free on every target, written with release and
/// read with acquire ordering instead of fences (the fence-free variant in H.-J. Boehm, "Can
/// seqlocks get along with programming language memory models?", 2012; GCC's ThreadSanitizer
/// does not model standalone fences), so there is no data race in the C++ sense.
template <typename T>
class Seqlock {
    static_assert(std::is_trivially_copyable_v<T>, "Seqlock copies the value bytewise");
    static constexpr std::size_t kWords = (sizeof(T) + 3) / 4;

public:
    Seqlock() { store(T{}); }

    /// Writer thread only.
    void store(const T& value) {
        std::array<std::uint32_t, kWords> w{};
        std::memcpy(w.data(), &value, sizeof(T));
        const std::uint32_t s = seq_.load(std::memory_order_relaxed);
        seq_.store(s + 1, std::memory_order_relaxed); // odd: a store is in progress
        for (std::size_t i = 0; i < kWords; ++i) {
            // Release: a reader that sees this word's new value also sees the odd sequence.
            words_[i].store(w[i], std::memory_order_release);
        }
        seq_.store(s + 2, std::memory_order_release);
    }

    /// Any thread: the last stored value, never a mix of two stores.
    [[nodiscard]] T load() const {
        std::array<std::uint32_t, kWords> w{};
        for (;;) {
            const std::uint32_t before = seq_.load(std::memory_order_acquire);
            if ((before & 1U) != 0) {
                continue; // the writer is in the middle of a store
            }
            for (std::size_t i = 0; i < kWords; ++i) {
                // Acquire: the sequence check below cannot move before these loads.
                w[i] = words_[i].load(std::memory_order_acquire);
            }
            if (seq_.load(std::memory_order_relaxed) == before) {
                break;
            }
        }
        T value;
        std::memcpy(static_cast<void*>(&value), w.data(), sizeof(T));
        return value;
    }

private:
    std::atomic<std::uint32_t> seq_{0};
    std::array<std::atomic<std::uint32_t>, kWords> words_{};
};

} // namespace codrive::controller
