// SPDX-License-Identifier: Apache-2.0
// Motor + mechanics model of one axis.
#include <codrive/sim/motor_model.hpp>

#include <algorithm>
#include <cmath>

namespace codrive::sim {

MotorModel::MotorModel(MachineConfig config) : config_(config) {}

std::uint32_t MotorModel::digital_inputs() const {
    std::uint32_t v = 0;
    if (neg_limit()) {
        v |= 1U << 0;
    }
    if (pos_limit()) {
        v |= 1U << 1;
    }
    if (home_switch()) {
        v |= 1U << 2;
    }
    return v;
}

void MotorModel::integrate(double v, double dt) {
    const double vmax = rev(config_.max_velocity_rev_s);
    v = std::clamp(v, -vmax, vmax);
    if (jammed_) {
        v = 0;
    }
    const double before = world_;
    double next = world_ + v * dt;
    blocked_ = false;
    const double lo = rev(config_.neg_stop_rev);
    const double hi = rev(config_.pos_stop_rev);
    if (next <= lo) {
        next = lo;
        blocked_ = v < 0;
    } else if (next >= hi) {
        next = hi;
        blocked_ = v > 0;
    }
    const double accel = dt > 0 ? ((next - before) / dt - velocity_) / dt : 0;
    velocity_ = dt > 0 ? (next - before) / dt : 0;
    last_world_ = before;
    world_ = next;
    // Index: one pulse per revolution at the configured phase.
    const double cpr = config_.counts_per_rev;
    const double phase = config_.index_phase_rev * cpr;
    index_crossed_ = std::floor((before - phase) / cpr) != std::floor((world_ - phase) / cpr);
    if (blocked_ || jammed_) {
        torque_ = std::copysign(config_.max_torque_permille, v);
    } else {
        const double per_permille = rev(config_.rev_s2_per_permille);
        torque_ = std::clamp(accel / per_permille, -config_.max_torque_permille,
                             config_.max_torque_permille);
    }
}

void MotorModel::follow_position(double demand, double demand_velocity, double dt) {
    const double err = demand - position();
    integrate(demand_velocity + config_.servo_gain * err, dt);
}

void MotorModel::follow_velocity(double demand_velocity, double dt) {
    integrate(demand_velocity, dt);
}

void MotorModel::apply_torque(double torque_permille, double dt) {
    const double t =
        std::clamp(torque_permille, -config_.max_torque_permille, config_.max_torque_permille);
    // Viscous friction keeps the speed finite: 1 % of the speed per millisecond.
    const double accel = t * rev(config_.rev_s2_per_permille) - velocity_ * 10.0;
    integrate(velocity_ + accel * dt, dt);
    torque_ = t;
}

void MotorModel::coast(double dt) {
    const double decay = std::max(0.0, 1.0 - 20.0 * dt);
    double v = velocity_ * decay;
    if (std::abs(v) < 1e-3 * config_.counts_per_rev) {
        v = 0;
    }
    integrate(v, dt);
    torque_ = 0;
}

} // namespace codrive::sim
