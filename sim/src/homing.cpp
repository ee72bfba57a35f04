// SPDX-License-Identifier: Apache-2.0
// Homing procedure of a simulated axis.
#include <codrive/sim/homing.hpp>

#include <cmath>

namespace codrive::sim {

void Homing::start(const HomingMethod& method, const HomingParams& params, MotorModel& motor,
                   Trajectory& traj) {
    method_ = method;
    params_ = params;
    status_ = Status::Running;
    phase_ = Phase::Search;
    dir_ = method.direction >= 0 ? 1 : -1;
    reversals_ = 0;
    blocked_time_ = 0;
    settled_ = false;
    error_.clear();
    traj.set({motor.position(), motor.velocity()});
    if (method.ref == HomingRef::CurrentPosition) {
        found(motor, traj);
    }
}

void Homing::found(MotorModel& motor, Trajectory& traj) {
    // The home position is where the reference was detected; the demand returns to it.
    const double before = motor.position();
    if (params_.move_by_offset) {
        // DS-BVS §5.8: move by the home offset, then that point becomes position 0.
        home_target_ = before + params_.home_offset;
        phase_ = Phase::Offset;
        return;
    }
    // CiA 402 §6.7.3: the home position takes the value of the home offset.
    motor.set_position(params_.home_offset);
    const double shift = motor.position() - before;
    traj.set({traj.position() + shift, traj.velocity()});
    home_target_ = motor.position();
    phase_ = Phase::Settle;
}

void Homing::step(MotorModel& motor, Trajectory& traj, bool halt, double dt) {
    if (status_ != Status::Running && !(status_ == Status::Attained && !settled_)) {
        if (status_ == Status::Error || status_ == Status::Idle) {
            traj.step_velocity(0, params_.acceleration, params_.acceleration, dt);
        } else {
            traj.step_position(home_target_, params_.zero_speed, params_.acceleration,
                               params_.acceleration, dt);
        }
        return;
    }
    if (halt) {
        traj.step_velocity(0, params_.acceleration, params_.acceleration, dt);
        return;
    }
    const double acc = params_.acceleration;
    switch (phase_) {
    case Phase::Search: {
        const double speed =
            method_.ref == HomingRef::IndexPulse ? params_.zero_speed : params_.switch_speed;
        traj.step_velocity(dir_ * speed, acc, acc, dt);
        const bool limit_ahead = dir_ < 0 ? motor.neg_limit() : motor.pos_limit();
        switch (method_.ref) {
        case HomingRef::LimitSwitch:
            if (limit_ahead) {
                phase_ = Phase::Stop;
            }
            break;
        case HomingRef::HomeSwitch:
            if (motor.home_switch()) {
                phase_ = Phase::Stop;
            } else if (limit_ahead) {
                // Narrow home switch methods reverse at the limit switch (CiA 402 methods
                // 7–14, 23–30); a second limit means the switch is not there.
                if (++reversals_ > 1) {
                    fail("home switch not found between the limit switches");
                } else {
                    dir_ = -dir_;
                }
            }
            break;
        case HomingRef::HardStop:
            blocked_time_ = motor.blocked() ? blocked_time_ + dt : 0;
            if (blocked_time_ >= 0.02) {
                // Blocked 20 ms: the current rose to the threshold (AKD2G HOME.PERRTHRESH,
                // DS-BVS 4500h). Home is where the axis stands.
                traj.set({motor.position(), 0});
                found(motor, traj);
            }
            break;
        case HomingRef::IndexPulse:
            if (motor.index_crossed()) {
                traj.set({motor.position(), 0});
                found(motor, traj);
            }
            break;
        case HomingRef::CurrentPosition:
            found(motor, traj);
            break;
        }
        if (method_.ref != HomingRef::HardStop && motor.blocked()) {
            fail("mechanical stop reached while searching the reference");
        }
        break;
    }
    case Phase::Stop:
        if (traj.step_velocity(0, acc, acc, dt)) {
            phase_ = Phase::Edge;
        }
        break;
    case Phase::Edge: {
        // Leave the reference slowly: a limit switch back toward the travel range, the home
        // switch through the edge the method names.
        const int d = method_.ref == HomingRef::LimitSwitch ? -dir_ : method_.edge;
        traj.step_velocity(d * params_.zero_speed, acc, acc, dt);
        const bool active = method_.ref == HomingRef::LimitSwitch
                                ? (dir_ < 0 ? motor.neg_limit() : motor.pos_limit())
                                : motor.home_switch();
        if (!active) {
            if (method_.index) {
                phase_ = Phase::Index;
            } else {
                traj.set({motor.position(), traj.velocity()});
                found(motor, traj);
            }
        }
        if (motor.blocked()) {
            fail("mechanical stop reached while searching the switch edge");
        }
        break;
    }
    case Phase::Index: {
        const int d = method_.ref == HomingRef::LimitSwitch ? -dir_ : method_.edge;
        traj.step_velocity(d * params_.zero_speed, acc, acc, dt);
        if (motor.index_crossed()) {
            traj.set({motor.position(), traj.velocity()});
            found(motor, traj);
        }
        break;
    }
    case Phase::Offset:
        if (traj.step_position(home_target_, params_.switch_speed, acc, acc, dt) &&
            std::abs(motor.position() - home_target_) < 1.0) {
            const double before = motor.position();
            motor.set_position(0);
            const double shift = motor.position() - before;
            traj.set({traj.position() + shift, 0});
            home_target_ = motor.position();
            status_ = Status::Attained;
            settled_ = true;
        }
        break;
    case Phase::Settle:
        status_ = Status::Attained;
        if (traj.step_position(home_target_, params_.zero_speed, acc, acc, dt) &&
            std::abs(motor.position() - home_target_) < 1.0) {
            settled_ = true;
        }
        break;
    }
}

} // namespace codrive::sim
