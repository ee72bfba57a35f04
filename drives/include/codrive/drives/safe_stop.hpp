// SPDX-License-Identifier: Apache-2.0
// The safe stop of one axis when its master stops (controller shutdown, `codrive drive` on a
// signal): quick stop if it is enabled, standstill, then disable voltage, within one budget.
#pragma once

#include <codrive/core/time.hpp>
#include <codrive/drives/axis.hpp>

namespace codrive::drives {

/// Whether an axis in `state` needs a safe stop: true in OPERATION ENABLED, SWITCHED ON, READY
/// TO SWITCH ON and QUICK STOP ACTIVE (power stage on, or one command from it).
[[nodiscard]] bool needs_safe_stop(cia402::State state);

/// Brings `axis` to SWITCH ON DISABLED (no torque) by `deadline` (CiA 402 §6.3 state machine)
/// without ever letting a moving motor coast: OPERATION ENABLED gets quick stop (transition
/// 11: the drive decelerates on its quick-stop ramp, 6085h / 605Ah) and the sequence waits for
/// standstill — SWITCH ON DISABLED reached by the drive itself (605Ah 0..4) or QUICK STOP
/// ACTIVE with statusword bit 10 (605Ah 5..8) — with the budget minus a reserve of
/// min(budget / 4, 200 ms); then disable voltage (transition 12) with all the time left. An
/// axis found in QUICK STOP ACTIVE gets the same wait for standstill. SWITCHED ON and READY TO
/// SWITCH ON get disable voltage (7, 10). A running operation (a move, homing, an enable) is
/// cancelled by it: its callback gets DriveErrc::Cancelled.
///
/// When the budget runs out while the drive is still on its ramp (QUICK STOP ACTIVE, bit 10
/// clear), no disable voltage is sent — it would cut the ramp — and `done` gets the quick
/// stop's DriveErrc::Timeout; the quick stop stays commanded and the drive ends its ramp on its
/// own. When the drive never entered the quick stop (it did not answer), the disable is still
/// tried.
///
/// Returns false, without calling `done`, when the axis needs no stop (needs_safe_stop() is
/// false). Otherwise `done` runs exactly once (possibly before this returns): success, the
/// quick-stop error (DriveErrc::Timeout: the drive did not answer) or the disable error. If the
/// axis operation is cancelled (Axis::cancel(), or another operation started on the axis), the
/// sequence ends there and `done` gets DriveErrc::Cancelled. `clock` tells the time left when
/// the quick stop ends; it and `axis` must outlive the sequence.
bool safe_stop(Axis& axis, TimePoint deadline, const IClock& clock, Axis::Done done);

} // namespace codrive::drives
