// SPDX-License-Identifier: Apache-2.0
// Homing procedure of a simulated axis (CiA 402 homing mode, the vendor method tables).
#pragma once

#include <codrive/sim/motor_model.hpp>
#include <codrive/sim/profile.hpp>
#include <codrive/sim/trajectory.hpp>

#include <string>

namespace codrive::sim {

/// Speeds and offsets of one homing run, in position units (per second, per second²).
struct HomingParams {
    double switch_speed = 0; ///< 6099h:01
    double zero_speed = 0;   ///< 6099h:02
    double acceleration = 0; ///< 609Ah
    double home_offset = 0;  ///< 607Ch
    bool move_by_offset = false;
};

/// Runs one homing method against the motor model's switches, stops and index pulses. The
/// search drives the trajectory; the caller makes the motor follow it.
class Homing {
public:
    enum class Status : std::uint8_t { Idle, Running, Attained, Error };

    void start(const HomingMethod& method, const HomingParams& params, MotorModel& motor,
               Trajectory& traj);
    /// Bit 4 cleared or mode left: the run is interrupted (status Idle).
    void interrupt() {
        if (status_ == Status::Running) {
            status_ = Status::Idle;
        }
    }
    /// Forgets an attained/failed result (a new mode, a new power-up).
    void clear() { status_ = Status::Idle; }
    /// One step; `halt` pauses the search (controlword bit 8).
    void step(MotorModel& motor, Trajectory& traj, bool halt, double dt);

    [[nodiscard]] Status status() const { return status_; }
    /// Attained and standing on the home position.
    [[nodiscard]] bool settled() const { return settled_; }
    [[nodiscard]] const std::string& error() const { return error_; }

private:
    enum class Phase : std::uint8_t { Search, Stop, Edge, Index, Offset, Settle };
    void found(MotorModel& motor, Trajectory& traj);
    void fail(std::string why) {
        status_ = Status::Error;
        error_ = std::move(why);
    }

    HomingMethod method_;
    HomingParams params_;
    Status status_ = Status::Idle;
    Phase phase_ = Phase::Search;
    int dir_ = 1;
    int reversals_ = 0;
    double blocked_time_ = 0;
    double home_target_ = 0;
    bool settled_ = false;
    std::string error_;
};

} // namespace codrive::sim
