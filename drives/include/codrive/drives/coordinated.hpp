// SPDX-License-Identifier: Apache-2.0
// Coordinated motion: an N-axis trajectory streamed as CSP targets, one set-point per axis for
// the same SYNC, and a coordinated stop along the path.
#pragma once

#include <codrive/drives/axis.hpp>
#include <codrive/drives/trajectory.hpp>

#include <Eigen/Dense>

#include <functional>
#include <vector>

namespace codrive::drives {

class CoordinatedMotion {
public:
    using Done = std::function<void(DriveVoid)>;

    /// `axes` must outlive this object; `period` is the SYNC period.
    CoordinatedMotion(std::vector<Axis*> axes, Duration period);

    /// Starts a straight-line move from the axes' current set-points (or actual positions) to
    /// `end` (drive position units). Limits per axis in units/s, /s², /s³. Errors (returned,
    /// `done` is not called): InvalidArgument (sizes), WrongState (an axis not OPERATION
    /// ENABLED), WrongMode (an axis not in CSP), NotMapped (no start position known).
    DriveVoid start(const Eigen::VectorXd& end, const Eigen::VectorXd& vmax,
                    const Eigen::VectorXd& amax, const Eigen::VectorXd& jmax, ProfileShape shape,
                    Done done);

    /// Once per SYNC period, before the SYNC goes out: computes the set-point for the next SYNC
    /// and hands every axis its target for that same SYNC. Ends the move (calls done) after the
    /// last set-point; fails it if an axis leaves OPERATION ENABLED.
    void on_sync();

    /// Coordinated stop: all axes decelerate along the path and stop together. `done` runs when
    /// they stand still (the move's own callback gets DriveErrc::Cancelled).
    void stop(Done done);

    [[nodiscard]] bool active() const { return active_; }
    [[nodiscard]] std::uint64_t cycles() const { return k_; }
    /// The set-point (unrounded) sent with the last on_sync().
    [[nodiscard]] const Eigen::VectorXd& last_setpoint() const { return last_; }
    [[nodiscard]] const LinearTrajectory& trajectory() const { return traj_; }

private:
    void complete(DriveVoid result);

    std::vector<Axis*> axes_;
    double period_s_;
    LinearTrajectory traj_;
    bool active_ = false;
    std::uint64_t k_ = 0; ///< SYNCs since the start of the current trajectory
    double t_base_ = 0;   ///< time of k_ = 0 on the current trajectory
    Eigen::VectorXd last_;
    Done done_;
    Done stop_done_;
};

} // namespace codrive::drives
