// SPDX-License-Identifier: Apache-2.0
// The allocation counter of the no-allocation proofs sees allocations of threads the test did not
// start (the controller's cyclic thread is one), and only when asked to.
#include <gtest/gtest.h>

#include <cstdint>
#include <new>
#include <thread>

// One program-wide counting operator new (included once per program).
#include <codrive/testing/counting_new.hpp>

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
