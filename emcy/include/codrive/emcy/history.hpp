// SPDX-License-Identifier: Apache-2.0
// A bounded per-node EMCY history (newest first), without allocation.
#pragma once

#include <codrive/core/time.hpp>
#include <codrive/emcy/message.hpp>

#include <array>
#include <cstddef>

namespace codrive::emcy {

struct EmcyRecord {
    EmcyMessage message;
    TimePoint time{};
};

/// The last kCapacity EMCYs of one node; older ones are dropped (counted in dropped()).
class EmcyHistory {
public:
    static constexpr std::size_t kCapacity = 16;

    void push(const EmcyRecord& r);
    void clear();
    [[nodiscard]] std::size_t size() const { return size_; }
    [[nodiscard]] bool empty() const { return size_ == 0; }
    /// i = 0 is the newest. The caller keeps i < size().
    [[nodiscard]] const EmcyRecord& operator[](std::size_t i) const;
    [[nodiscard]] std::uint64_t dropped() const { return dropped_; }

private:
    std::array<EmcyRecord, kCapacity> ring_{};
    std::size_t head_ = 0; ///< where the next record goes
    std::size_t size_ = 0;
    std::uint64_t dropped_ = 0;
};

} // namespace codrive::emcy
