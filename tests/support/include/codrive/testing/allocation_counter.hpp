// SPDX-License-Identifier: Apache-2.0
// The allocation counter behind counting_new.hpp: counters, AllocationScope, and a counter of a
// cyclic thread's allocations driven from the cycle callback. Any number of files may include
// this header; the operators that feed it are in counting_new.hpp (one file per program).
#pragma once

#include <codrive/testing/sanitizers.hpp>

#include <atomic>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <new>

// ThreadSanitizer's runtime (clang's libclang_rt.tsan_cxx, linked whole) defines the global
// operator new/delete itself, so counting_new.hpp cannot replace them there: no allocation is
// counted in a TSan build, and a test that counts aborts with a sentence instead of passing on
// a count of 0. (The TSan stage of tests/run-all.sh leaves the allocation tests out.)

namespace codrive::testing {
#ifdef CODRIVE_TESTING_TSAN
inline constexpr bool kCountsAllocations = false;
#else
inline constexpr bool kCountsAllocations = true;
#endif

/// Ends the program with a sentence when allocations cannot be counted in this build.
inline void require_allocation_counting() {
    if constexpr (!kCountsAllocations) {
        std::fputs("allocation counting: not available under ThreadSanitizer (its runtime owns "
                   "operator new); this test runs in the ASan+UBSan and Release builds\n",
                   stderr);
        std::abort();
    }
}
/// Allocations made by counting threads (any thread, while g_count_all_threads is set).
inline std::atomic<std::uint64_t> g_allocations{0};
/// The bytes those allocations asked for.
inline std::atomic<std::uint64_t> g_allocated_bytes{0};
/// Per thread: count this thread's allocations.
inline thread_local bool g_counting = false;
/// Count the allocations of every thread (threads the test did not start included).
inline std::atomic<bool> g_count_all_threads{false};

inline void note_allocation(std::size_t size) {
    if (g_counting || g_count_all_threads.load(std::memory_order_relaxed)) {
        g_allocations.fetch_add(1, std::memory_order_relaxed);
        g_allocated_bytes.fetch_add(size, std::memory_order_relaxed);
    }
}

[[gnu::noinline]] inline void* counted_malloc(std::size_t size) {
    note_allocation(size);
    return std::malloc(size == 0 ? 1 : size);
}

[[gnu::noinline]] inline void* counted_aligned(std::size_t size, std::align_val_t align) {
    note_allocation(size);
    const auto a = static_cast<std::size_t>(align);
    // aligned_alloc wants a multiple of the alignment.
    return std::aligned_alloc(a, ((size == 0 ? 1 : size) + a - 1) / a * a);
}

/// Counts the allocations made while it lives: by this thread, or by every thread
/// (`all_threads`: the cyclic thread, helper threads).
class AllocationScope {
public:
    explicit AllocationScope(bool all_threads = false)
        : all_(all_threads), start_(g_allocations.load()), start_bytes_(g_allocated_bytes.load()) {
        require_allocation_counting();
        if (all_) {
            g_count_all_threads = true;
        } else {
            g_counting = true;
        }
    }
    ~AllocationScope() { stop(); }
    AllocationScope(const AllocationScope&) = delete;
    AllocationScope& operator=(const AllocationScope&) = delete;
    void stop() {
        if (all_) {
            g_count_all_threads = false;
        } else {
            g_counting = false;
        }
    }
    [[nodiscard]] std::uint64_t count() const { return g_allocations.load() - start_; }
    /// The bytes the counted allocations asked for.
    [[nodiscard]] std::uint64_t bytes() const { return g_allocated_bytes.load() - start_bytes_; }

private:
    bool all_;
    std::uint64_t start_;
    std::uint64_t start_bytes_;
};
} // namespace codrive::testing

namespace codrive::testing {

/// Counts the allocations of the thread that runs a cycle callback (the controller's cyclic
/// thread), from the end of cycle `warmup` to the end of cycle `warmup + cycles`: everything the
/// thread does in between (its loop, sleeps, socket I/O, SYNC, PDOs, axes, the segment's
/// exchange) is counted. Call on_cycle() from the callback; read from any thread once done().
class CycleAllocations {
public:
    CycleAllocations(std::uint64_t warmup, std::uint64_t cycles)
        : warmup_(warmup), cycles_(cycles) {
        require_allocation_counting();
    }
    /// `ready`: false delays the warm-up (e.g. until the axis is enabled).
    void on_cycle(bool ready = true) {
        if (!ready || done()) {
            return;
        }
        const std::uint64_t n = ++seen_;
        if (n == warmup_) {
            start_ = g_allocations.load();
            g_counting = true;
        } else if (n == warmup_ + cycles_) {
            g_counting = false;
            count_.store(g_allocations.load() - start_, std::memory_order_relaxed);
            done_.store(true, std::memory_order_release);
        }
    }
    [[nodiscard]] bool done() const { return done_.load(std::memory_order_acquire); }
    /// Allocations over the counted cycles; valid once done().
    [[nodiscard]] std::uint64_t count() const { return count_.load(std::memory_order_relaxed); }
    [[nodiscard]] std::uint64_t cycles() const { return cycles_; }

private:
    std::uint64_t warmup_;
    std::uint64_t cycles_;
    std::uint64_t seen_ = 0;  ///< callback thread only
    std::uint64_t start_ = 0; ///< callback thread only
    std::atomic<std::uint64_t> count_{0};
    std::atomic<bool> done_{false};
};

} // namespace codrive::testing
