// SPDX-License-Identifier: Apache-2.0
// The lock-free hand-offs between the cyclic and the acyclic thread, driven by two real threads
// (run under ThreadSanitizer too): the SPSC ring keeps every value and its order, the stats
// seqlock never yields a torn snapshot.
#include "../../controller/src/seqlock.hpp"
#include "../../controller/src/spsc_ring.hpp"

#include <codrive/controller/controller.hpp>

#include <gtest/gtest.h>

#include <array>
#include <atomic>
#include <chrono>
#include <cstdint>
#include <thread>

using codrive::controller::ControllerStats;
using codrive::controller::Seqlock;
using codrive::controller::SpscRing;

namespace {

/// A request as big as the controller's: several words that must arrive together.
struct Message {
    std::uint64_t sequence = 0;
    std::array<std::uint64_t, 4> payload{};
};

} // namespace

TEST(SpscRingThreads, TwoThreadsPassTwoHundredThousandValuesInOrderWithoutLoss) {
    constexpr std::uint64_t kCount = 200000;
    SpscRing<Message, 64> ring;
    std::atomic<std::uint64_t> refused{0};
    std::thread producer([&] {
        for (std::uint64_t i = 1; i <= kCount;) {
            Message m;
            m.sequence = i;
            m.payload.fill(i * 3);
            if (ring.push(m)) {
                ++i;
            } else {
                refused.fetch_add(1, std::memory_order_relaxed); // full: the consumer is behind
                std::this_thread::yield();
            }
        }
    });
    std::uint64_t expected = 1;
    std::uint64_t mismatches = 0;
    Message m;
    while (expected <= kCount) {
        if (!ring.pop(m)) {
            std::this_thread::yield();
            continue;
        }
        if (m.sequence != expected || m.payload[0] != expected * 3 ||
            m.payload[3] != expected * 3) {
            ++mismatches;
        }
        ++expected;
    }
    producer.join();
    EXPECT_EQ(mismatches, 0U);
    EXPECT_EQ(expected, kCount + 1);
    EXPECT_TRUE(ring.empty());
    std::printf("SPSC ring, 2 threads: %llu values, producer found it full %llu times\n",
                static_cast<unsigned long long>(kCount),
                static_cast<unsigned long long>(refused.load()));
}

TEST(StatsSnapshot, ReaderOnAnotherThreadNeverSeesATornSnapshot) {
    // The writer keeps every field equal to one counter; a torn read (half of one store, half
    // of another, or half of a 64-bit value) shows up as fields that differ. The writer stores
    // until the reader is done, so the two overlap even on a busy machine. Between two stores it
    // spins a little, as the cyclic thread waits for its next cycle: a writer that stores
    // back to back leaves a reader almost no window without a store in progress (each read
    // retries), and the test then ran into its 10 s limit with two CPUs busy all the time.
    Seqlock<ControllerStats> cell;
    std::atomic<bool> stop{false};
    std::atomic<std::uint64_t> stores{0};
    std::thread writer([&] {
        std::uint64_t k = 0;
        while (!stop.load(std::memory_order_relaxed)) {
            ++k;
            ControllerStats s;
            const std::uint64_t v = k * 0x100000001ULL; // both 32-bit halves change
            s.cycles = v;
            s.overruns = v;
            s.tpdos_received = v;
            s.tpdos_missing = v;
            s.rpdos_sent = v;
            s.ecat_frame_errors = v;
            s.period_error_max = codrive::Duration{static_cast<std::int64_t>(k)};
            cell.store(s);
            for (int spin = 0; spin < 64 && !stop.load(std::memory_order_relaxed); ++spin) {
            }
        }
        stores.store(k, std::memory_order_release);
    });
    std::uint64_t torn = 0;
    std::uint64_t last = 0;
    std::uint64_t backwards = 0;
    std::uint64_t changes = 0;
    // Read until both threads demonstrably ran side by side: 200,000 reads that saw at least
    // 1,000 different stores (at most 10 s on a machine too busy to run them together; there at
    // least a few overlaps are required).
    std::uint64_t reads = 0;
    const auto give_up = std::chrono::steady_clock::now() + std::chrono::seconds(10);
    while ((reads < 200000 || changes < 1000) && std::chrono::steady_clock::now() < give_up) {
        ++reads;
        const ControllerStats s = cell.load();
        const std::uint64_t v = s.cycles;
        if (s.overruns != v || s.tpdos_received != v || s.tpdos_missing != v || s.rpdos_sent != v ||
            s.ecat_frame_errors != v ||
            static_cast<std::uint64_t>(s.period_error_max.count()) * 0x100000001ULL != v) {
            ++torn;
        }
        if (v < last) {
            ++backwards;
        }
        if (v != last) {
            ++changes;
        }
        last = v;
    }
    stop.store(true, std::memory_order_relaxed);
    writer.join();
    std::printf("seqlock, 2 threads: %llu reads saw %llu different stores of %llu\n",
                static_cast<unsigned long long>(reads), static_cast<unsigned long long>(changes),
                static_cast<unsigned long long>(stores.load()));
    EXPECT_EQ(torn, 0U) << "of " << reads << " reads";
    EXPECT_EQ(backwards, 0U);
    EXPECT_GE(changes, 10U) << "the reader hardly saw the writer at work";
    EXPECT_EQ(cell.load().cycles, stores.load() * 0x100000001ULL); // the last store stays
}
