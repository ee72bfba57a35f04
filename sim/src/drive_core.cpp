// SPDX-License-Identifier: Apache-2.0
// The simulated CiA 402 axis: device control state machine, faults and the step loop.
#include <codrive/sim/drive_core.hpp>

#include <algorithm>
#include <cmath>

namespace codrive::sim {

namespace cia = drives::cia402;
namespace obj = drives::cia402::obj;

DriveCore::DriveCore(ObjectDictionary& od, const SimProfile& profile, unsigned axis,
                     std::optional<MachineConfig> machine)
    : od_(od), profile_(profile), axis_(axis), motor_([&] {
          MachineConfig m = machine.value_or(profile.machine);
          m.counts_per_rev = profile.counts_per_rev;
          return m;
      }()) {
    install_objects();
    if (const auto offset = static_cast<std::uint16_t>(index(0x6000) - 0x6000);
        TouchProbe::present(od_, offset)) {
        probe_ = std::make_unique<TouchProbe>(od_, offset); // AKD2G §4.1.5
    }
    od_.on_write(index(obj::kControlword),
                 [this](std::uint16_t, std::uint8_t,
                        std::span<const std::uint8_t> d) -> tl::expected<void, SdoAbort> {
                     if (d.size() >= 2) {
                         on_controlword(get_le<std::uint16_t>(d.data()));
                     }
                     return {};
                 });
    od_.on_write(index(obj::kModesOfOperation),
                 [this](std::uint16_t, std::uint8_t,
                        std::span<const std::uint8_t> d) -> tl::expected<void, SdoAbort> {
                     if (d.empty() || !profile_.accepts_mode(static_cast<std::int8_t>(d[0]))) {
                         return tl::unexpected(SdoAbort::InvalidValue);
                     }
                     return {};
                 });
    od_.on_write(index(obj::kQuickStopOption),
                 [this](std::uint16_t, std::uint8_t,
                        std::span<const std::uint8_t> d) -> tl::expected<void, SdoAbort> {
                     const auto v = d.size() >= 2 ? get_le<std::int16_t>(d.data()) : -1000;
                     const auto o = profile_.quick_stop_options();
                     if (std::find(o.begin(), o.end(), v) == o.end()) {
                         return tl::unexpected(SdoAbort::InvalidValue);
                     }
                     return {};
                 });
    if (axis_ == 0 && !profile_.drive->abort_connection_options.empty()) {
        // 6007h values inside the range the drive reserves (DS-BVS §6.2.78: 1) are refused.
        od_.on_write(0x6007,
                     [this](std::uint16_t, std::uint8_t,
                            std::span<const std::uint8_t> d) -> tl::expected<void, SdoAbort> {
                         const auto v = d.size() >= 2 ? get_le<std::int16_t>(d.data()) : -1000;
                         const auto o = profile_.drive->abort_connection_options;
                         if (std::find(o.begin(), o.end(), v) == o.end()) {
                             return tl::unexpected(SdoAbort::InvalidValue);
                         }
                         return {};
                     });
    }
    od_.on_write(index(obj::kHomingMethod),
                 [this](std::uint16_t, std::uint8_t,
                        std::span<const std::uint8_t> d) -> tl::expected<void, SdoAbort> {
                     if (d.empty() ||
                         profile_.find_homing(static_cast<std::int8_t>(d[0])) == nullptr) {
                         return tl::unexpected(SdoAbort::InvalidValue);
                     }
                     return {};
                 });
    power_on();
}

std::uint16_t DriveCore::index(std::uint16_t base) const {
    return static_cast<std::uint16_t>(base + axis_ * profile_.axis_offset());
}

std::uint16_t DriveCore::mfr_index(std::uint16_t base) const {
    return static_cast<std::uint16_t>(base + axis_ * 0x100U);
}

double DriveCore::velocity_param(std::uint16_t base, std::uint8_t sub) const {
    return static_cast<double>(get<std::uint32_t>(base, sub)) * profile_.velocity_scale();
}

double DriveCore::accel_param(std::uint16_t base, std::uint8_t sub) const {
    return static_cast<double>(get<std::uint32_t>(base, sub)) * profile_.velocity_scale();
}

double DriveCore::quick_stop_decel() const {
    if (profile_.akd2g_objects) {
        // 605Ah 1/5 ramp with 6084h, 2/6 with AXIS#.CS.DEC (akd2g.md §5.4).
        const auto opt = get<std::int16_t>(obj::kQuickStopOption);
        if (opt == 1 || opt == 5) {
            return accel_param(obj::kProfileDeceleration);
        }
        return static_cast<double>(od_.get<std::uint32_t>(mfr_index(0x5002), 2).value_or(0)) *
               profile_.velocity_scale();
    }
    const auto opt = get<std::int16_t>(obj::kQuickStopOption);
    if (opt == 1 || opt == 5) {
        return accel_param(obj::kProfileDeceleration); // slow-down ramp
    }
    return accel_param(obj::kQuickStopDeceleration);
}

double DriveCore::halt_decel() const {
    if (mode_ == static_cast<std::int8_t>(cia::Mode::Homing)) {
        return accel_param(obj::kHomingAcceleration);
    }
    if (profile_.has_option_objects() && get<std::int16_t>(obj::kHaltOption) == 2) {
        return accel_param(obj::kQuickStopDeceleration);
    }
    return accel_param(obj::kProfileDeceleration);
}

bool DriveCore::enabled() const {
    return state_ == cia::State::OperationEnabled || state_ == cia::State::QuickStopActive ||
           (state_ == cia::State::FaultReactionActive && stop_.active) || stop_.active;
}

void DriveCore::power_on() {
    // Transition 0 (initialisation) and 1 (initialisation done, communication ready).
    state_ = cia::State::NotReadyToSwitchOn;
    faults_.clear();
    warnings_.clear();
    persistent_.clear();
    stop_ = {};
    homed_ = false;
    homing_.clear();
    pp_moving_ = false;
    pp_buffer_.reset();
    setpoint_ack_ = false;
    last_cw_ = 0;
    new_setpoint_edge_ = new_setpoint_fall_ = false;
    torque_demand_ = 0;
    ferr_time_ = 0;
    traj_.reset(motor_.position());
    if (probe_) {
        probe_->reset();
    }
    od_.set<std::uint16_t>(index(obj::kControlword), 0, 0);
    od_.set<std::uint16_t>(index(obj::kErrorCode), 0, 0);
    mode_ = get<std::int8_t>(obj::kModesOfOperation, 0, profile_.default_mode());
    set_state(cia::State::SwitchOnDisabled);
    if (sto_ && profile_.sto_warning_code != 0) {
        const FaultCode warn = profile_.fault(profile_.sto_warning_code);
        warnings_.push_back(warn);
        emit(AxisEvent::Kind::WarningRaised, warn);
    }
    update_outputs();
}

void DriveCore::emit(AxisEvent::Kind kind, const FaultCode& code) {
    if (handler_) {
        handler_(AxisEvent{kind, axis_, code});
    }
}

void DriveCore::set_state(cia::State s) {
    state_ = s;
    update_outputs();
}

void DriveCore::on_controlword(std::uint16_t cw) {
    const bool bit4 = (cw & cia::cw::kOpMode4) != 0;
    const bool was4 = (last_cw_ & cia::cw::kOpMode4) != 0;
    if (bit4 && !was4) {
        new_setpoint_edge_ = true;
    }
    if (!bit4 && was4) {
        new_setpoint_fall_ = true;
    }
    evaluate(cw);
    update_outputs(); // halt and mode bits show the new controlword at once
}

void DriveCore::evaluate(std::uint16_t cw) {
    const bool reset_edge =
        (cw & cia::cw::kFaultReset) != 0 && (last_cw_ & cia::cw::kFaultReset) == 0;
    last_cw_ = cw;
    if (reset_edge && state_ == cia::State::Fault) {
        try_fault_reset(); // transition 15
        return;
    }
    const auto c = cia::decode_command(cw);
    if (!c || *c == cia::Command::FaultReset) {
        return;
    }
    command(*c);
}

void DriveCore::command(cia::Command c) {
    // Device control per CiA 402 §6.3 (transition numbers in comments).
    const bool can_switch_on = !sto_; // AKD2G: STO (statusword bit 8) prevents enabling
    switch (state_) {
    case cia::State::SwitchOnDisabled:
        if (c == cia::Command::Shutdown) {
            set_state(cia::State::ReadyToSwitchOn); // 2
        }
        break;
    case cia::State::ReadyToSwitchOn:
        if ((c == cia::Command::SwitchOn || c == cia::Command::EnableOperation) && can_switch_on) {
            set_state(cia::State::SwitchedOn); // 3 (0x0F: 3, then 4 on the next evaluation)
        } else if (c == cia::Command::DisableVoltage || c == cia::Command::QuickStop) {
            set_state(cia::State::SwitchOnDisabled); // 7
        }
        break;
    case cia::State::SwitchedOn:
        if (c == cia::Command::EnableOperation && can_switch_on) {
            enter_mode(get<std::int8_t>(obj::kModesOfOperation));
            traj_.reset(motor_.position());
            set_state(cia::State::OperationEnabled); // 4
        } else if (c == cia::Command::Shutdown) {
            set_state(cia::State::ReadyToSwitchOn); // 6
        } else if (c == cia::Command::DisableVoltage || c == cia::Command::QuickStop) {
            set_state(cia::State::SwitchOnDisabled); // 10
        }
        break;
    case cia::State::OperationEnabled:
        if (stop_.active) {
            // A ramp of transition 5 or 8 is running; only a harder command overrides it.
            if (c == cia::Command::DisableVoltage) {
                disable_now(cia::State::SwitchOnDisabled);
            }
            break;
        }
        if (c == cia::Command::SwitchOn) { // disable operation
            const auto opt =
                profile_.has_option_objects() ? get<std::int16_t>(obj::kDisableOperationOption) : 1;
            if (opt == 0) {
                disable_now(cia::State::SwitchedOn); // 5
            } else {
                begin_stop(accel_param(obj::kProfileDeceleration), cia::State::SwitchedOn); // 5
            }
        } else if (c == cia::Command::Shutdown) {
            const auto opt =
                profile_.has_option_objects() ? get<std::int16_t>(obj::kShutdownOption) : 0;
            if (opt == 0) {
                disable_now(cia::State::ReadyToSwitchOn); // 8
            } else {
                begin_stop(accel_param(obj::kProfileDeceleration), cia::State::ReadyToSwitchOn);
            }
        } else if (c == cia::Command::DisableVoltage) {
            disable_now(cia::State::SwitchOnDisabled); // 9
        } else if (c == cia::Command::QuickStop) {
            quick_stop(); // 11
        }
        break;
    case cia::State::QuickStopActive:
        if (c == cia::Command::DisableVoltage) {
            disable_now(cia::State::SwitchOnDisabled); // 12
        } else if (c == cia::Command::EnableOperation && !stop_.active) {
            const auto opt = get<std::int16_t>(obj::kQuickStopOption);
            if (opt == 5 || opt == 6) {
                enter_mode(get<std::int8_t>(obj::kModesOfOperation));
                traj_.reset(motor_.position());
                set_state(cia::State::OperationEnabled); // 16
            }
        }
        break;
    case cia::State::NotReadyToSwitchOn:
    case cia::State::FaultReactionActive:
    case cia::State::Fault:
    case cia::State::Unknown:
        break;
    }
}

void DriveCore::begin_stop(double decel, cia::State then) {
    stop_.active = true;
    stop_.decel = std::max(decel, 1.0);
    stop_.then = then;
    traj_.set({motor_.position(), motor_.velocity()});
}

void DriveCore::disable_now(cia::State then) {
    stop_ = {};
    pp_moving_ = false;
    pp_buffer_.reset();
    homing_.interrupt();
    set_state(then);
}

void DriveCore::quick_stop() {
    const auto opt = get<std::int16_t>(obj::kQuickStopOption);
    const bool pt = mode_ == static_cast<std::int8_t>(cia::Mode::ProfileTorque);
    pp_moving_ = false;
    pp_buffer_.reset();
    homing_.interrupt();
    if (opt == 0 || (pt && profile_.quick_stop_ignored_in_pt)) {
        // 0: disable drive function; AKD2G PT: dynamic braking, disabled (akd2g.md §5.4).
        disable_now(cia::State::SwitchOnDisabled);
        return;
    }
    set_state(cia::State::QuickStopActive);
    // Options 1/2 leave QUICK STOP ACTIVE for SWITCH ON DISABLED when stopped (transition 12);
    // 5/6 stay (transition 16 is possible afterwards).
    begin_stop(quick_stop_decel(),
               (opt == 5 || opt == 6) ? cia::State::QuickStopActive : cia::State::SwitchOnDisabled);
}

void DriveCore::start_fault_reaction() {
    const bool was_enabled = enabled();
    pp_moving_ = false;
    pp_buffer_.reset();
    homing_.interrupt();
    stop_ = {};
    set_state(cia::State::FaultReactionActive); // 13
    if (!was_enabled) {
        return; // nothing to stop: FAULT at the next step (14)
    }
    double decel = 0;
    if (profile_.has_option_objects()) {
        switch (get<std::int16_t>(obj::kFaultReactionOption)) {
        case 1:
            decel = accel_param(obj::kProfileDeceleration);
            break;
        case 2:
            decel = accel_param(obj::kQuickStopDeceleration);
            break;
        default:
            decel = 0; // 0: disable drive function, the motor coasts
            break;
        }
    } else {
        // AKD2G: the controlled-stop machinery (AXIS#.CS.DEC) brings the axis down.
        decel = static_cast<double>(od_.get<std::uint32_t>(mfr_index(0x5002), 2).value_or(0)) *
                profile_.velocity_scale();
    }
    if (decel > 0) {
        begin_stop(decel, cia::State::Fault);
    }
}

void DriveCore::raise_fault(const FaultCode& code, bool persistent) {
    const bool known = std::any_of(faults_.begin(), faults_.end(),
                                   [&](const FaultCode& f) { return f.emcy == code.emcy; });
    if (!known) {
        faults_.push_back(code);
    }
    od_.set<std::uint16_t>(index(obj::kErrorCode), 0, code.emcy);
    publish_faults();
    (void)persistent;
    if (!known) {
        emit(AxisEvent::Kind::FaultRaised, code);
    }
    if (state_ != cia::State::Fault && state_ != cia::State::FaultReactionActive) {
        start_fault_reaction();
    }
}

void DriveCore::publish_faults() {
    // AKD2G 5004h/5104h AXIS#.FAULT1..10 (§5.3.84): the axis's active faults, Unsigned16. The
    // manual does not say what the value encodes; the simulator puts the EMCY code there.
    if (!profile_.akd2g_objects) {
        return;
    }
    for (std::uint8_t i = 1; i <= kAxisFaultSlots; ++i) {
        const std::uint16_t v = i <= faults_.size() ? faults_[i - 1U].emcy : std::uint16_t{0};
        od_.set<std::uint16_t>(mfr_index(0x5004), i, v);
    }
}

void DriveCore::try_fault_reset() {
    // Transition 15 only if no fault condition remains (akd2g.md §5.3, ds-bvs.md §2.2).
    if (sto_ && profile_.code_for(FaultKind::Sto).emcy != 0 &&
        std::any_of(faults_.begin(), faults_.end(),
                    [&](const FaultCode& f) { return f.emcy == profile_.sto_code; })) {
        return;
    }
    faults_.clear();
    od_.set<std::uint16_t>(index(obj::kErrorCode), 0, 0);
    publish_faults();
    ferr_time_ = 0;
    set_state(cia::State::SwitchOnDisabled);
    emit(AxisEvent::Kind::FaultsCleared, {});
}

void DriveCore::set_sto(bool active) {
    if (active == sto_) {
        return;
    }
    sto_ = active;
    const FaultCode warn = profile_.fault(profile_.sto_warning_code);
    if (active) {
        if (state_ == cia::State::OperationEnabled || state_ == cia::State::QuickStopActive ||
            state_ == cia::State::SwitchedOn || stop_.active) {
            // Torque is cut while the axis was powered: the STO fault (AKD2G F9000).
            const bool was_enabled = enabled();
            raise_fault(profile_.code_for(FaultKind::Sto), true);
            if (was_enabled) {
                stop_ = {}; // STO removes torque at once: no ramp
                set_state(cia::State::FaultReactionActive);
            }
        } else if (warn.emcy != 0) {
            warnings_.push_back(warn);
            emit(AxisEvent::Kind::WarningRaised, warn);
        }
        if (state_ == cia::State::ReadyToSwitchOn) {
            set_state(cia::State::SwitchOnDisabled);
        }
    } else if (warn.emcy != 0) {
        auto it = std::find_if(warnings_.begin(), warnings_.end(),
                               [&](const FaultCode& w) { return w.emcy == warn.emcy; });
        if (it != warnings_.end()) {
            warnings_.erase(it);
            emit(AxisEvent::Kind::WarningCleared, warn);
        }
    }
    if (profile_.akd2g_objects) {
        od_.set<std::uint8_t>(mfr_index(0x5007), 2, active ? 1 : 0);
    }
    update_outputs();
}

void DriveCore::inject(FaultKind kind) {
    switch (kind) {
    case FaultKind::Sto:
        set_sto(true);
        break;
    case FaultKind::OverCurrent:
        raise_fault(profile_.code_for(FaultKind::OverCurrent));
        break;
    case FaultKind::FollowingError:
        raise_fault(profile_.code_for(FaultKind::FollowingError));
        break;
    case FaultKind::HeartbeatLoss:
        if (profile_.heartbeat_loss_is_fault) {
            raise_fault(profile_.code_for(FaultKind::HeartbeatLoss));
        } else {
            abort_connection(od_.get<std::int16_t>(0x6007, 0).value_or(0));
        }
        break;
    case FaultKind::NodeReset:
        power_on();
        break;
    }
}

void DriveCore::abort_connection(std::int16_t option) {
    // 6007h (CiA 402): 0 no action, 1 fault signal, 2 disable voltage, 3 quick stop; negative
    // values are the manufacturer's. FIO -1 ("MFS mode", kuhnke-fio.md §1.7): the PDO values are
    // cleared, so the controlword reads 0 (disable voltage) and the drive coasts.
    switch (option) {
    case -1:
        od_.set<std::uint16_t>(index(obj::kControlword), 0, 0);
        command(cia::Command::DisableVoltage);
        break;
    case 1:
        raise_fault(profile_.code_for(FaultKind::HeartbeatLoss));
        break;
    case 2:
        command(cia::Command::DisableVoltage);
        break;
    case 3:
        command(cia::Command::QuickStop);
        break;
    default:
        break;
    }
}

void DriveCore::enter_mode(std::int8_t mode) {
    if (mode != mode_) {
        homing_.clear();
    }
    mode_ = mode;
    pp_moving_ = false;
    pp_buffer_.reset();
    setpoint_ack_ = false;
    in_window_time_ = 0;
    velocity_window_time_ = 0;
    torque_demand_ = 0;
    csp_last_target_ = static_cast<double>(get<std::int32_t>(obj::kTargetPosition));
    csp_since_change_ = 0;
    csp_segment_time_ = csp_period_; // no segment running: hold 607Ah
    pp_target_ = motor_.position();
}

void DriveCore::step(double dt) {
    // Controlword changed without a write hook (a PDO engine writing values directly).
    const auto cw = get<std::uint16_t>(obj::kControlword);
    if (cw != last_cw_) {
        on_controlword(cw);
    } else if (state_ == cia::State::SwitchedOn) {
        // Level-triggered: 0x0F in READY TO SWITCH ON goes 3, then 4 here. QUICK STOP ACTIVE
        // is left only by a new controlword (a local quick stop must not undo itself).
        evaluate(cw);
    }
    const auto requested = get<std::int8_t>(obj::kModesOfOperation);
    if (requested != mode_ && profile_.accepts_mode(requested)) {
        enter_mode(requested);
        traj_.set({motor_.position(), motor_.velocity()});
    }

    if (state_ == cia::State::FaultReactionActive && !stop_.active) {
        set_state(cia::State::Fault); // 14
    }

    if (stop_.active) {
        const bool stopped = traj_.step_velocity(0, stop_.decel, stop_.decel, dt);
        motor_.follow_position(traj_.position(), traj_.velocity(), dt);
        if (stopped && std::abs(motor_.velocity()) < 1e-3 * profile_.counts_per_rev) {
            const cia::State then = stop_.then;
            stop_ = {};
            if (then != cia::State::QuickStopActive) {
                set_state(then);
            }
            traj_.reset(motor_.position());
        }
    } else if (state_ == cia::State::OperationEnabled) {
        run_mode(dt);
    } else if (state_ == cia::State::QuickStopActive) {
        traj_.step_velocity(0, quick_stop_decel(), quick_stop_decel(), dt);
        motor_.follow_position(traj_.position(), traj_.velocity(), dt);
    } else {
        motor_.coast(dt);
        traj_.reset(motor_.position());
    }
    new_setpoint_edge_ = false;
    new_setpoint_fall_ = false;
    monitor_following_error(dt);
    update_outputs();
    if (probe_) {
        probe_->step(get<std::int32_t>(obj::kPositionActual));
    }
}

void DriveCore::monitor_following_error(double dt) {
    following_error_ = traj_.position() - motor_.position();
    const bool position_mode = state_ == cia::State::OperationEnabled &&
                               (mode_ == 1 || mode_ == 6 || mode_ == 8 || mode_ == -8);
    const auto window = get<std::uint32_t>(obj::kFollowingErrorWindow);
    // AKD2G: 6065h = 0 switches monitoring off (akd2g.md §5.6).
    const bool exceeded =
        position_mode && window != 0 && std::abs(following_error_) > static_cast<double>(window);
    ferr_bit_ = exceeded;
    ferr_time_ = exceeded ? ferr_time_ + dt : 0;
    const auto timeout_ms = od_.find(index(obj::kFollowingErrorTimeout), 0) != nullptr
                                ? get<std::uint16_t>(obj::kFollowingErrorTimeout)
                                : 0;
    if (exceeded && ferr_time_ * 1000.0 >= static_cast<double>(timeout_ms)) {
        raise_fault(profile_.code_for(FaultKind::FollowingError));
    }
}

void DriveCore::run_mode(double dt) {
    // Halt option 0 "disable drive function" (DS-BVS §6.2.92; CiA 402 605Dh): while halt is
    // set the power stage gives no torque and the motor coasts; the state stays.
    if ((last_cw_ & cia::cw::kHalt) != 0 && profile_.has_option_objects() &&
        get<std::int16_t>(obj::kHaltOption, 0, 1) == 0) {
        motor_.coast(dt);
        traj_.reset(motor_.position());
        return;
    }
    switch (mode_) {
    case 1:
        run_pp(dt);
        break;
    case 3:
        run_pv(dt);
        break;
    case 4:
        run_pt(dt);
        break;
    case 6:
        run_hm(dt);
        break;
    case 8:
    case -8:
        run_csp(dt);
        break;
    case 9:
    case -9: {
        const double v = (static_cast<double>(get<std::int32_t>(obj::kTargetVelocity)) +
                          static_cast<double>(get<std::int32_t>(obj::kVelocityOffset))) *
                         profile_.velocity_scale();
        traj_.set({traj_.position() + v * dt, v});
        motor_.follow_position(traj_.position(), v, dt);
        break;
    }
    case 10:
    case -10: {
        const double t = static_cast<double>(get<std::int16_t>(obj::kTargetTorque)) +
                         static_cast<double>(get<std::int16_t>(obj::kTorqueOffset));
        motor_.apply_torque(t, dt);
        traj_.set({motor_.position(), motor_.velocity()});
        break;
    }
    default:
        // Not reached: 6060h refuses modes the simulator does not run (accepts_mode); hold.
        traj_.step_velocity(0, accel_param(obj::kProfileDeceleration),
                            accel_param(obj::kProfileDeceleration), dt);
        motor_.follow_position(traj_.position(), traj_.velocity(), dt);
        break;
    }
}

void DriveCore::run_pp(double dt) {
    const std::uint16_t cw = last_cw_;
    const bool halt = (cw & cia::cw::kHalt) != 0;
    const auto vmax_of = [this] {
        double v = velocity_param(obj::kProfileVelocity);
        if (profile_.max_profile_velocity != 0) {
            v = std::min(v, velocity_param(obj::kMaxProfileVelocity));
        }
        return v;
    };
    if (new_setpoint_edge_) {
        // Set-point handshake (CiA 402 §6.8.2): bit 4 rising = new set-point.
        const bool immediate = (cw & cia::cw::kOpMode5) != 0;
        const bool relative = (cw & cia::cw::kOpMode6) != 0;
        const double target_raw = static_cast<double>(get<std::int32_t>(obj::kTargetPosition));
        if (!immediate && pp_moving_ && pp_buffer_) {
            // Buffer full: the set-point is ignored (bit 12 still 1).
        } else {
            const double base = (pp_moving_ && !immediate) ? pp_target_ : traj_.position();
            const double target = relative ? base + target_raw : target_raw;
            if (immediate || !pp_moving_) {
                pp_target_ = target;
                pp_moving_ = true;
                in_window_time_ = 0;
            } else {
                pp_buffer_ = target;
                pp_buffer_vmax_ = vmax_of();
            }
            setpoint_ack_ = true;
        }
    }
    if (new_setpoint_fall_ && !pp_buffer_) {
        setpoint_ack_ = false;
    }
    if (halt) {
        traj_.step_velocity(0, halt_decel(), halt_decel(), dt);
    } else if (pp_moving_) {
        const bool done =
            traj_.step_position(pp_target_, vmax_of(), accel_param(obj::kProfileAcceleration),
                                accel_param(obj::kProfileDeceleration), dt);
        if (done) {
            if (pp_buffer_) {
                pp_target_ = *pp_buffer_;
                pp_buffer_.reset();
                in_window_time_ = 0;
                if ((cw & cia::cw::kOpMode4) == 0) {
                    setpoint_ack_ = false;
                }
            } else {
                pp_moving_ = false;
            }
        }
    }
    motor_.follow_position(traj_.position(), traj_.velocity(), dt);
    const double window =
        profile_.akd2g_objects
            ? static_cast<double>(od_.get<std::uint32_t>(mfr_index(0x5016), 1).value_or(0))
            : static_cast<double>(get<std::uint32_t>(obj::kPositionWindow));
    const bool standstill = std::abs(motor_.velocity()) < 1e-3 * profile_.counts_per_rev;
    if (!pp_moving_ && standstill && std::abs(motor_.position() - pp_target_) <= window) {
        in_window_time_ += dt;
    } else {
        in_window_time_ = 0;
    }
}

void DriveCore::run_pv(double dt) {
    const bool halt = (last_cw_ & cia::cw::kHalt) != 0;
    double target =
        static_cast<double>(get<std::int32_t>(obj::kTargetVelocity)) * profile_.velocity_scale();
    if (profile_.max_profile_velocity != 0) {
        const double vmax = velocity_param(obj::kMaxProfileVelocity);
        target = std::clamp(target, -vmax, vmax);
    }
    if (halt) {
        target = 0;
    }
    const double dec = halt ? halt_decel() : accel_param(obj::kProfileDeceleration);
    traj_.step_velocity(target, accel_param(obj::kProfileAcceleration), dec, dt);
    motor_.follow_position(traj_.position(), traj_.velocity(), dt);
    // Velocity window (606Dh/606Eh): the counter runs while inside (akd2g.md §5.9 example).
    // 606Dh is UNSIGNED16 on most drives, UNSIGNED32 on the DS-BVS (manual §6.2.104).
    const SubObject* window_object = od_.find(index(0x606D), 0);
    const double window =
        static_cast<double>(window_object != nullptr ? window_object->value.as_uint().value_or(0)
                                                     : 0) *
        profile_.velocity_scale();
    if (std::abs(motor_.velocity() - target) <= window) {
        velocity_window_time_ += dt;
    } else {
        velocity_window_time_ = 0;
    }
}

void DriveCore::run_pt(double dt) {
    const bool halt = (last_cw_ & cia::cw::kHalt) != 0;
    double target = halt ? 0 : static_cast<double>(get<std::int16_t>(obj::kTargetTorque));
    const auto max_torque = static_cast<double>(get<std::uint16_t>(obj::kMaxTorque, 0, 1000));
    target = std::clamp(target, -max_torque, max_torque);
    const double slope =
        profile_.akd2g_objects ? static_cast<double>(get<std::uint32_t>(obj::kTorqueSlope)) : 0.0;
    if (slope <= 0) {
        torque_demand_ = target;
    } else {
        const double d = slope * dt;
        torque_demand_ += std::clamp(target - torque_demand_, -d, d);
    }
    motor_.apply_torque(torque_demand_, dt);
    traj_.set({motor_.position(), motor_.velocity()});
}

void DriveCore::run_hm(double dt) {
    const bool halt = (last_cw_ & cia::cw::kHalt) != 0;
    if (new_setpoint_edge_) {
        const auto method = get<std::int8_t>(obj::kHomingMethod);
        const HomingMethod* m = profile_.find_homing(method);
        if (m != nullptr) {
            HomingParams hp;
            hp.switch_speed = velocity_param(obj::kHomingSpeeds, 1);
            hp.zero_speed = velocity_param(obj::kHomingSpeeds, 2);
            hp.acceleration = accel_param(obj::kHomingAcceleration);
            hp.home_offset = static_cast<double>(get<std::int32_t>(obj::kHomeOffset));
            hp.move_by_offset = profile_.homing_moves_by_offset;
            homing_.start(*m, hp, motor_, traj_);
        }
    } else if (new_setpoint_fall_) {
        // AKD2G: bit 4 is level-triggered; 0 stops the homing (akd2g.md §5.7).
        homing_.interrupt();
    }
    homing_.step(motor_, traj_, halt, dt);
    motor_.follow_position(traj_.position(), traj_.velocity(), dt);
    if (homing_.status() == Homing::Status::Attained) {
        homed_ = true;
    }
}

void DriveCore::run_csp(double dt) {
    const double target = static_cast<double>(get<std::int32_t>(obj::kTargetPosition)) +
                          static_cast<double>(get<std::int32_t>(obj::kPositionOffset));
    csp_since_change_ += dt;
    if (target != csp_last_target_) {
        // CiA 402 CSP: a set-point is where the axis is to be one cycle later. Interpolate from
        // where the interpolation stands now to the new set-point over the measured set-point
        // period, so a late or early set-point costs at most one period of lag and never
        // accumulates (a fixed-rate interpolation fell further behind with every irregular
        // cycle of a loaded machine, and overshot with its feed-forward when it caught up).
        csp_period_ = std::clamp(csp_since_change_, dt, 0.1);
        csp_from_ = traj_.position();
        csp_last_target_ = target;
        csp_since_change_ = 0;
        csp_segment_time_ = 0;
    }
    csp_segment_time_ += dt;
    double pos = target;
    double feed_forward = 0;
    if (csp_segment_time_ < csp_period_) {
        const double f = csp_segment_time_ / csp_period_;
        pos = csp_from_ + (target - csp_from_) * f;
        feed_forward = (target - csp_from_) / csp_period_;
    }
    traj_.set({pos, feed_forward});
    motor_.follow_position(pos, feed_forward, dt);
}

void DriveCore::update_outputs() {
    namespace sw = cia::sw;
    std::uint16_t s = cia::state_bits(state_);
    if (profile_.akd2g_objects) {
        s |= sw::kVoltageEnabled; // DC bus present
    } else if (state_ != cia::State::SwitchOnDisabled && state_ != cia::State::NotReadyToSwitchOn) {
        s |= sw::kVoltageEnabled;
    }
    if (state_ != cia::State::QuickStopActive && state_ != cia::State::NotReadyToSwitchOn &&
        state_ != cia::State::SwitchOnDisabled && state_ != cia::State::Fault &&
        state_ != cia::State::FaultReactionActive) {
        s |= sw::kQuickStop;
    }
    if (state_ == cia::State::SwitchOnDisabled) {
        s |= sw::kQuickStop; // bit 5 is "don't care" there; drives report 1
    }
    if (!warnings_.empty()) {
        s |= sw::kWarning;
    }
    if (profile_.drive->quirks.sto_in_statusword_bit8 && sto_) {
        s |= sw::kManufacturer8;
    }
    // FIO §7.8.1.4: in CSP bit 8 = synchronised with the fieldbus (process data arriving).
    // Bit 15 (CLA, closed loop available after an auto setup) stays 0: no auto setup is run.
    if (profile_.drive->quirks.csp_bit8_synchronised && mode_ == 8 && fieldbus_synchronised_) {
        s |= sw::kManufacturer8;
    }
    s |= sw::kRemote;
    const bool standstill = std::abs(motor_.velocity()) < 1e-3 * profile_.counts_per_rev;
    const bool halt = (last_cw_ & cia::cw::kHalt) != 0;
    if (state_ == cia::State::QuickStopActive && !stop_.active) {
        s |= sw::kTargetReached; // quick stop with 605Ah 5/6 completed
    }
    if (state_ == cia::State::OperationEnabled && !stop_.active) {
        switch (mode_) {
        case 1: {
            const auto time_ms =
                profile_.ds_bvs_objects ? get<std::uint16_t>(obj::kPositionWindowTime) : 0;
            if (halt ? standstill
                     : (!pp_moving_ && in_window_time_ * 1000.0 + 1e-9 >= time_ms &&
                        in_window_time_ > 0)) {
                s |= sw::kTargetReached;
            }
            if (setpoint_ack_) {
                s |= sw::kOpMode12;
            }
            if (ferr_bit_) {
                s |= sw::kOpMode13;
            }
            break;
        }
        case 3: {
            const auto time_ms = get<std::uint16_t>(0x606E);
            if (halt ? standstill
                     : velocity_window_time_ * 1000.0 + 1e-9 >= std::max<double>(time_ms, 1)) {
                s |= sw::kTargetReached;
            }
            if (standstill) {
                s |= sw::kOpMode12; // speed = 0
            }
            break;
        }
        case 4:
            if (halt ? standstill
                     : std::abs(torque_demand_ -
                                static_cast<double>(get<std::int16_t>(obj::kTargetTorque))) < 1) {
                s |= sw::kTargetReached;
            }
            if (standstill) {
                s |= sw::kOpMode12;
            }
            break;
        case 6:
            switch (homing_.status()) {
            case Homing::Status::Idle:
                s |= sw::kTargetReached; // interrupted or not started
                break;
            case Homing::Status::Running:
                break;
            case Homing::Status::Attained:
                s |= sw::kOpMode12;
                if (homing_.settled()) {
                    s |= sw::kTargetReached;
                }
                break;
            case Homing::Status::Error:
                s |= sw::kOpMode13;
                if (standstill) {
                    s |= sw::kTargetReached;
                }
                break;
            }
            break;
        case 8:
        case 9:
        case 10:
            s |= sw::kOpMode12; // following the cyclic set-points
            if (mode_ == 8 && ferr_bit_) {
                s |= sw::kOpMode13;
            }
            break;
        default:
            break;
        }
    }
    if (profile_.ds_bvs_objects && !profile_.akd2g_objects && profile_.name() == "ds-bvs" &&
        homed_) {
        s |= 1U << 15; // DS-BVS §5.8.2: position referenced to home
    }
    statusword_ = s;
    od_.set<std::uint16_t>(index(obj::kStatusword), 0, s);
    od_.set<std::int8_t>(index(obj::kModesOfOperationDisplay), 0, mode_);
    const auto pos = static_cast<std::int32_t>(std::llround(motor_.position()));
    od_.set<std::int32_t>(index(obj::kPositionActual), 0, pos);
    // 6063h in the drive's internal counts where they differ from 6064h (AKD2G §5.4.6).
    const std::uint32_t internal = profile_.drive->quirks.internal_counts_per_rev;
    od_.set<std::int32_t>(index(0x6063), 0,
                          internal == 0
                              ? pos
                              : static_cast<std::int32_t>(std::llround(
                                    motor_.position() * internal / profile_.counts_per_rev)));
    od_.set<std::int32_t>(index(obj::kPositionDemand), 0,
                          static_cast<std::int32_t>(std::llround(traj_.position())));
    od_.set<std::int32_t>(index(0x60FC), 0,
                          static_cast<std::int32_t>(std::llround(traj_.position())));
    const double vs = profile_.velocity_scale();
    od_.set<std::int32_t>(index(obj::kVelocityActual), 0,
                          static_cast<std::int32_t>(std::llround(motor_.velocity() / vs)));
    od_.set<std::int32_t>(index(obj::kVelocityDemand), 0,
                          static_cast<std::int32_t>(std::llround(traj_.velocity() / vs)));
    od_.set<std::int16_t>(index(obj::kTorqueActual), 0,
                          static_cast<std::int16_t>(std::lround(motor_.torque())));
    od_.set<std::int16_t>(index(0x6078), 0,
                          static_cast<std::int16_t>(std::lround(motor_.torque())));
    od_.set<std::int32_t>(index(obj::kFollowingErrorActual), 0,
                          static_cast<std::int32_t>(std::llround(following_error_)));
    od_.set<std::uint32_t>(index(obj::kDigitalInputs), 0, motor_.digital_inputs());
}

} // namespace codrive::sim
