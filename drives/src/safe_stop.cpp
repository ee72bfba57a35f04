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

/// Kept for the disable after the quick stop: a few cycles or SDO round trips.
constexpr Duration kDisableReserve = milliseconds(200);

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
    if (s != cia402::State::OperationEnabled && s != cia402::State::QuickStopActive) {
        axis.disable(std::move(done), left(deadline, clock)); // 7, 10: no motion to stop
        return true;
    }
    // The quick stop ends at standstill (Axis::quick_stop); it gets the budget but the
    // disable's reserve. A drive already in QUICK STOP ACTIVE may still be on its ramp: it
    // gets the same wait.
    const Duration budget = left(deadline, clock);
    const Duration reserve = std::min<Duration>(budget / 4, kDisableReserve);
    auto shared_done = std::make_shared<Axis::Done>(std::move(done));
    axis.quick_stop(
        [ax, ck, deadline, shared_done](DriveVoid qs) {
            if (cancelled(qs)) {
                (*shared_done)(std::move(qs));
                return;
            }
            if (!qs && ax->state() == cia402::State::QuickStopActive) {
                // Still decelerating when the budget ran out: disable voltage (transition 12)
                // now would cut the ramp and let the motor coast. The quick stop stays
                // commanded and the drive finishes its ramp on its own.
                (*shared_done)(std::move(qs));
                return;
            }
            // Stopped (QUICK STOP ACTIVE with bit 10, or SWITCH ON DISABLED already), or the
            // drive never entered the quick stop: disable voltage with what is left.
            ax->disable(
                [qs, shared_done](DriveVoid r) { (*shared_done)(!qs && r ? qs : std::move(r)); },
                left(deadline, *ck));
        },
        std::max<Duration>(budget - reserve, milliseconds(1)));
    return true;
}

} // namespace codrive::drives
