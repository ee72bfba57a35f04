// SPDX-License-Identifier: Apache-2.0
// Axis modes of operation: discovery (6502h), mode change confirmed by 6061h, the profile
// position set-point handshake, profile velocity/torque, homing and cyclic set-points.
#include <codrive/drives/axis.hpp>

#include <fmt/format.h>

namespace codrive::drives {

using cia402::Mode;
using cia402::State;
namespace sw = cia402::sw;
namespace cw = cia402::cw;
namespace obj = cia402::obj;

void Axis::discover(Done done) {
    std::weak_ptr<bool> alive = alive_;
    transport_.read_as<std::uint32_t>(
        index(obj::kSupportedDriveModes), 0,
        [this, alive, done = std::move(done)](DriveResult<std::uint32_t> r) {
            if (alive.expired()) {
                return;
            }
            if (!r) {
                done(drive_fail(DriveErrc::Transport,
                                fmt::format("{}: reading supported drive modes (6502h) failed: {}",
                                            name_, r.error().message)));
                return;
            }
            supported_modes_ = *r;
            modes_discovered_ = true;
            done({});
        });
}

bool Axis::supports_mode(std::int8_t mode) const {
    if (!modes_discovered_) {
        return profile_->supports_mode(mode);
    }
    Profile p = *profile_;
    p.supported_modes = supported_modes_;
    return p.supports_mode(mode);
}

void Axis::set_mode(std::int8_t mode, Done done, Duration timeout) {
    if (!supports_mode(mode)) {
        if (done) {
            done(drive_fail(DriveErrc::NotSupported,
                            fmt::format("{}: mode {} is not supported (6502h = 0x{:08X})", name_,
                                        cia402::mode_name(mode), supported_modes_)));
        }
        return;
    }
    Operation op;
    op.kind = OpKind::ModeChange;
    op.what = fmt::format("mode change to {}", cia402::mode_name(mode));
    op.mode = mode;
    op.done = std::move(done);
    op.timeout = timeout;
    mode_command_ = mode;
    mode_written_ = false;
    if (mode == static_cast<std::int8_t>(Mode::CyclicSyncPosition) ||
        mode == static_cast<std::int8_t>(Mode::InterpolatedPosition)) {
        // In CSP the drive takes 607Ah as its set-point from the cycle the mode changes (CiA 402
        // §6.8): a cyclic 607Ah still holding an earlier PP target would make the axis jump.
        if (const auto p = position_actual()) {
            target_position_ = *p;
            if (out_target_position_.valid()) {
                transport_.set(out_target_position_, *p);
            }
        }
    }
    next_poll_ = now_; // poll 6061h at once
    start(std::move(op));
}

void Axis::advance_mode_change() {
    Operation& op = *op_;
    if (op.step == 0) {
        op.step = 1;
        if (out_mode_.valid()) {
            return; // written with the next cycle's outputs
        }
        write_value<std::int8_t>(obj::kModesOfOperation, 0, op.mode);
        return;
    }
    if (op.pending_writes > 0) {
        return;
    }
    if (mode_display_ && *mode_display_ == op.mode) {
        finish({});
    }
}

bool Axis::check_motion_preconditions(Mode mode) {
    if (state_ != State::OperationEnabled) {
        fail(DriveErrc::WrongState, fmt::format("{}: {} needs OPERATION ENABLED, the axis is in {}",
                                                name_, op_->what, state_text()));
        return false;
    }
    if (mode_display_ && *mode_display_ != static_cast<std::int8_t>(mode)) {
        fail(DriveErrc::WrongMode,
             fmt::format("{}: {} needs mode {}, 6061h reports {}", name_, op_->what,
                         cia402::mode_name(static_cast<std::int8_t>(mode)),
                         cia402::mode_name(*mode_display_)));
        return false;
    }
    return true;
}

void Axis::move_to(std::int32_t target, MoveOptions options, Done done, Duration timeout) {
    Operation op;
    op.kind = OpKind::Move;
    op.what = fmt::format("move to {}{}", target, options.relative ? " (relative)" : "");
    op.target = target;
    op.move = options;
    op.done = std::move(done);
    op.timeout = timeout;
    start(std::move(op));
}

void Axis::run_velocity(std::int32_t velocity, Done done, Duration timeout) {
    Operation op;
    op.kind = OpKind::Velocity;
    op.what = fmt::format("velocity {}", velocity);
    op.target = velocity;
    op.done = std::move(done);
    op.timeout = timeout;
    start(std::move(op));
}

void Axis::run_torque(std::int16_t torque, Done done, Duration timeout) {
    Operation op;
    op.kind = OpKind::Torque;
    op.what = fmt::format("torque {}", torque);
    op.target = torque;
    op.done = std::move(done);
    op.timeout = timeout;
    start(std::move(op));
}

void Axis::home(const HomingParams& params, Done done, Duration timeout) {
    Operation op;
    op.kind = OpKind::Homing;
    op.what = fmt::format("homing (method {})", params.method);
    op.homing = params;
    op.done = std::move(done);
    op.timeout = timeout;
    start(std::move(op));
}

void Axis::advance_motion() {
    Operation& op = *op_;
    if (!has_status_) {
        return;
    }
    const Mode mode = op.kind == OpKind::Move       ? Mode::ProfilePosition
                      : op.kind == OpKind::Velocity ? Mode::ProfileVelocity
                      : op.kind == OpKind::Torque   ? Mode::ProfileTorque
                                                    : Mode::Homing;
    if (op.step == 0) {
        if (!check_motion_preconditions(mode)) {
            return;
        }
        op.step = 1;
        switch (op.kind) {
        case OpKind::Move:
            if (op.move.velocity) {
                write_value<std::uint32_t>(obj::kProfileVelocity, 0, *op.move.velocity);
            }
            if (op.move.acceleration) {
                write_value<std::uint32_t>(obj::kProfileAcceleration, 0, *op.move.acceleration);
            }
            if (op.move.deceleration) {
                write_value<std::uint32_t>(obj::kProfileDeceleration, 0, *op.move.deceleration);
            }
            target_position_ = op.target;
            if (!out_target_position_.valid()) {
                write_value<std::int32_t>(obj::kTargetPosition, 0, op.target);
            }
            break;
        case OpKind::Velocity:
            target_velocity_ = op.target;
            if (!out_target_velocity_.valid()) {
                write_value<std::int32_t>(obj::kTargetVelocity, 0, op.target);
                cw_sent_.reset(); // DS-BVS takes 60FFh with the next controlword write
            }
            break;
        case OpKind::Torque:
            target_torque_ = static_cast<std::int16_t>(op.target);
            if (!out_target_torque_.valid()) {
                write_value<std::int16_t>(obj::kTargetTorque, 0,
                                          static_cast<std::int16_t>(op.target));
                cw_sent_.reset();
            }
            break;
        default: // homing
            write_value<std::int8_t>(obj::kHomingMethod, 0, op.homing.method);
            write_value<std::uint32_t>(obj::kHomingSpeeds, 1, op.homing.speed_switch);
            write_value<std::uint32_t>(obj::kHomingSpeeds, 2, op.homing.speed_zero);
            write_value<std::uint32_t>(obj::kHomingAcceleration, 0, op.homing.acceleration);
            write_value<std::int32_t>(obj::kHomeOffset, 0, op.homing.offset);
            break;
        }
        return;
    }
    if (!op_) {
        return;
    }
    // Leaving OPERATION ENABLED ends any motion.
    if (state_ != State::OperationEnabled) {
        const std::string f = fault_description();
        fail(state_ == State::Fault || state_ == State::FaultReactionActive ? DriveErrc::Fault
                                                                            : DriveErrc::WrongState,
             fmt::format("{}: {} aborted: the axis entered {}{}", name_, op.what, state_text(),
                         f.empty() ? std::string() : ": " + f));
        return;
    }
    if (op.step == 1) {
        if (op.pending_writes > 0) {
            return;
        }
        op.step = 2;
        op.armed_sample = status_samples_;
        if (op.kind == OpKind::Move) {
            // New set-point (bit 4) with the options: 5 immediate, 6 relative, 9 blend.
            std::uint16_t bits = cw::kOpMode4;
            if (op.move.immediate) {
                bits = static_cast<std::uint16_t>(bits | cw::kOpMode5);
            }
            if (op.move.relative) {
                bits = static_cast<std::uint16_t>(bits | cw::kOpMode6);
            }
            if (op.move.change_on_setpoint) {
                bits = static_cast<std::uint16_t>(bits | cw::kOpMode9);
            }
            mode_bits_ = bits;
        } else if (op.kind == OpKind::Homing) {
            mode_bits_ = cw::kOpMode4; // start homing (level)
        }
        return;
    }
    const bool bit10 = (statusword_ & sw::kTargetReached) != 0;
    const bool bit12 = (statusword_ & sw::kOpMode12) != 0;
    const bool bit13 = (statusword_ & sw::kOpMode13) != 0;
    // Only statuswords sampled after the command went out count (one cycle of latency).
    const bool fresh = status_samples_ > op.armed_sample + 1;
    switch (op.kind) {
    case OpKind::Move:
        if (bit13 && fresh) {
            fail(DriveErrc::FollowingError,
                 fmt::format("{}: {} failed: following error (statusword bit 13)", name_, op.what));
            return;
        }
        if (op.step == 2) {
            if (bit12) { // set-point acknowledged: take bit 4 back (keep 5/6/9 until done)
                mode_bits_ = static_cast<std::uint16_t>(mode_bits_ & ~cw::kOpMode4);
                op.step = 3;
                op.armed_sample = status_samples_;
            }
            return;
        }
        if (fresh && !bit12 && bit10) {
            finish({});
        }
        return;
    case OpKind::Velocity:
    case OpKind::Torque:
        if (fresh && bit10) {
            finish({});
        }
        return;
    default: // homing (CiA 402 homing status: bit 13 error, bit 12 attained, bit 10 reached)
        if (!fresh) {
            return;
        }
        if (bit13) {
            fail(DriveErrc::HomingError,
                 fmt::format("{}: {} failed: homing error (statusword bit 13){}", name_, op.what,
                             last_error_code_ != 0 ? ": " + fault_description() : ""));
            return;
        }
        if (bit12 && bit10) {
            finish({});
        }
        return;
    }
}

void Axis::set_target_position(std::int32_t target) {
    target_position_ = target;
    if (out_target_position_.valid()) {
        transport_.set(out_target_position_, target); // into the image now: goes with the next RPDO
    } else {
        write_value<std::int32_t>(obj::kTargetPosition, 0, target);
    }
}

void Axis::set_target_velocity(std::int32_t target) {
    target_velocity_ = target;
    if (out_target_velocity_.valid()) {
        transport_.set(out_target_velocity_, target); // into the image now: goes with the next RPDO
    } else {
        write_value<std::int32_t>(obj::kTargetVelocity, 0, target);
    }
}

void Axis::set_target_torque(std::int16_t target) {
    target_torque_ = target;
    if (out_target_torque_.valid()) {
        transport_.set(out_target_torque_, target); // into the image now: goes with the next RPDO
    } else {
        write_value<std::int16_t>(obj::kTargetTorque, 0, target);
    }
}

void Axis::set_ip_target(std::int32_t target) {
    ip_target_ = target;
    if (out_ip_data_.valid()) {
        transport_.set(out_ip_data_, target); // into the image now: goes with the next RPDO
    } else {
        write_value<std::int32_t>(obj::kInterpolationDataRecord, 1, target);
    }
}

bool Axis::following_setpoints() const {
    return has_status_ && (statusword_ & sw::kOpMode12) != 0;
}

std::optional<std::int32_t> Axis::position_actual() const {
    if (auto v = transport_.get<std::int32_t>(in_position_)) {
        return v;
    }
    return polled_position_;
}

std::optional<std::int32_t> Axis::velocity_actual() const {
    return transport_.get<std::int32_t>(in_velocity_);
}

std::optional<std::int32_t> Axis::following_error_actual() const {
    return transport_.get<std::int32_t>(in_following_error_);
}

std::optional<std::int16_t> Axis::torque_actual() const {
    return transport_.get<std::int16_t>(in_torque_);
}

} // namespace codrive::drives
