// SPDX-License-Identifier: Apache-2.0
// The CiA 402 scenario as transport-neutral steps on drives::Axis: the vcan test (CANopen) and
// the EtherCAT test run the same steps, only the cycle driver and the fault injection differ.
#pragma once

#include <codrive/core/time.hpp>
#include <codrive/drives/axis.hpp>
#include <codrive/drives/transport.hpp>

#include <gtest/gtest.h>

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

namespace codrive::testing::cia402 {

/// How the steps drive the bus: the I/O loop and the per-cycle hook of the transport in use
/// (CANopen: the controller's SYNC callback; EtherCAT: the process-data cycle).
struct CycleDriver {
    Duration period{}; ///< SYNC / process-data cycle
    /// Runs the I/O loop until pred() holds or `timeout` passes; returns pred().
    std::function<bool(const std::function<bool()>& pred, Duration timeout)> run_until;
    /// Installs a hook called once per cycle, after the cycle's inputs arrived and before its
    /// outputs go out (the place for cyclic set-points); an empty function removes it. The hook
    /// gets `on_time` = false when the host, not the drive, disturbed the cycle (CANopen test:
    /// it started more than two periods after the previous one).
    std::function<void(std::function<void(bool on_time)>)> set_cycle_hook;

    void run_for(Duration d) const {
        run_until([] { return false; }, d);
    }
};

/// Runs one asynchronous axis operation to its end. Failure: the axis's error sentence, or
/// "did not finish" after `timeout`.
::testing::AssertionResult run_op(const CycleDriver& d, const std::string& what,
                                  const std::function<void(drives::Axis::Done)>& op,
                                  Duration timeout = seconds(10));

/// Brings the axis to OPERATION ENABLED (fault reset first if needed).
::testing::AssertionResult enable(const CycleDriver& d, drives::Axis& axis);

/// Changes the mode of operation, confirmed by 6061h.
::testing::AssertionResult set_mode(const CycleDriver& d, drives::Axis& axis,
                                    drives::cia402::Mode mode);

/// Homing: mode HM, the method with its speeds, attained + reached; then the actual position
/// must be within `tolerance` of `expected_position`.
::testing::AssertionResult home(const CycleDriver& d, drives::Axis& axis,
                                const drives::HomingParams& params, std::int32_t expected_position,
                                std::int32_t tolerance);

/// A profile-position move: mode PP, set-point handshake, target reached (statusword bit 10);
/// then the actual position must be within `window` of `target`.
::testing::AssertionResult pp_move(const CycleDriver& d, drives::Axis& axis, std::int32_t target,
                                   std::int32_t window, const drives::MoveOptions& options = {});

/// What the PV step measured (velocity actual value 606Ch, drive units).
struct PvFigures {
    std::int32_t at_speed = 0;   ///< 606Ch while running at the target velocity
    std::int32_t after_stop = 0; ///< 606Ch after the stop
};

/// Profile velocity: mode PV, target velocity → target reached; 606Ch (cyclic, must be mapped)
/// must be within `tolerance` of `velocity`; then velocity 0 → 606Ch within `tolerance` of 0
/// and the position stops changing.
::testing::AssertionResult pv_run_and_stop(const CycleDriver& d, drives::Axis& axis,
                                           std::int32_t velocity, std::int32_t tolerance,
                                           PvFigures* figures = nullptr);

/// What the CSP path step measured.
struct PathFigures {
    std::uint64_t cycles = 0;      ///< cycles with a streamed set-point
    std::vector<double> max_error; ///< per axis: max |60F4h| (the drive's following error)
    /// per axis: max |actual − closest set-point of the last `max_latency` cycles| (end to end,
    /// includes transport and scheduling jitter; reported, not asserted)
    std::vector<double> max_path_error;
    std::vector<double> max_travel;         ///< per axis: the path's extent, for scale
    std::vector<std::uint64_t> worst_cycle; ///< per axis: the cycle of max_error
    std::vector<std::uint64_t> cycles_over; ///< per axis: cycles above the tolerance
    std::vector<double> max_error_all;      ///< per axis: max |60F4h| including disturbed cycles
    std::uint64_t disturbed = 0;            ///< cycles within `max_latency` after a late cycle
};

/// Coordinated CSP: all axes to CSP, then jerk-limited straight legs out by `excursion` (per
/// axis, drive units) and back, streamed by drives::CoordinatedMotion one set-point per axis
/// per cycle, until at least `cycles` cycles ran. The following error of an axis is the drive's
/// following error actual value 60F4h (CiA 402: position demand − position actual), which must
/// be in the process data: its maximum must be ≤ `tolerance` over every cycle except those up
/// to `max_latency` cycles after a cycle that started late (reported separately), and every axis
/// must end the path within `tolerance` of its end point. The end-to-end error against the
/// master's set-points (|actual − the closest set-point of the last `max_latency` cycles|) is
/// measured too and reported in `figures`.
::testing::AssertionResult csp_path(const CycleDriver& d, const std::vector<drives::Axis*>& axes,
                                    const std::vector<double>& excursion, std::uint64_t cycles,
                                    double tolerance, PathFigures* figures = nullptr,
                                    unsigned max_latency = 4);

/// The CiA 402 state a quick stop ends in for a 605Ah option code: 5..8 stay in QUICK STOP
/// ACTIVE, 0..4 go on to SWITCH ON DISABLED (CiA 402 §6.3.4, object 605Ah).
[[nodiscard]] drives::cia402::State quick_stop_end_state(std::int16_t option_code);

/// Quick stop while moving: mode PV at `velocity` (motion checked on the actual position),
/// 605Ah read over the transport, quick stop; the statusword must show the state that option
/// code leads to and the position must stop changing (±`standstill` over 100 ms). Then
/// enable again (transition 16 from QUICK STOP ACTIVE, else 2-3-4).
::testing::AssertionResult quick_stop_while_moving(const CycleDriver& d, drives::Axis& axis,
                                                   drives::DriveTransport& transport,
                                                   std::int32_t velocity, std::int32_t standstill,
                                                   std::int16_t* option_code = nullptr);

/// An injected fault: `inject(true)` causes it; the axis must reach FAULT with `expected_code`
/// as its last error code (EMCY), and the profile's vendor text for the code must contain
/// `expected_text`; `inject(false)` removes the cause, fault reset, enable → OPERATION ENABLED.
::testing::AssertionResult fault_and_recover(const CycleDriver& d, drives::Axis& axis,
                                             const std::function<bool(bool on)>& inject,
                                             std::uint16_t expected_code,
                                             const std::string& expected_text);

} // namespace codrive::testing::cia402
