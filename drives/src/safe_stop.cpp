// SPDX-License-Identifier: Apache-2.0
// Safe stop of one axis: quick stop then disable voltage within a time budget.
#include <codrive/drives/safe_stop.hpp>

#include <algorithm>
#include <memory>

namespace codrive::drives {

namespace {

/// What is left of the budget, never zero (zero means "the axis's default" to Axis).
Duration left(TimePoint deadline, const IClock& clock) {
    return std::max<Duration>(deadline - clock.now(), milliseconds(1));
}

bool cancelled(const DriveVoid& r) {
    return !r && r.error().code == make_error_code(DriveErrc::Cancelled);
}

} // namespace

bool needs_safe_stop(cia402::State state) {
    using cia402::State;
    return state == State::OperationEnabled || state == State::SwitchedOn ||
           state == State::ReadyToSwitchOn || state == State::QuickStopActive;
}

bool safe_stop(Axis& axis, TimePoint deadline, const IClock& clock, Axis::Done done) {
    const cia402::State s = axis.state();
    if (!needs_safe_stop(s)) {
        return false;
    }
    Axis* ax = &axis;
    const IClock* ck = &clock;
    if (s != cia402::State::OperationEnabled) {
        axis.disable(std::move(done), left(deadline, clock));
        return true;
    }
    // The quick stop gets half of what is left, so the disable always has the other half.
    auto shared_done = std::make_shared<Axis::Done>(std::move(done));
    axis.quick_stop(
        [ax, ck, deadline, shared_done](DriveVoid qs) {
            if (cancelled(qs)) {
                (*shared_done)(std::move(qs));
                return;
            }
            ax->disable(
                [qs, shared_done](DriveVoid r) { (*shared_done)(!qs && r ? qs : std::move(r)); },
                left(deadline, *ck));
        },
        left(deadline, clock) / 2);
    return true;
}

} // namespace codrive::drives
