// SPDX-License-Identifier: Apache-2.0
// Constant-jerk segment profiles (time-optimal trapezoid and 7-segment S-curve) and the
// coordinated straight-line N-axis move.
#include <codrive/drives/trajectory.hpp>

#include <algorithm>
#include <cmath>
#include <limits>

namespace codrive::drives {

namespace {

MotionState integrate(MotionState s, double a0, double j, double d) {
    MotionState out;
    out.p = s.p + s.v * d + a0 * d * d / 2.0 + j * d * d * d / 6.0;
    out.v = s.v + a0 * d + j * d * d / 2.0;
    out.a = a0 + j * d;
    return out;
}

/// Time to go from 0 to v (and a back to 0) in an S-curve.
double s_curve_ramp_time(double v, double amax, double jmax) {
    return v * jmax >= amax * amax ? v / amax + amax / jmax : 2.0 * std::sqrt(v / jmax);
}

/// The three segments of an S-curve velocity change of size dv ≥ 0 (sign applies to jerk).
void s_curve_ramp(std::vector<ScalarProfile::Segment>& out, double dv, double amax, double jmax,
                  double sign) {
    if (dv <= 0) {
        return;
    }
    double tj = 0;
    double ta = 0;
    double ap = 0;
    if (dv * jmax >= amax * amax) {
        tj = amax / jmax;
        ta = dv / amax - amax / jmax;
        ap = amax;
    } else {
        tj = std::sqrt(dv / jmax);
        ap = jmax * tj;
    }
    out.push_back({tj, sign * jmax, 0});
    if (ta > 0) {
        out.push_back({ta, 0, sign * ap});
    }
    out.push_back({tj, -sign * jmax, sign * ap});
}

} // namespace

ScalarProfile::ScalarProfile(MotionState start, std::vector<Segment> segments)
    : start_(start), segments_(std::move(segments)) {
    MotionState s = start_;
    for (const Segment& seg : segments_) {
        starts_.push_back(s);
        s = integrate(s, seg.a0, seg.jerk, seg.duration);
        duration_ += seg.duration;
    }
    end_ = s;
    end_.a = 0;
}

ScalarProfile ScalarProfile::rest_to_rest(double distance, double vmax, double amax, double jmax,
                                          ProfileShape shape) {
    if (distance <= 0 || vmax <= 0 || amax <= 0) {
        return ScalarProfile(MotionState{}, {});
    }
    std::vector<Segment> segs;
    if (shape == ProfileShape::Trapezoidal || jmax <= 0) {
        double v = vmax;
        if (v * v / amax > distance) {
            v = std::sqrt(distance * amax); // triangle
        }
        const double ta = v / amax;
        const double tv = (distance - v * v / amax) / v;
        segs.push_back({ta, 0, amax});
        if (tv > 0) {
            segs.push_back({tv, 0, 0});
        }
        segs.push_back({ta, 0, -amax});
    } else {
        double v = vmax;
        if (v * s_curve_ramp_time(v, amax, jmax) > distance) {
            // Largest peak velocity whose ramps fit the distance (v·T(v) grows with v).
            double lo = 0;
            double hi = vmax;
            for (int i = 0; i < 100; ++i) {
                const double mid = (lo + hi) / 2;
                (mid * s_curve_ramp_time(mid, amax, jmax) > distance ? hi : lo) = mid;
            }
            v = lo;
        }
        s_curve_ramp(segs, v, amax, jmax, 1.0);
        const double tv = (distance - v * s_curve_ramp_time(v, amax, jmax)) / v;
        if (tv > 0) {
            segs.push_back({tv, 0, 0});
        }
        s_curve_ramp(segs, v, amax, jmax, -1.0);
    }
    ScalarProfile p(MotionState{}, std::move(segs));
    p.end_ = MotionState{distance, 0, 0}; // exact end despite rounding in the integration
    return p;
}

ScalarProfile ScalarProfile::stop_from(MotionState from, double amax, double jmax,
                                       ProfileShape shape) {
    std::vector<Segment> segs;
    const double v0 = std::max(from.v, 0.0);
    if (v0 <= 0 || amax <= 0) {
        return ScalarProfile(MotionState{from.p, 0, 0}, {});
    }
    if (shape == ProfileShape::Trapezoidal || jmax <= 0) {
        segs.push_back({v0 / amax, 0, -amax});
        ScalarProfile p(MotionState{from.p, v0, 0}, std::move(segs));
        p.end_.v = 0;
        return p;
    }
    MotionState s{from.p, v0, std::clamp(from.a, -amax, amax)};
    const double a0 = s.a;
    if (a0 < 0 && v0 <= a0 * a0 / (2 * jmax)) {
        // Already braking hard enough: standstill comes while the deceleration fades.
        const double disc = std::max(a0 * a0 - 2 * jmax * v0, 0.0);
        const double t = (-a0 - std::sqrt(disc)) / jmax;
        segs.push_back({t, jmax, a0});
        ScalarProfile p(s, std::move(segs));
        p.end_.v = 0;
        return p;
    }
    // Jerk down from a0 to the peak deceleration ap, hold it, jerk back to 0 as v reaches 0:
    // Δv = (a0² − 2·ap²) / 2J − |ap|·t2 = −v0.
    double ap = -std::sqrt((a0 * a0 + 2 * jmax * v0) / 2);
    double t2 = 0;
    if (ap < -amax) {
        ap = -amax;
        t2 = (v0 + (a0 * a0 - 2 * amax * amax) / (2 * jmax)) / amax;
    }
    segs.push_back({(a0 - ap) / jmax, -jmax, a0});
    if (t2 > 0) {
        segs.push_back({t2, 0, ap});
    }
    segs.push_back({-ap / jmax, jmax, ap});
    ScalarProfile p(s, std::move(segs));
    p.end_.v = 0;
    return p;
}

MotionState ScalarProfile::at(double t) const {
    if (segments_.empty() || t <= 0) {
        return segments_.empty() ? end_ : start_;
    }
    if (t >= duration_) {
        return end_;
    }
    double t0 = 0;
    for (std::size_t i = 0; i < segments_.size(); ++i) {
        const Segment& seg = segments_[i];
        if (t < t0 + seg.duration || i + 1 == segments_.size()) {
            return integrate(starts_[i], seg.a0, seg.jerk, t - t0);
        }
        t0 += seg.duration;
    }
    return end_;
}

LinearTrajectory::LinearTrajectory(const Eigen::VectorXd& start, const Eigen::VectorXd& end,
                                   const Eigen::VectorXd& vmax, const Eigen::VectorXd& amax,
                                   const Eigen::VectorXd& jmax, ProfileShape shape)
    : start_(start), delta_(end - start), shape_(shape) {
    constexpr double kInf = std::numeric_limits<double>::infinity();
    vs_ = kInf;
    as_ = kInf;
    js_ = kInf;
    bool moving = false;
    // The path parameter s runs from 0 to 1; axis i moves delta_i per unit of s, so the path
    // limit is the tightest of limit_i / |delta_i|.
    for (Eigen::Index i = 0; i < delta_.size(); ++i) {
        const double d = std::abs(delta_[i]);
        if (d == 0) {
            continue;
        }
        moving = true;
        vs_ = std::min(vs_, vmax[i] / d);
        as_ = std::min(as_, amax[i] / d);
        js_ = std::min(js_, jmax.size() > i ? jmax[i] / d : kInf);
    }
    if (!moving) {
        vs_ = as_ = js_ = 0;
        return;
    }
    if (!std::isfinite(js_)) {
        js_ = 0;
    }
    profile_ = ScalarProfile::rest_to_rest(1.0, vs_, as_, js_, shape_);
}

Eigen::VectorXd LinearTrajectory::position(double t) const {
    return start_ + delta_ * profile_.at(t).p;
}

Eigen::VectorXd LinearTrajectory::velocity(double t) const {
    return delta_ * profile_.at(t).v;
}

Eigen::VectorXd LinearTrajectory::acceleration(double t) const {
    return delta_ * profile_.at(t).a;
}

LinearTrajectory LinearTrajectory::stopped_at(double t) const {
    LinearTrajectory out = *this;
    out.profile_ = ScalarProfile::stop_from(profile_.at(t), as_, js_, shape_);
    return out;
}

} // namespace codrive::drives
