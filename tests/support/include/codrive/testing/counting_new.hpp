// SPDX-License-Identifier: Apache-2.0
// Counting replacements of the global allocation functions, for proving "no allocation on the
// cyclic path". Include this header in exactly ONE source file of a program (it defines every
// replaceable operator new/delete form, aligned and nothrow ones included); count with an
// AllocationScope, or set g_counting on a thread the test does not control (e.g. from a callback
// on the controller's cyclic thread) and read g_allocations.
// A program that gathers several such files (allocation_tests, tests/CMakeLists.txt) compiles them
// with CODRIVE_COUNTING_NEW_ELSEWHERE and defines the operators in tests/support/counting_new.cpp.
#pragma once

#include <cstdlib>
#include <new>

// The replacements pair malloc with free; GCC cannot see that through the replacement and warns.
#pragma GCC diagnostic ignored "-Wmismatched-new-delete"

#include <codrive/testing/allocation_counter.hpp>

#if !defined(CODRIVE_TESTING_TSAN) && !defined(CODRIVE_COUNTING_NEW_ELSEWHERE) // see above

void* operator new(std::size_t size) {
    if (void* p = codrive::testing::counted_malloc(size)) {
        return p;
    }
    throw std::bad_alloc();
}
void* operator new[](std::size_t size) {
    return operator new(size);
}
void* operator new(std::size_t size, const std::nothrow_t&) noexcept {
    return codrive::testing::counted_malloc(size);
}
void* operator new[](std::size_t size, const std::nothrow_t&) noexcept {
    return codrive::testing::counted_malloc(size);
}
void* operator new(std::size_t size, std::align_val_t align) {
    if (void* p = codrive::testing::counted_aligned(size, align)) {
        return p;
    }
    throw std::bad_alloc();
}
void* operator new[](std::size_t size, std::align_val_t align) {
    return operator new(size, align);
}
void* operator new(std::size_t size, std::align_val_t align, const std::nothrow_t&) noexcept {
    return codrive::testing::counted_aligned(size, align);
}
void* operator new[](std::size_t size, std::align_val_t align, const std::nothrow_t&) noexcept {
    return codrive::testing::counted_aligned(size, align);
}
void operator delete(void* p) noexcept {
    std::free(p);
}
void operator delete[](void* p) noexcept {
    std::free(p);
}
void operator delete(void* p, std::size_t) noexcept {
    std::free(p);
}
void operator delete[](void* p, std::size_t) noexcept {
    std::free(p);
}
void operator delete(void* p, const std::nothrow_t&) noexcept {
    std::free(p);
}
void operator delete[](void* p, const std::nothrow_t&) noexcept {
    std::free(p);
}
void operator delete(void* p, std::align_val_t) noexcept {
    std::free(p);
}
void operator delete[](void* p, std::align_val_t) noexcept {
    std::free(p);
}
void operator delete(void* p, std::size_t, std::align_val_t) noexcept {
    std::free(p);
}
void operator delete[](void* p, std::size_t, std::align_val_t) noexcept {
    std::free(p);
}
void operator delete(void* p, std::align_val_t, const std::nothrow_t&) noexcept {
    std::free(p);
}
void operator delete[](void* p, std::align_val_t, const std::nothrow_t&) noexcept {
    std::free(p);
}
#endif // !CODRIVE_TESTING_TSAN && !CODRIVE_COUNTING_NEW_ELSEWHERE
