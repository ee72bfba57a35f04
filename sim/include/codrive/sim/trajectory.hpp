// SPDX-License-Identifier: Apache-2.0
// Online trapezoidal profile generator: position and velocity ramps re-planned every step.
#pragma once

namespace codrive::sim {

/// A 1-D trajectory point in position units and position units per second.
struct TrajectoryPoint {
    double position = 0;
    double velocity = 0;
};

/// Generates trapezoidal (or triangular) moves. Re-planning every step means a new target,
/// velocity or acceleration takes effect at once without a stop ("change set immediately"),
/// and the move ends exactly on the target.
class Trajectory {
public:
    void reset(double position) { point_ = {position, 0}; }
    /// Moves toward `target` with at most `vmax`, accelerating with `acc`, braking with `dec`.
    /// Returns true once the target is reached and the velocity is 0.
    bool step_position(double target, double vmax, double acc, double dec, double dt);
    /// Ramps the velocity toward `target_velocity` (acc when speeding up, dec when slowing).
    /// Returns true when the target velocity is reached.
    bool step_velocity(double target_velocity, double acc, double dec, double dt);

    [[nodiscard]] const TrajectoryPoint& point() const { return point_; }
    [[nodiscard]] double position() const { return point_.position; }
    [[nodiscard]] double velocity() const { return point_.velocity; }
    void set(TrajectoryPoint p) { point_ = p; }

private:
    TrajectoryPoint point_;
};

} // namespace codrive::sim
