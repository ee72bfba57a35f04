// SPDX-License-Identifier: Apache-2.0
// A cycle-callback driver for controller tests: enables one axis once its statusword arrived,
// then ramps its CSP target by `step` increments per cycle up to `distance`. Everything runs in
// the cycle callback (in Threading::DedicatedCyclic the axis belongs to the cyclic thread); the
// test thread watches the atomics.
#pragma once

#include <codrive/drives/axis.hpp>

#include <algorithm>
#include <atomic>
#include <cstdint>
#include <string>

namespace codrive::testing {

class EnableThenRamp {
public:
    enum Phase : int { Waiting = 0, Enabling = 1, Moving = 2, Done = 3, Failed = -1 };

    EnableThenRamp(drives::Axis& axis, std::int32_t step, std::int32_t distance)
        : axis_(axis), step_(step), distance_(distance) {}

    /// Call from the controller's cycle callback.
    void on_cycle() {
        const int p = phase_.load(std::memory_order_acquire);
        if (p == Waiting && axis_.has_statusword()) {
            phase_.store(Enabling);
            axis_.enable([this](drives::DriveVoid r) {
                if (!r) {
                    failure_ = r.error().message; // published by the release below
                    phase_.store(Failed, std::memory_order_release);
                    return;
                }
                start_ = axis_.position_actual().value_or(0);
                phase_.store(Moving, std::memory_order_release);
            });
        } else if (p == Moving) {
            offset_ = std::min(offset_ + step_, distance_);
            axis_.set_target_position(start_ + offset_);
            if (offset_ == distance_) {
                phase_.store(Done, std::memory_order_release);
            }
        }
        position_.store(axis_.position_actual().value_or(0), std::memory_order_relaxed);
    }

    [[nodiscard]] int phase() const { return phase_.load(std::memory_order_acquire); }
    [[nodiscard]] bool finished() const { return phase() == Done || phase() == Failed; }
    [[nodiscard]] bool done() const { return phase() == Done; }
    /// Why the enable failed; valid once phase() is Failed.
    [[nodiscard]] const std::string& failure() const { return failure_; }
    /// Position when the ramp began; valid once phase() is Moving or Done.
    [[nodiscard]] std::int32_t start() const { return start_; }
    /// The axis's last position actual value, as seen in the cycle callback.
    [[nodiscard]] std::int32_t position() const {
        return position_.load(std::memory_order_relaxed);
    }

private:
    drives::Axis& axis_;
    const std::int32_t step_;
    const std::int32_t distance_;
    std::atomic<int> phase_{Waiting};
    std::string failure_;
    std::atomic<std::int32_t> position_{0};
    std::int32_t start_ = 0;
    std::int32_t offset_ = 0;
};

} // namespace codrive::testing
