// SPDX-License-Identifier: Apache-2.0
// The transport-neutral CiA 402 scenario steps (enable, homing, PP, PV, coordinated CSP path,
// quick stop, fault and recovery) on drives::Axis.
#include <codrive/drives/coordinated.hpp>
#include <codrive/testing/cia402_scenario.hpp>

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <limits>
#include <memory>

namespace codrive::testing::cia402 {

using drives::Axis;
using drives::DriveVoid;
using drives::cia402::Mode;
using drives::cia402::State;
using ::testing::AssertionFailure;
using ::testing::AssertionResult;
using ::testing::AssertionSuccess;

AssertionResult run_op(const CycleDriver& d, const std::string& what,
                       const std::function<void(Axis::Done)>& op, Duration timeout) {
    // Shared so that a late completion after a timeout does not write to a dead frame.
    auto result = std::make_shared<std::optional<DriveVoid>>();
    op([result](DriveVoid r) { *result = std::move(r); });
    d.run_until([&] { return result->has_value(); }, timeout);
    if (!result->has_value()) {
        return AssertionFailure() << what << " did not finish within " << to_ms(timeout) << " ms";
    }
    if (!**result) {
        return AssertionFailure() << what << " failed: " << (*result)->error().message;
    }
    return AssertionSuccess();
}

AssertionResult enable(const CycleDriver& d, Axis& axis) {
    return run_op(d, axis.name() + " enable",
                  [&](Axis::Done done) { axis.enable(done, seconds(5)); });
}

AssertionResult set_mode(const CycleDriver& d, Axis& axis, Mode mode) {
    return run_op(d,
                  fmt::format("{} mode {}", axis.name(),
                              drives::cia402::mode_name(static_cast<std::int8_t>(mode))),
                  [&](Axis::Done done) { axis.set_mode(mode, done, seconds(5)); });
}

AssertionResult home(const CycleDriver& d, Axis& axis, const drives::HomingParams& params,
                     std::int32_t expected_position, std::int32_t tolerance) {
    if (auto r = set_mode(d, axis, Mode::Homing); !r) {
        return r;
    }
    if (auto r = run_op(
            d, fmt::format("{} homing (method {})", axis.name(), params.method),
            [&](Axis::Done done) { axis.home(params, done, seconds(30)); }, seconds(31));
        !r) {
        return r;
    }
    d.run_for(d.period * 3); // a fresh actual value after the reference was set
    const auto pos = axis.position_actual();
    if (!pos) {
        return AssertionFailure() << axis.name() << ": no actual position after homing";
    }
    if (std::abs(static_cast<std::int64_t>(*pos) - expected_position) > tolerance) {
        return AssertionFailure() << axis.name() << ": homed to " << *pos << ", expected "
                                  << expected_position << " ± " << tolerance;
    }
    return AssertionSuccess();
}

AssertionResult pp_move(const CycleDriver& d, Axis& axis, std::int32_t target, std::int32_t window,
                        const drives::MoveOptions& options) {
    if (auto r = set_mode(d, axis, Mode::ProfilePosition); !r) {
        return r;
    }
    if (auto r = run_op(
            d, fmt::format("{} PP move to {}", axis.name(), target),
            [&](Axis::Done done) { axis.move_to(target, options, done, seconds(30)); },
            seconds(31));
        !r) {
        return r;
    }
    if ((axis.statusword() & drives::cia402::sw::kTargetReached) == 0) {
        return AssertionFailure() << axis.name() << ": move done but statusword 0x" << std::hex
                                  << axis.statusword() << " has no target reached (bit 10)";
    }
    const auto pos = axis.position_actual();
    if (!pos || std::abs(static_cast<std::int64_t>(*pos) - target) > window) {
        return AssertionFailure() << axis.name() << ": target reached at "
                                  << (pos ? std::to_string(*pos) : std::string("?")) << ", target "
                                  << target << " ± " << window;
    }
    return AssertionSuccess();
}

namespace {

/// The actual position, checked: the steps need it cyclically.
AssertionResult position(const Axis& axis, std::int32_t& out) {
    const auto p = axis.position_actual();
    if (!p) {
        return AssertionFailure() << axis.name() << ": position actual value (6064h) not received";
    }
    out = *p;
    return AssertionSuccess();
}

/// True if the position moved less than `standstill` over `window`.
AssertionResult stands_still(const CycleDriver& d, const Axis& axis, std::int32_t standstill,
                             Duration window) {
    std::int32_t before = 0;
    std::int32_t after = 0;
    if (auto r = position(axis, before); !r) {
        return r;
    }
    d.run_for(window);
    if (auto r = position(axis, after); !r) {
        return r;
    }
    if (std::abs(static_cast<std::int64_t>(after) - before) > standstill) {
        return AssertionFailure() << axis.name() << ": still moving (" << before << " → " << after
                                  << " in " << to_ms(window) << " ms)";
    }
    return AssertionSuccess();
}

} // namespace

AssertionResult pv_run_and_stop(const CycleDriver& d, Axis& axis, std::int32_t velocity,
                                std::int32_t tolerance, PvFigures* figures) {
    if (auto r = set_mode(d, axis, Mode::ProfileVelocity); !r) {
        return r;
    }
    if (auto r = run_op(d, fmt::format("{} PV at {}", axis.name(), velocity),
                        [&](Axis::Done done) { axis.run_velocity(velocity, done, seconds(10)); });
        !r) {
        return r;
    }
    // Target reached can come from a statusword sampled just before the new target acted:
    // give 606Ch the ramp time to arrive.
    d.run_until(
        [&] {
            const auto v = axis.velocity_actual();
            return v && std::abs(static_cast<std::int64_t>(*v) - velocity) <= tolerance;
        },
        seconds(3));
    d.run_for(d.period * 10);
    const auto at_speed = axis.velocity_actual();
    if (!at_speed) {
        return AssertionFailure() << axis.name()
                                  << ": velocity actual value (606Ch) is not in the process data";
    }
    if (std::abs(static_cast<std::int64_t>(*at_speed) - velocity) > tolerance) {
        return AssertionFailure() << axis.name() << ": 606Ch = " << *at_speed << " at target "
                                  << velocity << " ± " << tolerance;
    }
    if (auto r = run_op(d, axis.name() + " PV stop",
                        [&](Axis::Done done) { axis.run_velocity(0, done, seconds(10)); });
        !r) {
        return r;
    }
    // Target reached (bit 10) says the velocity is inside the velocity window (606Dh); give
    // the ramp the rest of the way to standstill.
    d.run_until(
        [&] { return std::abs(axis.velocity_actual().value_or(velocity)) <= tolerance / 10; },
        seconds(2));
    const std::int32_t after = axis.velocity_actual().value_or(velocity);
    if (figures != nullptr) {
        figures->at_speed = *at_speed;
        figures->after_stop = after;
    }
    if (std::abs(after) > tolerance) {
        return AssertionFailure() << axis.name() << ": 606Ch = " << after << " after the stop";
    }
    return stands_still(d, axis, std::max(tolerance / 10, 2), milliseconds(100));
}

AssertionResult csp_path(const CycleDriver& d, const std::vector<Axis*>& axes,
                         const std::vector<double>& excursion, std::uint64_t cycles,
                         double tolerance, PathFigures* figures, unsigned max_latency) {
    const auto n = static_cast<Eigen::Index>(axes.size());
    if (axes.empty() || excursion.size() != axes.size()) {
        return AssertionFailure() << "csp_path: one excursion per axis";
    }
    Eigen::VectorXd home(n);
    for (Eigen::Index i = 0; i < n; ++i) {
        Axis& a = *axes[static_cast<std::size_t>(i)];
        if (auto r = set_mode(d, a, Mode::CyclicSyncPosition); !r) {
            return r;
        }
        std::int32_t p = 0;
        if (auto r = position(a, p); !r) {
            return r;
        }
        a.set_target_position(p); // start from where the axis stands
        home[i] = p;
    }
    d.run_for(d.period * 3);
    // Legs sized so that one leg lasts about half the requested cycles.
    const double seconds_per_leg =
        std::chrono::duration<double>(d.period).count() * static_cast<double>(cycles) / 2.0;
    Eigen::VectorXd far(n);
    Eigen::VectorXd vmax(n);
    Eigen::VectorXd amax(n);
    Eigen::VectorXd jmax(n);
    for (Eigen::Index i = 0; i < n; ++i) {
        const double e = excursion[static_cast<std::size_t>(i)];
        far[i] = home[i] + e;
        // Cruise for about half the leg: v = 1.6·|e|/T, ramps a quarter of the leg each.
        vmax[i] = std::max(1.0, 1.6 * std::abs(e) / seconds_per_leg);
        amax[i] = vmax[i] / (0.2 * seconds_per_leg);
        jmax[i] = amax[i] / (0.05 * seconds_per_leg);
    }

    drives::CoordinatedMotion motion(axes, d.period);
    std::vector<Eigen::VectorXd> sent; // set-point per cycle
    sent.reserve(cycles + 600);
    std::vector<double> max_error(axes.size(), 0.0);
    std::vector<double> max_path_error(axes.size(), 0.0);
    std::vector<std::uint64_t> worst_cycle(axes.size(), 0);
    std::vector<std::uint64_t> over(axes.size(), 0);
    std::uint64_t streamed = 0;
    bool outward = true;
    Eigen::VectorXd last_end = home;
    bool leg_running = false;
    std::string failure;
    const auto start_leg = [&] {
        const Eigen::VectorXd& end = outward ? far : home;
        last_end = end;
        auto r = motion.start(end, vmax, amax, jmax, drives::ProfileShape::JerkLimited,
                              [&](DriveVoid res) {
                                  leg_running = false;
                                  if (!res && failure.empty()) {
                                      failure = res.error().message;
                                  }
                              });
        if (!r) {
            failure = r.error().message;
            return;
        }
        leg_running = true;
        outward = !outward;
    };
    std::vector<double> max_error_all(axes.size(), 0.0);
    std::uint64_t disturbed = 0;
    unsigned quiet = 0; // cycles still disturbed after a late one
    d.set_cycle_hook([&](bool on_time) {
        if (!failure.empty()) {
            return;
        }
        if (!on_time) {
            quiet = max_latency + 1;
        }
        const bool counted = quiet == 0;
        if (quiet > 0) {
            --quiet;
            ++disturbed;
        }
        // The drive's following error (60F4h) and the actual values of this cycle against the
        // recent set-points.
        if (!sent.empty()) {
            for (std::size_t i = 0; i < axes.size(); ++i) {
                const auto p = axes[i]->position_actual();
                const auto fe = axes[i]->following_error_actual();
                if (!p || !fe) {
                    failure = axes[i]->name() + ": position actual value (6064h) or following " +
                              "error actual value (60F4h) not in the process data";
                    return;
                }
                const double drive_error = std::abs(static_cast<double>(*fe));
                max_error_all[i] = std::max(max_error_all[i], drive_error);
                if (counted && drive_error > max_error[i]) {
                    max_error[i] = drive_error;
                    worst_cycle[i] = sent.size();
                }
                if (counted && drive_error > tolerance) {
                    ++over[i];
                }
                double best = std::numeric_limits<double>::infinity();
                for (unsigned lag = 1; lag <= max_latency && lag <= sent.size(); ++lag) {
                    const double sp = sent[sent.size() - lag][static_cast<Eigen::Index>(i)];
                    best = std::min(best, std::abs(static_cast<double>(*p) - std::round(sp)));
                }
                max_path_error[i] = std::max(max_path_error[i], best);
            }
        }
        if (streamed >= cycles && !leg_running) {
            return;
        }
        if (!leg_running) {
            start_leg();
            if (!failure.empty()) {
                return;
            }
        }
        motion.on_sync();
        sent.push_back(motion.last_setpoint());
        ++streamed;
    });
    const Duration budget = d.period * static_cast<std::int64_t>(cycles * 3 + 2000);
    const bool finished = d.run_until(
        [&] { return !failure.empty() || (streamed >= cycles && !leg_running); }, budget);
    d.run_for(d.period * static_cast<std::int64_t>(max_latency + 1)); // last actual values
    d.set_cycle_hook({});
    if (figures != nullptr) {
        figures->cycles = streamed;
        figures->max_error = max_error;
        figures->max_path_error = max_path_error;
        figures->max_error_all = max_error_all;
        figures->disturbed = disturbed;
        figures->worst_cycle = worst_cycle;
        figures->cycles_over = over;
        figures->max_travel.clear();
        for (double e : excursion) {
            figures->max_travel.push_back(std::abs(e));
        }
    }
    if (!failure.empty()) {
        return AssertionFailure() << "CSP path failed after " << streamed << " cycles: " << failure;
    }
    if (!finished || streamed < cycles) {
        return AssertionFailure() << "CSP path streamed only " << streamed << " of " << cycles
                                  << " cycles";
    }
    for (std::size_t i = 0; i < axes.size(); ++i) {
        if (max_error[i] > tolerance) {
            return AssertionFailure() << axes[i]->name() << ": max following error " << max_error[i]
                                      << " > tolerance " << tolerance;
        }
        // Every axis must have arrived at the end point of the last leg.
        const auto p = axes[i]->position_actual();
        const double end = last_end[static_cast<Eigen::Index>(i)];
        if (!p || std::abs(static_cast<double>(*p) - end) > tolerance) {
            return AssertionFailure() << axes[i]->name() << ": path ended at "
                                      << (p ? std::to_string(*p) : std::string("?"))
                                      << ", expected " << end << " ± " << tolerance;
        }
        if (axes[i]->state() != State::OperationEnabled) {
            return AssertionFailure()
                   << axes[i]->name()
                   << " left OPERATION ENABLED: " << drives::cia402::to_string(axes[i]->state());
        }
    }
    return AssertionSuccess();
}

State quick_stop_end_state(std::int16_t option_code) {
    return option_code >= 5 && option_code <= 8 ? State::QuickStopActive : State::SwitchOnDisabled;
}

AssertionResult quick_stop_while_moving(const CycleDriver& d, Axis& axis,
                                        drives::DriveTransport& transport, std::int32_t velocity,
                                        std::int32_t standstill, std::int16_t* option_code) {
    std::optional<drives::DriveResult<std::int16_t>> option;
    transport.read_as<std::int16_t>(
        axis.index(drives::cia402::obj::kQuickStopOption), 0,
        [&option](drives::DriveResult<std::int16_t> r) { option = std::move(r); });
    d.run_until([&] { return option.has_value(); }, seconds(2));
    if (!option || !*option) {
        return AssertionFailure() << axis.name() << ": reading 605Ah failed: "
                                  << (option ? option->error().message : "timeout");
    }
    const std::int16_t code = **option;
    if (option_code != nullptr) {
        *option_code = code;
    }
    if (auto r = set_mode(d, axis, Mode::ProfileVelocity); !r) {
        return r;
    }
    if (auto r = run_op(d, fmt::format("{} PV at {}", axis.name(), velocity),
                        [&](Axis::Done done) { axis.run_velocity(velocity, done, seconds(10)); });
        !r) {
        return r;
    }
    if (stands_still(d, axis, standstill, milliseconds(100))) {
        return AssertionFailure() << axis.name() << ": not moving before the quick stop";
    }
    if (auto r = run_op(d, axis.name() + " quick stop",
                        [&](Axis::Done done) { axis.quick_stop(done, seconds(5)); });
        !r) {
        return r;
    }
    const State expected = quick_stop_end_state(code);
    d.run_until([&] { return axis.state() == expected; }, seconds(2));
    if (axis.state() != expected) {
        return AssertionFailure() << axis.name() << ": after quick stop with 605Ah = " << code
                                  << " the statusword 0x" << std::hex << axis.statusword()
                                  << " shows " << drives::cia402::to_string(axis.state())
                                  << ", expected " << drives::cia402::to_string(expected);
    }
    if (expected == State::QuickStopActive &&
        (axis.statusword() & drives::cia402::sw::kQuickStop) != 0) {
        return AssertionFailure() << axis.name() << ": QUICK STOP ACTIVE needs statusword bit 5 "
                                  << "clear, statusword 0x" << std::hex << axis.statusword();
    }
    // The state is entered when the quick-stop ramp starts, not when it ends: the axis must come
    // to a standstill on the ramp of 6085h (the DS-BVS default, 1000 rpm/s, needs 0.6 s from
    // 600 rpm: DS-BVS manual §6.2.122), so allow up to 3 s of 100 ms standstill checks.
    AssertionResult still = AssertionFailure();
    for (int i = 0; i < 30 && !(still = stands_still(d, axis, standstill, milliseconds(100)));
         ++i) {
    }
    if (!still) {
        return still;
    }
    // Leave PV with target velocity 0 so that enabling again does not restart the motion.
    axis.set_target_velocity(0);
    return enable(d, axis);
}

AssertionResult fault_and_recover(const CycleDriver& d, Axis& axis,
                                  const std::function<bool(bool on)>& inject,
                                  std::uint16_t expected_code, const std::string& expected_text) {
    if (!inject(true)) {
        return AssertionFailure() << axis.name() << ": fault injection failed";
    }
    d.run_until([&] { return axis.state() == State::Fault && axis.last_error_code() != 0; },
                seconds(3));
    if (axis.state() != State::Fault) {
        return AssertionFailure() << axis.name() << ": the injected fault left the axis in "
                                  << drives::cia402::to_string(axis.state());
    }
    if (axis.last_error_code() != expected_code) {
        return AssertionFailure() << axis.name() << ": EMCY code 0x" << std::hex
                                  << axis.last_error_code() << ", expected 0x" << expected_code;
    }
    const std::string text = axis.profile().fault_text(expected_code);
    if (text.find(expected_text) == std::string::npos) {
        return AssertionFailure() << axis.name() << ": vendor text for 0x" << std::hex
                                  << expected_code << " is \"" << text << "\", expected \""
                                  << expected_text << "\"";
    }
    const std::string diagnosis = axis.diagnose();
    if (!inject(false)) {
        return AssertionFailure() << axis.name() << ": removing the fault cause failed";
    }
    if (auto r = run_op(d, axis.name() + " fault reset",
                        [&](Axis::Done done) { axis.fault_reset(done, seconds(5)); });
        !r) {
        return r << " (diagnosis: " << diagnosis << ")";
    }
    if (auto r = enable(d, axis); !r) {
        return r;
    }
    if (axis.state() != State::OperationEnabled) {
        return AssertionFailure() << axis.name() << " is in "
                                  << drives::cia402::to_string(axis.state())
                                  << " after fault reset and enable";
    }
    return AssertionSuccess();
}

} // namespace codrive::testing::cia402
