// SPDX-License-Identifier: Apache-2.0
// The safe stop of one axis when its master stops (controller shutdown, `codrive drive` on a
// signal): quick stop if it is enabled, then disable voltage, within one time budget.
#pragma once

#include <codrive/core/time.hpp>
#include <codrive/drives/axis.hpp>

namespace codrive::drives {

/// Whether an axis in `state` needs a safe stop: true in OPERATION ENABLED, SWITCHED ON, READY
/// TO SWITCH ON and QUICK STOP ACTIVE (power stage on, or one command from it).
[[nodiscard]] bool needs_safe_stop(cia402::State state);

/// Brings `axis` to SWITCH ON DISABLED (no torque) by `deadline` (CiA 402 §6.3 state machine):
/// OPERATION ENABLED gets quick stop (transition 11: the drive decelerates on its quick-stop
/// ramp, 6085h / 605Ah) with at most half of the time left, then disable voltage (12) with all
/// the time left; SWITCHED ON, READY TO SWITCH ON and QUICK STOP ACTIVE get disable voltage
/// (7, 10, 12). A running operation (a move, homing, an enable) is cancelled by it: its callback
/// gets DriveErrc::Cancelled. The disable runs even when the quick stop failed (timed out).
///
/// Returns false, without calling `done`, when the axis needs no stop (needs_safe_stop() is
/// false). Otherwise `done` runs exactly once (possibly before this returns): success, the
/// quick-stop error (DriveErrc::Timeout: the drive did not answer) or the disable error. If the
/// axis operation is cancelled (Axis::cancel(), or another operation started on the axis), the
/// sequence ends there and `done` gets DriveErrc::Cancelled. `clock` tells the time left when
/// the quick stop ends; it and `axis` must outlive the sequence.
bool safe_stop(Axis& axis, TimePoint deadline, const IClock& clock, Axis::Done done);

} // namespace codrive::drives
