// SPDX-License-Identifier: Apache-2.0
// Online trapezoidal profile generator.
#include <codrive/sim/trajectory.hpp>

#include <algorithm>
#include <cmath>

namespace codrive::sim {

namespace {

/// Changes v toward want by at most acc·dt when speeding up and dec·dt when slowing down.
double ramp(double v, double want, double acc, double dec, double dt) {
    const bool speeding_up = (v >= 0 && want > v) || (v <= 0 && want < v);
    const bool same_sign = (v >= 0) == (want >= 0);
    const double limit = (speeding_up && same_sign ? acc : dec) * dt;
    if (std::abs(want - v) <= limit) {
        return want;
    }
    return v + (want > v ? limit : -limit);
}

} // namespace

bool Trajectory::step_position(double target, double vmax, double acc, double dec, double dt) {
    vmax = std::max(vmax, 1e-9);
    acc = std::max(acc, 1e-9);
    dec = std::max(dec, 1e-9);
    const double dist = target - point_.position;
    if (std::abs(dist) < 1e-6 && std::abs(point_.velocity) <= dec * dt) {
        point_ = {target, 0};
        return true;
    }
    const double dir = dist >= 0 ? 1.0 : -1.0;
    // Fastest velocity from which the target can still be reached by braking with `dec`,
    // evaluated half a step ahead so the discrete ramp does not overshoot.
    const double brake_v = std::sqrt(2.0 * dec * std::abs(dist));
    const double want = dir * std::min(vmax, brake_v);
    const double v = ramp(point_.velocity, want, acc, dec, dt);
    double next = point_.position + 0.5 * (point_.velocity + v) * dt;
    if ((target - next) * dir <= 0) {
        // Crossing the target this step: land on it.
        if (std::abs(v) <= dec * dt * 2 || std::abs(dist) < std::abs(v) * dt) {
            point_ = {target, 0};
            return true;
        }
        next = target;
    }
    point_ = {next, v};
    return false;
}

bool Trajectory::step_velocity(double target_velocity, double acc, double dec, double dt) {
    const double v =
        ramp(point_.velocity, target_velocity, std::max(acc, 1e-9), std::max(dec, 1e-9), dt);
    point_.position += 0.5 * (point_.velocity + v) * dt;
    point_.velocity = v;
    return v == target_velocity;
}

} // namespace codrive::sim
