// SPDX-License-Identifier: Apache-2.0
// Trajectories: a 1-D profile of constant-jerk segments (trapezoidal or jerk-limited), and a
// straight-line N-axis move that keeps every axis within its limits and arrives together.
#pragma once

#include <Eigen/Dense>

#include <vector>

namespace codrive::drives {

enum class ProfileShape : std::uint8_t { Trapezoidal, JerkLimited };

/// Position/velocity/acceleration of a profile at one instant.
struct MotionState {
    double p = 0;
    double v = 0;
    double a = 0;
};

/// A 1-D motion profile made of segments of constant jerk (a trapezoid uses jerk 0 and
/// acceleration steps).
class ScalarProfile {
public:
    struct Segment {
        double duration = 0;
        double jerk = 0;
        double a0 = 0; ///< acceleration at the segment start
    };

    ScalarProfile() = default;
    ScalarProfile(MotionState start, std::vector<Segment> segments);

    /// From rest at 0 to rest at `distance` (≥ 0) within |v| ≤ vmax, |a| ≤ amax, |j| ≤ jmax
    /// (jmax ignored for trapezoidal), time-optimal for the shape.
    static ScalarProfile rest_to_rest(double distance, double vmax, double amax, double jmax,
                                      ProfileShape shape);
    /// From `from` (v ≥ 0) to standstill as fast as the limits allow.
    static ScalarProfile stop_from(MotionState from, double amax, double jmax, ProfileShape shape);

    [[nodiscard]] MotionState at(double t) const;
    [[nodiscard]] double duration() const { return duration_; }
    [[nodiscard]] const MotionState& end() const { return end_; }

private:
    MotionState start_;
    std::vector<Segment> segments_;
    std::vector<MotionState> starts_; ///< state at each segment start
    MotionState end_;
    double duration_ = 0;
};

/// Limits of one axis, in its units per second (², ³).
struct AxisLimits {
    double velocity = 0;
    double acceleration = 0;
    double jerk = 0;
};

/// A coordinated straight-line move: axis i follows start_i + (end_i − start_i)·s(t) with one
/// scalar profile s from 0 to 1, so all axes start, stop and arrive together and each stays
/// within its own limits.
class LinearTrajectory {
public:
    LinearTrajectory() = default;
    LinearTrajectory(const Eigen::VectorXd& start, const Eigen::VectorXd& end,
                     const Eigen::VectorXd& vmax, const Eigen::VectorXd& amax,
                     const Eigen::VectorXd& jmax, ProfileShape shape);

    [[nodiscard]] Eigen::VectorXd position(double t) const;
    [[nodiscard]] Eigen::VectorXd velocity(double t) const;
    [[nodiscard]] Eigen::VectorXd acceleration(double t) const;
    [[nodiscard]] double duration() const { return profile_.duration(); }
    [[nodiscard]] Eigen::Index axes() const { return start_.size(); }
    [[nodiscard]] const Eigen::VectorXd& start() const { return start_; }
    [[nodiscard]] Eigen::VectorXd end() const { return start_ + delta_; }

    /// The coordinated stop from time t: same path, decelerating at the path limits, so every
    /// axis stops at the same instant on the line.
    [[nodiscard]] LinearTrajectory stopped_at(double t) const;

private:
    Eigen::VectorXd start_;
    Eigen::VectorXd delta_;
    double vs_ = 0; ///< path limits (fraction of the line per second ...)
    double as_ = 0;
    double js_ = 0;
    ProfileShape shape_ = ProfileShape::Trapezoidal;
    ScalarProfile profile_;
};

} // namespace codrive::drives
