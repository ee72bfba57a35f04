// SPDX-License-Identifier: Apache-2.0
// Motor + mechanics model of one axis: servo-following, torque, limits, switches, index pulse.
#pragma once

#include <cstdint>

namespace codrive::sim {

/// The simulated machine around one motor, in motor revolutions (converted with the profile's
/// position units per revolution). Defaults: limit switches at ±10 rev, mechanical stops at
/// ±10.5 rev, a home switch active between 2 and 3 rev, one index pulse per revolution at
/// 0.25 rev. The axis powers up at world position 0.
struct MachineConfig {
    double counts_per_rev = 65536;
    double neg_limit_rev = -10;
    double pos_limit_rev = 10;
    double neg_stop_rev = -10.5;
    double pos_stop_rev = 10.5;
    double home_low_rev = 2;
    double home_high_rev = 3;
    double index_phase_rev = 0.25;
    double max_velocity_rev_s = 100;   ///< mechanical speed limit
    double max_torque_permille = 3000; ///< peak torque
    double rev_s2_per_permille = 0.5;  ///< acceleration per ‰ of rated torque (inertia)
    double servo_gain = 200;           ///< position loop gain (1/s)
};

/// One motor. Positions are user position units; `world` is the mechanical position the
/// switches and stops are fixed to, `user = world + offset` (homing changes the offset).
class MotorModel {
public:
    explicit MotorModel(MachineConfig config = {});

    /// Powered and following a position demand (PP, HM, CSP): velocity feed-forward plus a
    /// proportional position loop.
    void follow_position(double demand, double demand_velocity, double dt);
    /// Powered and following a velocity demand (PV, CSV).
    void follow_velocity(double demand_velocity, double dt);
    /// Powered, producing a torque (PT, CST) in ‰ of rated torque.
    void apply_torque(double torque_permille, double dt);
    /// Not powered: the motor coasts to a stop on friction.
    void coast(double dt);

    [[nodiscard]] double position() const { return world_ + offset_; }
    [[nodiscard]] double world() const { return world_; }
    [[nodiscard]] double velocity() const { return velocity_; }
    [[nodiscard]] double torque() const { return torque_; }
    /// Moves the user coordinate so the current position reads `user_position` (homing).
    void set_position(double user_position) { offset_ = user_position - world_; }
    /// Teleports the mechanics (tests).
    void set_world(double world) {
        world_ = world;
        last_world_ = world;
        velocity_ = 0;
    }

    [[nodiscard]] bool neg_limit() const { return world_ <= rev(config_.neg_limit_rev); }
    [[nodiscard]] bool pos_limit() const { return world_ >= rev(config_.pos_limit_rev); }
    [[nodiscard]] bool home_switch() const {
        return world_ >= rev(config_.home_low_rev) && world_ <= rev(config_.home_high_rev);
    }
    /// True if an index pulse passed during the last step.
    [[nodiscard]] bool index_crossed() const { return index_crossed_; }
    /// True while pushing against a mechanical stop.
    [[nodiscard]] bool blocked() const { return blocked_; }
    /// 60FDh bits: 0 negative limit, 1 positive limit, 2 home switch.
    [[nodiscard]] std::uint32_t digital_inputs() const;
    [[nodiscard]] const MachineConfig& config() const { return config_; }
    /// Jams the mechanics (fault injection: the motor cannot move).
    void set_jammed(bool on) { jammed_ = on; }

private:
    [[nodiscard]] double rev(double r) const { return r * config_.counts_per_rev; }
    void integrate(double v, double dt);

    MachineConfig config_;
    double world_ = 0;
    double last_world_ = 0;
    double offset_ = 0;
    double velocity_ = 0;
    double torque_ = 0;
    bool index_crossed_ = false;
    bool blocked_ = false;
    bool jammed_ = false;
};

} // namespace codrive::sim
