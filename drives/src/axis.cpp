// SPDX-License-Identifier: Apache-2.0
// The CiA 402 axis: status decoding, command sequencing for the power state machine (CiA 402
// §6.2 figure "state machine", transitions 2..16), process-image I/O and SDO polling.
#include <codrive/drives/axis.hpp>

#include <fmt/format.h>

namespace codrive::drives {

using cia402::Command;
using cia402::State;
namespace sw = cia402::sw;
namespace cw = cia402::cw;
namespace obj = cia402::obj;

std::string DriveTransport::hex_index(std::uint16_t index, std::uint8_t subindex) {
    return fmt::format("0x{:04X}:{:02X}", index, subindex);
}

Axis::Axis(DriveTransport& transport, AxisConfig config)
    : transport_(transport),
      profile_(config.profile != nullptr ? config.profile : &generic_profile()),
      axis_(config.axis == 0 ? 1 : config.axis), timeout_(config.timeout),
      poll_period_(config.poll_period), alive_(std::make_shared<bool>(true)) {
    if (!config.name.empty()) {
        name_ = std::move(config.name);
    } else {
        const std::string t = transport_.name();
        name_ = t.empty() ? fmt::format("axis {}", axis_) : fmt::format("{} axis {}", t, axis_);
    }
    supported_modes_ = profile_->supported_modes;
    bind();
}

Axis::~Axis() = default;

void Axis::bind() {
    status_received_.reset();
    in_statusword_ = transport_.input(index(obj::kStatusword), 0);
    in_mode_display_ = transport_.input(index(obj::kModesOfOperationDisplay), 0);
    in_position_ = transport_.input(index(obj::kPositionActual), 0);
    in_velocity_ = transport_.input(index(obj::kVelocityActual), 0);
    in_torque_ = transport_.input(index(obj::kTorqueActual), 0);
    in_following_error_ = transport_.input(index(obj::kFollowingErrorActual), 0);
    out_controlword_ = transport_.output(index(obj::kControlword), 0);
    out_mode_ = transport_.output(index(obj::kModesOfOperation), 0);
    out_target_position_ = transport_.output(index(obj::kTargetPosition), 0);
    out_target_velocity_ = transport_.output(index(obj::kTargetVelocity), 0);
    out_target_torque_ = transport_.output(index(obj::kTargetTorque), 0);
    out_ip_data_ = transport_.output(index(obj::kInterpolationDataRecord), 1);
}

std::uint16_t Axis::controlword() const {
    std::uint16_t v = cia402::command_bits(command_);
    v = static_cast<std::uint16_t>(v | mode_bits_);
    if (ip_enabled_) {
        v = static_cast<std::uint16_t>(v | cw::kOpMode4);
    }
    if (halt_) {
        v = static_cast<std::uint16_t>(v | cw::kHalt);
    }
    if (fault_reset_bit_) {
        v = static_cast<std::uint16_t>(v | cw::kFaultReset);
    }
    return v;
}

bool Axis::cyclic_status() const {
    return in_statusword_.valid();
}

// ---- cycle / tick ---------------------------------------------------------------------------

void Axis::on_cycle(TimePoint now) {
    now_ = now;
    if (auto v = transport_.get<std::uint16_t>(in_statusword_)) {
        // A late TPDO leaves last cycle's statusword in the image: it is not a new sample, and
        // counting it would let an operation accept a statusword from before its command.
        const auto received = transport_.input_count(in_statusword_);
        if (!received || !status_received_ || *received != *status_received_) {
            status_received_ = received;
            update_status(*v);
        }
    }
    if (auto m = transport_.get<std::int8_t>(in_mode_display_)) {
        mode_display_ = *m;
    }
    advance(now);
    write_outputs();
}

TimePoint Axis::next_deadline() const {
    TimePoint t = kNever;
    const bool need_mode = !in_mode_display_.valid() && op_ && op_->kind == OpKind::ModeChange;
    if (!cyclic_status() || need_mode) {
        t = next_poll_;
    }
    if (op_ && op_->deadline_armed) {
        t = std::min(t, op_->deadline);
    }
    return t;
}

void Axis::on_tick(TimePoint now) {
    now_ = now;
    poll(now);
    advance(now);
    if (!out_controlword_.valid()) {
        write_outputs();
    }
}

void Axis::poll(TimePoint now) {
    const bool need_status = !cyclic_status();
    const bool need_mode = !in_mode_display_.valid() && op_ && op_->kind == OpKind::ModeChange;
    if ((!need_status && !need_mode) || poll_in_flight_ || now < next_poll_) {
        return;
    }
    next_poll_ = now + poll_period_;
    std::weak_ptr<bool> alive = alive_;
    if (need_mode) {
        poll_in_flight_ = true;
        transport_.read_as<std::int8_t>(index(obj::kModesOfOperationDisplay), 0,
                                        [this, alive](DriveResult<std::int8_t> r) {
                                            if (alive.expired()) {
                                                return;
                                            }
                                            poll_in_flight_ = false;
                                            if (r) {
                                                mode_display_ = *r;
                                            }
                                            advance(now_);
                                            write_outputs();
                                        });
        if (!need_status) {
            return;
        }
    }
    poll_in_flight_ = true;
    transport_.read_as<std::uint16_t>(index(obj::kStatusword), 0,
                                      [this, alive](DriveResult<std::uint16_t> r) {
                                          if (alive.expired()) {
                                              return;
                                          }
                                          poll_in_flight_ = false;
                                          if (r) {
                                              update_status(*r);
                                          }
                                          advance(now_);
                                          write_outputs();
                                      });
}

cia402::Command Axis::hold_command(State s) {
    switch (s) {
    case State::OperationEnabled:
        return Command::EnableOperation;
    case State::SwitchedOn:
        return Command::SwitchOn;
    case State::ReadyToSwitchOn:
        return Command::Shutdown;
    case State::QuickStopActive:
        return Command::QuickStop;
    default:
        return Command::DisableVoltage;
    }
}

void Axis::update_status(std::uint16_t value) {
    statusword_ = value;
    has_status_ = true;
    ++status_samples_;
    const State next = cia402::decode_state(value);
    if (status_samples_ == 1 && !op_) {
        // A master that attaches to a running drive must not disable it: command what keeps
        // the drive in the state it is in until the application asks for something else.
        command_ = hold_command(next);
    }
    if (next == state_) {
        return;
    }
    const State prev = state_;
    state_ = next;
    if (next == State::Fault && profile_->has_object(obj::kErrorCode)) {
        // 603Fh names the fault for messages; EMCY may have told us already.
        std::weak_ptr<bool> alive = alive_;
        transport_.read_as<std::uint16_t>(index(obj::kErrorCode), 0,
                                          [this, alive](DriveResult<std::uint16_t> r) {
                                              if (!alive.expired() && r && *r != 0) {
                                                  last_error_code_ = *r;
                                              }
                                          });
    } else if (next == State::Fault && profile_->axis_fault_list != 0) {
        attribute_fault(0, 0); // AKD2G: this axis's own fault list (5004h/5104h, §5.3.84)
    } else if (next == State::Fault && profile_->fault_code_in_1003) {
        // No 603Fh (AKD2G): the newest 1003h entry is the last EMCY, its code in bits 0..15.
        // 1003h is one object for the whole device, not per axis.
        std::weak_ptr<bool> alive = alive_;
        transport_.read_as<std::uint32_t>(0x1003, 1, [this, alive](DriveResult<std::uint32_t> r) {
            if (!alive.expired() && r && (*r & 0xFFFFU) != 0) {
                last_error_code_ = static_cast<std::uint16_t>(*r & 0xFFFFU);
            }
        });
    }
    if (state_handler_) {
        state_handler_(prev, next);
    }
}

void Axis::write_outputs() {
    if (!has_status_) {
        // Until the first statusword the axis does not know what would keep the drive where it
        // is; any controlword now could disable a drive another master left running.
        return;
    }
    const std::uint16_t cwv = controlword();
    if (out_controlword_.valid()) {
        transport_.set(out_controlword_, cwv);
        cw_sent_ = cwv;
    } else if (!cw_write_in_flight_ && (!cw_sent_ || *cw_sent_ != cwv)) {
        cw_write_in_flight_ = true;
        std::weak_ptr<bool> alive = alive_;
        transport_.write_as<std::uint16_t>(
            index(obj::kControlword), 0, cwv, [this, alive, cwv](DriveVoid r) {
                if (alive.expired()) {
                    return;
                }
                cw_write_in_flight_ = false;
                if (!r) {
                    if (op_) {
                        fail(DriveErrc::Transport,
                             fmt::format("{}: {} failed writing controlword 0x{:04X}: {}", name_,
                                         op_->what, cwv, r.error().message));
                    }
                    return;
                }
                cw_sent_ = cwv;
                advance(now_);
                write_outputs(); // a newer controlword may be waiting
            });
    }
    if (mode_command_ && out_mode_.valid()) {
        transport_.set(out_mode_, *mode_command_);
        mode_written_ = true;
    }
    if (out_target_position_.valid() && state_ != State::OperationEnabled) {
        // Until the axis is enabled the cyclic target follows the actual position, so enabling
        // in CSP does not jump to whatever the RPDO happened to hold (initially 0).
        if (auto p = position_actual()) {
            target_position_ = *p;
        }
    }
    if (target_position_ && out_target_position_.valid()) {
        transport_.set(out_target_position_, *target_position_);
    }
    if (target_velocity_ && out_target_velocity_.valid()) {
        transport_.set(out_target_velocity_, *target_velocity_);
    }
    if (target_torque_ && out_target_torque_.valid()) {
        transport_.set(out_target_torque_, *target_torque_);
    }
    if (ip_target_ && out_ip_data_.valid()) {
        transport_.set(out_ip_data_, *ip_target_);
    }
}

void Axis::write_object(std::uint16_t index_value, std::uint8_t sub, Bytes data) {
    if (!op_) {
        transport_.write(index_value, sub, std::move(data), [](DriveVoid) {});
        return;
    }
    ++op_->pending_writes;
    std::weak_ptr<bool> alive = alive_;
    transport_.write(index_value, sub, std::move(data), [this, alive](DriveVoid r) {
        if (alive.expired() || !op_) {
            return;
        }
        --op_->pending_writes;
        if (!r) {
            fail(DriveErrc::Transport,
                 fmt::format("{}: {} failed: {}", name_, op_->what, r.error().message));
            return;
        }
        advance(now_);
        write_outputs();
    });
}

// ---- operations -----------------------------------------------------------------------------

void Axis::start(Operation op) {
    if (op_) {
        Operation old = std::move(*op_);
        op_.reset();
        mode_bits_ = 0;
        if (old.done) {
            old.done(drive_fail(DriveErrc::Cancelled,
                                fmt::format("{}: {} cancelled by {}", name_, old.what, op.what)));
        }
    }
    if (op.timeout == Duration::zero()) {
        op.timeout = timeout_;
    }
    op_ = std::move(op);
    // Run the first step at once when the axis has run before: the statusword is fresh enough.
    if (now_ != TimePoint{}) {
        advance(now_);
        write_outputs();
    }
}

void Axis::finish(DriveVoid result) {
    if (!op_) {
        return;
    }
    Operation op = std::move(*op_);
    op_.reset();
    if (op.kind == OpKind::Homing || op.kind == OpKind::Move) {
        mode_bits_ = 0;
    }
    if (op.done) {
        op.done(std::move(result));
    }
}

void Axis::cancel() {
    if (op_) {
        fail(DriveErrc::Cancelled, fmt::format("{}: {} cancelled", name_, op_->what));
    }
}

void Axis::enable(Done done, Duration timeout) {
    Operation op;
    op.kind = OpKind::Enable;
    op.what = "enable";
    op.done = std::move(done);
    op.timeout = timeout;
    start(std::move(op));
}

void Axis::shutdown(Done done, Duration timeout) {
    Operation op;
    op.kind = OpKind::Shutdown;
    op.what = "shutdown";
    op.done = std::move(done);
    op.timeout = timeout;
    start(std::move(op));
}

void Axis::switch_on(Done done, Duration timeout) {
    Operation op;
    op.kind = OpKind::SwitchOn;
    op.what = "switch on";
    op.done = std::move(done);
    op.timeout = timeout;
    start(std::move(op));
}

void Axis::disable(Done done, Duration timeout) {
    Operation op;
    op.kind = OpKind::Disable;
    op.what = "disable";
    op.done = std::move(done);
    op.timeout = timeout;
    start(std::move(op));
}

void Axis::quick_stop(Done done, Duration timeout) {
    Operation op;
    op.kind = OpKind::QuickStop;
    op.what = "quick stop";
    op.done = std::move(done);
    op.timeout = timeout;
    start(std::move(op));
}

void Axis::fault_reset(Done done, Duration timeout) {
    Operation op;
    op.kind = OpKind::FaultReset;
    op.what = "fault reset";
    op.done = std::move(done);
    op.timeout = timeout;
    start(std::move(op));
}

void Axis::advance(TimePoint now) {
    if (!op_) {
        return;
    }
    if (!op_->deadline_armed) {
        op_->deadline = now + op_->timeout;
        op_->deadline_armed = true;
    }
    switch (op_->kind) {
    case OpKind::Enable:
    case OpKind::Shutdown:
    case OpKind::SwitchOn:
    case OpKind::Disable:
    case OpKind::QuickStop:
    case OpKind::FaultReset:
        advance_power(now);
        break;
    case OpKind::ModeChange:
        advance_mode_change();
        break;
    case OpKind::Move:
    case OpKind::Velocity:
    case OpKind::Torque:
    case OpKind::Homing:
        advance_motion();
        break;
    }
    if (!op_ || now < op_->deadline) {
        return;
    }
    // Timed out: say where the axis is stuck and why it probably is.
    std::string detail;
    switch (op_->kind) {
    case OpKind::ModeChange:
        detail = fmt::format(
            "{}: mode change to {} timed out: {}", name_, cia402::mode_name(op_->mode),
            mode_display_ ? fmt::format("6061h still reports {}", cia402::mode_name(*mode_display_))
                          : std::string("6061h was never received"));
        break;
    case OpKind::Move:
        detail = fmt::format("{}: {} timed out in {}: {}", name_, op_->what, state_text(),
                             op_->step <= 2 ? "no set-point acknowledge (statusword bit 12)"
                                            : "target not reached (statusword bit 10 clear)");
        break;
    case OpKind::Velocity:
    case OpKind::Torque:
        detail = fmt::format("{}: {} timed out in {}: target not reached (statusword bit 10 "
                             "clear)",
                             name_, op_->what, state_text());
        break;
    case OpKind::Homing:
        detail =
            fmt::format("{}: {} timed out in {}: homing not attained (statusword bits "
                        "12/10 = {}/{})",
                        name_, op_->what, state_text(), (statusword_ & sw::kOpMode12) != 0 ? 1 : 0,
                        (statusword_ & sw::kTargetReached) != 0 ? 1 : 0);
        break;
    case OpKind::QuickStop:
        if (state_ == State::QuickStopActive) {
            detail = fmt::format("{}: quick stop timed out in QUICK STOP ACTIVE: the drive is "
                                 "still on its quick-stop ramp (statusword bit 10 clear); the "
                                 "quick stop stays commanded",
                                 name_);
            break;
        }
        [[fallthrough]];
    default:
        detail =
            fmt::format("{}: {} timed out in {}: {}", name_, op_->what, state_text(), diagnose());
        break;
    }
    fail(DriveErrc::Timeout, detail);
}

void Axis::advance_power(TimePoint) {
    if (!has_status_) {
        return;
    }
    const OpKind kind = op_->kind;
    // Fault: a rising edge of bit 7 (transition 15). The edge needs one controlword with bit 7
    // clear on the wire first (CiA 402 §6.2.1: "fault reset ... on the rising edge").
    if (state_ == State::Fault && kind != OpKind::QuickStop) {
        if (!fault_reset_bit_) {
            if (cw_sent_ && (*cw_sent_ & cw::kFaultReset) == 0) {
                command_ = Command::DisableVoltage; // 0x0080: nothing but the reset
                fault_reset_bit_ = true;
                op_->fault_reset_phase = true;
            } else {
                command_ = Command::DisableVoltage;
            }
        }
        return;
    }
    if (state_ == State::FaultReactionActive) {
        return; // transition 14 is automatic
    }
    if (fault_reset_bit_) {
        // Left FAULT: take bit 7 back so the next fault can be reset again.
        fault_reset_bit_ = false;
        command_ = Command::DisableVoltage;
    }
    switch (kind) {
    case OpKind::FaultReset:
        if (state_ != State::Fault) {
            finish({});
        }
        return;
    case OpKind::QuickStop:
        switch (state_) {
        case State::OperationEnabled:
        case State::SwitchedOn:
        case State::ReadyToSwitchOn:
            command_ = Command::QuickStop; // 11, 10, 7
            return;
        case State::QuickStopActive:
            // Entered when the ramp starts. With 605Ah 5..8 the drive stays here and reports
            // the end of the ramp with bit 10 (target reached); with 0..4 it goes on to SWITCH
            // ON DISABLED by itself (transition 12 of CiA 402 §6.3, "quick stop completed").
            // Disable voltage before that would cut the ramp and let the motor coast.
            command_ = Command::QuickStop;
            if ((statusword_ & sw::kTargetReached) != 0) {
                finish({});
            }
            return;
        case State::SwitchOnDisabled:
        case State::Fault:
            finish({});
            return;
        default:
            return;
        }
    case OpKind::Disable:
        if (state_ == State::SwitchOnDisabled) {
            command_ = Command::DisableVoltage;
            finish({});
            return;
        }
        if (state_ != State::NotReadyToSwitchOn && state_ != State::Unknown) {
            command_ = Command::DisableVoltage; // 7, 9, 10, 12
        }
        return;
    default:
        break;
    }
    // Enable / shutdown / switch on: walk towards the target state one transition at a time
    // (the DS-BVS manual: "no new transition until the previous one is finished").
    const State target = kind == OpKind::Enable     ? State::OperationEnabled
                         : kind == OpKind::SwitchOn ? State::SwitchedOn
                                                    : State::ReadyToSwitchOn;
    if (state_ == target) {
        command_ = hold_command(target);
        finish({});
        return;
    }
    switch (state_) {
    case State::SwitchOnDisabled:
        command_ = Command::Shutdown; // 2
        break;
    case State::ReadyToSwitchOn:
        command_ = Command::SwitchOn; // 3 (0x07: bit 3 clear works on every drive)
        break;
    case State::SwitchedOn:
        command_ = target == State::OperationEnabled ? Command::EnableOperation // 4
                                                     : Command::Shutdown;       // 6
        break;
    case State::OperationEnabled:
        command_ = target == State::SwitchedOn ? Command::DisableOperation // 5
                                               : Command::Shutdown;        // 8
        break;
    case State::QuickStopActive:
        command_ = target == State::OperationEnabled ? Command::EnableOperation // 16
                                                     : Command::DisableVoltage; // 12
        break;
    default:
        break; // NOT READY TO SWITCH ON: transition 1 is automatic
    }
}

// ---- messages -------------------------------------------------------------------------------

std::string Axis::state_text() const {
    return std::string(has_status_ ? cia402::to_string(state_) : "unknown state");
}

std::string Axis::fault_description() const {
    if (last_error_code_ == 0) {
        return {};
    }
    const std::string vendor = profile_->fault_text(last_error_code_);
    return vendor.empty() ? fmt::format("error code 0x{:04X}", last_error_code_)
                          : fmt::format("error code 0x{:04X} ({})", last_error_code_, vendor);
}

std::string Axis::diagnose() const {
    if (!has_status_) {
        return "no statusword received (is the node operational and 6041h mapped or readable?)";
    }
    const Quirks& q = profile_->quirks;
    if (state_ == State::Fault) {
        std::string s = "the drive is in FAULT";
        const std::string f = fault_description();
        if (!f.empty()) {
            s += ": " + f;
        }
        if (fault_reset_bit_) {
            s += "; fault reset (controlword bit 7) did not clear it, the cause is probably "
                 "still present";
        }
        return s;
    }
    if (state_ == State::FaultReactionActive) {
        return "fault reaction still active";
    }
    if (state_ == State::NotReadyToSwitchOn) {
        return "the drive is still initialising (NOT READY TO SWITCH ON)";
    }
    if (q.sto_in_statusword_bit8 && (statusword_ & sw::kManufacturer8) != 0) {
        return "STO active (statusword bit 8)";
    }
    if (!q.remote_bit9_always_set && (statusword_ & sw::kRemote) == 0) {
        return profile_ == &akd2g_profile()
                   ? "the drive is not under fieldbus control (statusword bit 9 remote is 0: "
                     "AXIS#.CMDSOURCE is not fieldbus, e.g. WorkBench has control)"
                   : "the drive is not under fieldbus control (statusword bit 9 remote is 0)";
    }
    if (state_ == State::Unknown) {
        return fmt::format("statusword 0x{:04X} matches no CiA 402 state", statusword_);
    }
    if ((state_ == State::ReadyToSwitchOn || state_ == State::SwitchOnDisabled) &&
        (statusword_ & sw::kVoltageEnabled) == 0 && op_ &&
        (op_->kind == OpKind::Enable || op_->kind == OpKind::SwitchOn)) {
        return q.voltage_bit4_is_dc_bus
                   ? "no DC bus voltage (statusword bit 4 clear)"
                   : "main voltage not applied (statusword bit 4 voltage enabled is 0)";
    }
    if (state_ == State::QuickStopActive) {
        return "quick stop active (statusword bit 5 clear)";
    }
    if ((statusword_ & sw::kInternalLimit) != 0) {
        return "internal limit active (statusword bit 11)";
    }
    if (!op_) {
        // Nothing was asked of the drive: a resting state is an answer, not a failure.
        switch (state_) {
        case State::SwitchOnDisabled:
            return "SWITCH ON DISABLED: power stage off, ready to be enabled";
        case State::ReadyToSwitchOn:
            return "READY TO SWITCH ON: power stage off, ready to be enabled";
        case State::SwitchedOn:
            return "SWITCHED ON: power stage on, operation not enabled yet";
        default:
            break;
        }
    }
    return fmt::format("the drive did not follow controlword 0x{:04X} (statusword 0x{:04X})",
                       controlword(), statusword_);
}

} // namespace codrive::drives
