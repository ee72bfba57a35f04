// SPDX-License-Identifier: Apache-2.0
// Helpers shared by the fuzz targets: a byte reader over the fuzzer input and an invariant check.
// A target that plays the other side of a service records its frames with testing::RecordingBus.
#pragma once

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <span>
#include <string>
#include <vector>

namespace codrive::fuzz {

/// Consumes the fuzzer input front to back; reads past the end yield zeros.
class Input {
public:
    Input(const std::uint8_t* data, std::size_t size) : data_(data), size_(size) {}

    [[nodiscard]] bool empty() const { return pos_ >= size_; }
    [[nodiscard]] std::size_t remaining() const { return size_ - std::min(pos_, size_); }

    std::uint8_t byte() { return pos_ < size_ ? data_[pos_++] : std::uint8_t{0}; }
    std::uint16_t u16() {
        const auto lo = byte();
        return static_cast<std::uint16_t>(lo | (byte() << 8));
    }
    /// Up to `n` bytes (fewer at the end of the input).
    std::span<const std::uint8_t> bytes(std::size_t n) {
        const std::size_t take = std::min(n, remaining());
        std::span<const std::uint8_t> out(data_ + pos_, take);
        pos_ += take;
        return out;
    }

private:
    const std::uint8_t* data_;
    std::size_t size_;
    std::size_t pos_ = 0;
};

/// A broken invariant: print why, then abort so libFuzzer saves the input as a crash.
[[noreturn]] inline void invariant_failed(const char* what) {
    std::fprintf(stderr, "fuzz invariant violated: %s\n", what);
    std::abort();
}

#define CODRIVE_FUZZ_CHECK(cond)                                                                   \
    do {                                                                                           \
        if (!(cond)) {                                                                             \
            ::codrive::fuzz::invariant_failed(#cond);                                              \
        }                                                                                          \
    } while (false)

} // namespace codrive::fuzz
