// SPDX-License-Identifier: Apache-2.0
// codrive-ecat-sim --delay-us: every frame goes back a fixed time after the slaves processed
// it, as behind a slow host or a long line. The frames keep their order and their rate; the
// slaves see each one when it arrives.
#pragma once

#include <codrive/core/time.hpp>

#include <algorithm>
#include <cstdint>
#include <deque>
#include <span>
#include <vector>

namespace codrive::sim::ecat {

class DelayLine {
public:
    explicit DelayLine(Duration delay) : delay_(delay) {}

    [[nodiscard]] bool active() const { return delay_ > Duration::zero(); }

    /// Holds a copy of `frame` until `now` + the delay.
    void hold(std::span<const std::uint8_t> frame, TimePoint now) {
        held_.push_back({now + delay_, {frame.begin(), frame.end()}});
    }

    /// When the oldest held frame is due, or `otherwise` if that is earlier or none is held.
    [[nodiscard]] TimePoint next_due(TimePoint otherwise) const {
        return held_.empty() ? otherwise : std::min(otherwise, held_.front().due);
    }

    /// Hands every frame due by `now` to `send`, oldest first.
    template <typename Send>
    void release(TimePoint now, Send&& send) {
        while (!held_.empty() && held_.front().due <= now) {
            send(std::span<const std::uint8_t>(held_.front().frame));
            held_.pop_front();
        }
    }

private:
    struct Held {
        TimePoint due;
        std::vector<std::uint8_t> frame;
    };
    Duration delay_;
    std::deque<Held> held_;
};

} // namespace codrive::sim::ecat
