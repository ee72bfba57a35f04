// SPDX-License-Identifier: Apache-2.0
// Units: the CiA 402 factor group (608Fh, 6091h, 6092h, 6096h, 6097h), the FIO's SI unit objects
// (60A8h/60A9h) and an SI layer (metres or radians, per second) on top of an Axis.
#pragma once

#include <codrive/drives/axis.hpp>
#include <codrive/drives/error.hpp>
#include <codrive/drives/profile.hpp>
#include <codrive/drives/transport.hpp>

#include <cstdint>
#include <functional>
#include <numbers>
#include <optional>

namespace codrive::drives {

/// A numerator/divisor pair as the factor-group objects hold it (sub 1 / sub 2).
struct Ratio {
    std::uint32_t num = 1;
    std::uint32_t den = 1;
    [[nodiscard]] double value() const {
        return den == 0 ? 0.0 : static_cast<double>(num) / static_cast<double>(den);
    }
};

/// The factor group of one axis. Position units per shaft revolution = feed (6092h); motor
/// revolutions per shaft revolution = gear (6091h). Velocity objects hold position units per
/// second × 6096h, acceleration objects velocity units per second × 6097h (AKD2G manual
/// §4.1.4, whose worked examples the tests reproduce).
struct FactorGroup {
    double increments_per_motor_rev = 0; ///< 608Fh:1 / 608Fh:2 (AKD2G: 2^32); 0 = unknown
    Ratio gear;
    Ratio feed;
    Ratio velocity;
    Ratio acceleration;

    [[nodiscard]] double position_units_per_shaft_rev() const { return feed.value(); }
    [[nodiscard]] double position_units_per_motor_rev() const {
        return gear.value() == 0 ? 0 : feed.value() / gear.value();
    }
    /// Drive-internal increments for a position value, and back (needs increments_per_motor_rev).
    [[nodiscard]] double to_increments(double position) const;
    [[nodiscard]] double from_increments(double increments) const;
    /// The velocity object value (60FFh, 606Ch) for position units per second, and back.
    [[nodiscard]] double velocity_value(double position_units_per_s) const {
        return position_units_per_s * velocity.value();
    }
    [[nodiscard]] double position_units_per_s(double velocity_value) const;
    /// The acceleration object value (6083h) for position units per second².
    [[nodiscard]] double acceleration_value(double position_units_per_s2) const {
        return position_units_per_s2 * velocity.value() * acceleration.value();
    }
};

/// SI size of one drive unit: position (m or rad), velocity (m/s or rad/s), acceleration.
struct SiScale {
    double position = 1;     ///< SI per position unit
    double velocity = 1;     ///< SI/s per velocity unit
    double acceleration = 1; ///< SI/s² per acceleration unit
    bool linear = false;     ///< metres (true) or radians

    /// From the factor group and the mechanics: SI per shaft revolution (2π rad for a rotary
    /// output, the screw lead in metres for a linear axis).
    static SiScale from_factor_group(const FactorGroup& fg, double si_per_shaft_rev,
                                     bool linear = false);
    /// From the FIO's 60A8h/60A9h (bits 31..24 exponent, 23..16 unit, 15..8 time unit) and the
    /// acceleration factor 6097h. Errors: InvalidArgument for non-SI units (increments, steps,
    /// poles, dimensionless) or unknown codes.
    static DriveResult<SiScale> from_si_unit_objects(std::uint32_t si_position,
                                                     std::uint32_t si_velocity,
                                                     Ratio acceleration = {});
    /// DS-BVS fixed units: counts (608Fh:1 per motor rev), RPM, RPM/s.
    static SiScale fixed_rpm(double counts_per_rev);

    [[nodiscard]] std::int32_t to_position(double si) const;
    [[nodiscard]] double from_position(std::int32_t value) const { return value * position; }
    [[nodiscard]] std::int32_t to_velocity(double si_per_s) const;
    [[nodiscard]] double from_velocity(std::int32_t value) const { return value * velocity; }
    [[nodiscard]] std::uint32_t to_acceleration(double si_per_s2) const;
};

/// SI size of one 60A8h position unit (m, rad), or nullopt for non-SI codes.
[[nodiscard]] std::optional<double> si_position_unit(std::uint32_t si_position);

/// Reads the factor group of an axis (objects the profile lacks keep their defaults; AKD2G uses
/// its fixed 2^32 increments per revolution). Errors: Transport.
void read_factor_group(DriveTransport& t, const Profile& p, unsigned axis,
                       std::function<void(DriveResult<FactorGroup>)> done);

/// Reads whatever defines the axis's units (FIO: 60A8h/60A9h/6097h; DS-BVS: 608Fh:1 with RPM;
/// others: the factor group) and builds the SI scale.
void read_si_scale(DriveTransport& t, const Profile& p, unsigned axis, double si_per_shaft_rev,
                   bool linear, std::function<void(DriveResult<SiScale>)> done);

/// SI commands on an Axis: metres or radians (per second).
class SiAxis {
public:
    SiAxis(Axis& axis, SiScale scale) : axis_(axis), scale_(scale) {}
    void move_to(double si, MoveOptions options, Axis::Done done,
                 Duration timeout = Duration::zero()) {
        axis_.move_to(scale_.to_position(si), options, std::move(done), timeout);
    }
    void run_velocity(double si_per_s, Axis::Done done, Duration timeout = Duration::zero()) {
        axis_.run_velocity(scale_.to_velocity(si_per_s), std::move(done), timeout);
    }
    void set_target_position(double si) { axis_.set_target_position(scale_.to_position(si)); }
    void set_target_velocity(double si_per_s) {
        axis_.set_target_velocity(scale_.to_velocity(si_per_s));
    }
    [[nodiscard]] std::optional<double> position() const {
        auto p = axis_.position_actual();
        return p ? std::optional<double>(scale_.from_position(*p)) : std::nullopt;
    }
    [[nodiscard]] const SiScale& scale() const { return scale_; }
    [[nodiscard]] Axis& axis() { return axis_; }

private:
    Axis& axis_;
    SiScale scale_;
};

} // namespace codrive::drives
