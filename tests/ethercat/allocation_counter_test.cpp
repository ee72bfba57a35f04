// SPDX-License-Identifier: Apache-2.0
// The allocation counter behind the cyclic-thread proofs of this suite
// (ControllerOverEthercat.DedicatedCyclicThreadAllocatesNothingOverAThousandCycles) sees the
// allocations of threads the test did not start, and only when asked to.
#include <gtest/gtest.h>

#include <cstdint>
#include <new>
#include <thread>

// The counting operators themselves are defined once, in controller_ecat_test.cpp.
#include <codrive/testing/allocation_counter.hpp>

using codrive::testing::AllocationScope;

namespace {

void allocate_once() {
    void* volatile p = ::operator new(32);
    ::operator delete(p);
}

} // namespace

TEST(AllocationCounter, AllThreadsScopeSeesAnotherThreadsAllocationAThreadScopeDoesNot) {
    std::uint64_t own_thread_only = 0;
    {
        std::thread t;
        AllocationScope scope;
        t = std::thread(allocate_once); // std::thread's own state: allocated on this thread
        t.join();
        own_thread_only = scope.count();
    }
    std::uint64_t all_threads = 0;
    {
        std::thread t;
        AllocationScope scope(true);
        t = std::thread(allocate_once);
        t.join();
        scope.stop();
        all_threads = scope.count();
    }
    // Both scopes see the std::thread state made on this thread; only the second one sees the
    // allocation the other thread made.
    EXPECT_LE(own_thread_only, 1U);
    EXPECT_EQ(all_threads, own_thread_only + 1);
}
