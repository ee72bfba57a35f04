// SPDX-License-Identifier: Apache-2.0
// Counting replacements of the global allocation functions, for proving "no allocation on the
// cyclic path". Include this header in exactly ONE source file of a program (it defines the
// replaceable operator new/delete forms); set g_counting on the measuring thread and read
// g_allocations.
#pragma once

#include <atomic>
#include <cstdint>
#include <cstdlib>
#include <new>

// The replacements pair malloc with free; GCC cannot see that through the replacement and warns.
#pragma GCC diagnostic ignored "-Wmismatched-new-delete"

namespace codrive::testing {
/// Allocations made by threads whose g_counting was true.
inline std::atomic<std::uint64_t> g_allocations{0};
/// Per thread: count this thread's allocations.
inline thread_local bool g_counting = false;
} // namespace codrive::testing

void* operator new(std::size_t size) {
    if (codrive::testing::g_counting) {
        codrive::testing::g_allocations.fetch_add(1, std::memory_order_relaxed);
    }
    if (void* p = std::malloc(size == 0 ? 1 : size)) {
        return p;
    }
    throw std::bad_alloc();
}
void operator delete(void* p) noexcept {
    std::free(p);
}
void operator delete(void* p, std::size_t) noexcept {
    std::free(p);
}
// Every other replaceable form too, so no allocation pairs with the runtime's own operators.
void* operator new(std::size_t size, const std::nothrow_t&) noexcept {
    if (codrive::testing::g_counting) {
        codrive::testing::g_allocations.fetch_add(1, std::memory_order_relaxed);
    }
    return std::malloc(size == 0 ? 1 : size);
}
void* operator new[](std::size_t size) {
    return operator new(size);
}
void* operator new[](std::size_t size, const std::nothrow_t& tag) noexcept {
    return operator new(size, tag);
}
void operator delete(void* p, const std::nothrow_t&) noexcept {
    std::free(p);
}
void operator delete[](void* p) noexcept {
    std::free(p);
}
void operator delete[](void* p, std::size_t) noexcept {
    std::free(p);
}
void operator delete[](void* p, const std::nothrow_t&) noexcept {
    std::free(p);
}
