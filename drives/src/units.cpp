// SPDX-License-Identifier: Apache-2.0
// Factor group arithmetic, 60A8h/60A9h decoding and reading the unit objects from a drive.
#include <codrive/drives/units.hpp>

#include <algorithm>
#include <cmath>
#include <fmt/format.h>
#include <limits>
#include <memory>
#include <vector>

namespace codrive::drives {

namespace {
constexpr double kTwoPi = 2.0 * std::numbers::pi;

template <typename T>
T clamp_round(double v) {
    const double lo = static_cast<double>(std::numeric_limits<T>::min());
    const double hi = static_cast<double>(std::numeric_limits<T>::max());
    return static_cast<T>(std::clamp(std::round(v), lo, hi));
}
} // namespace

double FactorGroup::to_increments(double position) const {
    const double per_rev = position_units_per_motor_rev();
    return per_rev == 0 ? 0 : position / per_rev * increments_per_motor_rev;
}

double FactorGroup::from_increments(double increments) const {
    return increments_per_motor_rev == 0
               ? 0
               : increments / increments_per_motor_rev * position_units_per_motor_rev();
}

double FactorGroup::position_units_per_s(double velocity_value) const {
    const double f = velocity.value();
    return f == 0 ? 0 : velocity_value / f;
}

SiScale SiScale::from_factor_group(const FactorGroup& fg, double si_per_shaft_rev, bool linear) {
    SiScale s;
    s.linear = linear;
    const double units = fg.position_units_per_shaft_rev();
    s.position = units == 0 ? 0 : si_per_shaft_rev / units;
    const double vf = fg.velocity.value();
    s.velocity = vf == 0 ? 0 : s.position / vf;
    const double af = fg.acceleration.value();
    s.acceleration = vf * af == 0 ? 0 : s.position / (vf * af);
    return s;
}

std::optional<double> si_position_unit(std::uint32_t si_position) {
    const auto exponent = static_cast<std::int8_t>(si_position >> 24);
    const auto unit = static_cast<std::uint8_t>(si_position >> 16);
    double base = 0;
    // CiA 402 / FIO manual §7.2.3 unit codes.
    switch (unit) {
    case 0x01:
        base = 1.0;
        break; // metre
    case 0xC1:
        base = 0.0254;
        break; // inch
    case 0xC2:
        base = 0.3048;
        break; // foot
    case 0x40:
        base = kTwoPi / 400.0;
        break; // grade
    case 0x10:
        base = 1.0;
        break; // radian
    case 0x41:
        base = kTwoPi / 360.0;
        break; // degree
    case 0x42:
        base = kTwoPi / 360.0 / 60.0;
        break; // arcminute
    case 0x43:
        base = kTwoPi / 360.0 / 3600.0;
        break; // arcsecond
    case 0xB4:
        base = kTwoPi;
        break; // mechanical revolution
    default:
        return std::nullopt; // increments, steps, poles, dimensionless: drive specific
    }
    return base * std::pow(10.0, exponent);
}

DriveResult<SiScale> SiScale::from_si_unit_objects(std::uint32_t si_position,
                                                   std::uint32_t si_velocity, Ratio acceleration) {
    const auto pos = si_position_unit(si_position);
    if (!pos) {
        return drive_fail(DriveErrc::InvalidArgument,
                          fmt::format("position unit 60A8h = 0x{:08X} is not an SI length or "
                                      "angle",
                                      si_position));
    }
    const auto vel_pos = si_position_unit(si_velocity & 0xFFFF0000U);
    double per_time = 0;
    switch (static_cast<std::uint8_t>(si_velocity >> 8)) {
    case 0x03:
        per_time = 1.0;
        break;
    case 0x47:
        per_time = 60.0;
        break;
    case 0x48:
        per_time = 3600.0;
        break;
    case 0x49:
        per_time = 86400.0;
        break;
    case 0x4A:
        per_time = 365.25 * 86400.0;
        break;
    default:
        break;
    }
    if (!vel_pos || per_time == 0) {
        return drive_fail(
            DriveErrc::InvalidArgument,
            fmt::format("velocity unit 60A9h = 0x{:08X} is not an SI velocity", si_velocity));
    }
    SiScale s;
    const auto code = static_cast<std::uint8_t>(si_position >> 16);
    s.linear = code == 0x01 || code == 0xC1 || code == 0xC2;
    s.position = *pos;
    s.velocity = *vel_pos / per_time;
    const double af = acceleration.value();
    s.acceleration = af == 0 ? 0 : s.velocity / af;
    return s;
}

SiScale SiScale::fixed_rpm(double counts_per_rev) {
    SiScale s;
    s.position = counts_per_rev == 0 ? 0 : kTwoPi / counts_per_rev;
    s.velocity = kTwoPi / 60.0;
    s.acceleration = kTwoPi / 60.0;
    return s;
}

std::int32_t SiScale::to_position(double si) const {
    return position == 0 ? 0 : clamp_round<std::int32_t>(si / position);
}

std::int32_t SiScale::to_velocity(double si_per_s) const {
    return velocity == 0 ? 0 : clamp_round<std::int32_t>(si_per_s / velocity);
}

std::uint32_t SiScale::to_acceleration(double si_per_s2) const {
    return acceleration == 0 ? 0 : clamp_round<std::uint32_t>(std::abs(si_per_s2) / acceleration);
}

// ---- reading from a drive -----------------------------------------------------------------

namespace {

/// Reads a list of U32 objects one after the other; absent objects are skipped.
struct U32Reader : std::enable_shared_from_this<U32Reader> {
    struct Item {
        std::uint16_t index;
        std::uint8_t sub;
        std::uint32_t* out;
    };
    DriveTransport* t = nullptr;
    std::vector<Item> items;
    std::size_t next = 0;
    std::function<void(DriveVoid)> done;

    void run() {
        if (next == items.size()) {
            done({});
            return;
        }
        const Item item = items[next++];
        auto self = shared_from_this();
        t->read_as<std::uint32_t>(item.index, item.sub, [self, item](DriveResult<std::uint32_t> r) {
            if (!r) {
                self->done(tl::unexpected(r.error()));
                return;
            }
            *item.out = *r;
            self->run();
        });
    }
};

} // namespace

void read_factor_group(DriveTransport& t, const Profile& p, unsigned axis,
                       std::function<void(DriveResult<FactorGroup>)> done) {
    auto fg = std::make_shared<FactorGroup>();
    auto enc = std::make_shared<std::array<std::uint32_t, 2>>(std::array<std::uint32_t, 2>{0, 1});
    auto reader = std::make_shared<U32Reader>();
    reader->t = &t;
    const auto add = [&](std::uint16_t base, std::uint8_t sub, std::uint32_t* out) {
        if (p.has_object(base)) {
            reader->items.push_back({p.axis_index(base, axis), sub, out});
        }
    };
    add(cia402::obj::kPositionEncoderResolution, 1, &(*enc)[0]);
    add(cia402::obj::kPositionEncoderResolution, 2, &(*enc)[1]);
    add(cia402::obj::kGearRatio, 1, &fg->gear.num);
    add(cia402::obj::kGearRatio, 2, &fg->gear.den);
    add(cia402::obj::kFeedConstant, 1, &fg->feed.num);
    add(cia402::obj::kFeedConstant, 2, &fg->feed.den);
    add(cia402::obj::kVelocityFactor, 1, &fg->velocity.num);
    add(cia402::obj::kVelocityFactor, 2, &fg->velocity.den);
    add(cia402::obj::kAccelerationFactor, 1, &fg->acceleration.num);
    add(cia402::obj::kAccelerationFactor, 2, &fg->acceleration.den);
    const bool has_encoder = p.has_object(cia402::obj::kPositionEncoderResolution);
    const bool akd2g = &p == &akd2g_profile();
    reader->done = [fg, enc, has_encoder, akd2g, done = std::move(done)](DriveVoid r) {
        if (!r) {
            done(tl::unexpected(r.error()));
            return;
        }
        if (has_encoder && (*enc)[1] != 0) {
            fg->increments_per_motor_rev =
                static_cast<double>((*enc)[0]) / static_cast<double>((*enc)[1]);
        } else if (akd2g) {
            fg->increments_per_motor_rev = 4294967296.0; // §4.1.4: always 2^32 per motor rev
        }
        done(*fg);
    };
    reader->run();
}

void read_si_scale(DriveTransport& t, const Profile& p, unsigned axis, double si_per_shaft_rev,
                   bool linear, std::function<void(DriveResult<SiScale>)> done) {
    if (p.quirks.si_unit_objects) {
        auto vals = std::make_shared<std::array<std::uint32_t, 4>>(
            std::array<std::uint32_t, 4>{0, 0, 1, 1});
        auto reader = std::make_shared<U32Reader>();
        reader->t = &t;
        reader->items = {{p.axis_index(cia402::obj::kSiUnitPosition, axis), 0, &(*vals)[0]},
                         {p.axis_index(cia402::obj::kSiUnitVelocity, axis), 0, &(*vals)[1]},
                         {p.axis_index(cia402::obj::kAccelerationFactor, axis), 1, &(*vals)[2]},
                         {p.axis_index(cia402::obj::kAccelerationFactor, axis), 2, &(*vals)[3]}};
        reader->done = [vals, done = std::move(done)](DriveVoid r) {
            if (!r) {
                done(tl::unexpected(r.error()));
                return;
            }
            done(SiScale::from_si_unit_objects((*vals)[0], (*vals)[1],
                                               Ratio{(*vals)[2], (*vals)[3]}));
        };
        reader->run();
        return;
    }
    if (!p.has_object(cia402::obj::kFeedConstant) &&
        p.has_object(cia402::obj::kPositionEncoderResolution)) {
        // DS-BVS: counts per 608Fh:1, velocity RPM, acceleration RPM/s.
        t.read_as<std::uint32_t>(p.axis_index(cia402::obj::kPositionEncoderResolution, axis), 1,
                                 [done = std::move(done)](DriveResult<std::uint32_t> r) {
                                     if (!r) {
                                         done(tl::unexpected(r.error()));
                                         return;
                                     }
                                     done(SiScale::fixed_rpm(static_cast<double>(*r)));
                                 });
        return;
    }
    read_factor_group(
        t, p, axis, [si_per_shaft_rev, linear, done = std::move(done)](DriveResult<FactorGroup> r) {
            if (!r) {
                done(tl::unexpected(r.error()));
                return;
            }
            done(SiScale::from_factor_group(*r, si_per_shaft_rev, linear));
        });
}

} // namespace codrive::drives
