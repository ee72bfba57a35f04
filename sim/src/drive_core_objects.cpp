// SPDX-License-Identifier: Apache-2.0
// The CiA 402 objects of one simulated axis, with the profile's types, access, ranges, defaults.
#include <codrive/sim/drive_core.hpp>

#include <algorithm>
#include <limits>

namespace codrive::sim {

namespace obj = drives::cia402::obj;

namespace {

Value make_value(DataType t, std::int64_t v) {
    if (is_signed_integer(t)) {
        if (auto r = Value::from_int(t, v)) {
            return *r;
        }
    } else if (auto r = Value::from_uint(t, static_cast<std::uint64_t>(v))) {
        return *r;
    }
    return Value::zero(t);
}

/// PDO direction letters of the specs: 'R' RPDO-mappable (rww), 'T' TPDO-mappable, '-' none.
SubObject make_sub(std::uint8_t sub, std::string name, DataType t, Access a, char pdo,
                   std::int64_t v) {
    Access access = a;
    if (pdo == 'R' && a == Access::Rw) {
        access = Access::Rww;
    } else if (pdo == 'T' && a == Access::Rw) {
        access = Access::Rwr;
    }
    return SubObject::make(sub, std::move(name), t, access, make_value(t, v), pdo != '-');
}

/// Installs one axis's objects. Where the drive profile (codrive::drives, the master's data)
/// describes an object, its data type comes from there, and for the objects the profile gives
/// drive-specific values (Profile::object_overrides, taken from the manual) also the value range
/// and, where the manual documents defaults (Profile::documents_defaults), the default: one
/// place per fact, the simulator never keeps a second copy.
class Installer {
public:
    Installer(ObjectDictionary& od, std::uint16_t offset, const drives::Profile& drive)
        : od_(od), offset_(offset), drive_(drive), objects_(drives::device_objects(drive, 1)) {}

    SubObject& var(std::uint16_t base, std::string name, DataType t, Access a, char pdo,
                   std::int64_t v) {
        Object o;
        o.index = static_cast<std::uint16_t>(base + offset_);
        o.name = name;
        o.code = ObjectCode::Var;
        o.subs.emplace(0, profile_sub(base, 0, std::move(name), t, a, pdo, v));
        return od_.insert(std::move(o)).subs.at(0);
    }
    /// A sub-object of a RECORD/ARRAY, typed and valued as var() does.
    SubObject sub(std::uint16_t base, std::uint8_t si, std::string name, DataType t, Access a,
                  std::int64_t v) {
        return profile_sub(base, si, std::move(name), t, a, '-', v);
    }
    void range(SubObject& s, std::int64_t lo, std::int64_t hi) {
        s.low_limit = make_value(s.type, lo);
        s.high_limit = make_value(s.type, hi);
    }
    /// A RECORD/ARRAY with sub 0 = highest sub-index (ro) and the given entries.
    Object& record(std::uint16_t base, std::string name, ObjectCode code,
                   std::vector<SubObject> subs, std::uint16_t offset_override = 0xFFFF) {
        Object o;
        o.index = static_cast<std::uint16_t>(
            base + (offset_override == 0xFFFF ? offset_ : offset_override));
        o.name = std::move(name);
        o.code = code;
        std::uint8_t highest = 0;
        for (auto& s : subs) {
            highest = std::max(highest, s.subindex);
        }
        o.subs.emplace(0, make_sub(0, "Highest sub-index supported", DataType::Unsigned8,
                                   Access::Ro, '-', highest));
        for (auto& s : subs) {
            const std::uint8_t si = s.subindex;
            o.subs.emplace(si, std::move(s));
        }
        return od_.insert(std::move(o));
    }

private:
    [[nodiscard]] const drives::ObjectSpec* spec(std::uint16_t base, std::uint8_t si) const {
        for (const auto& o : objects_) {
            if (o.index == base && o.subindex == si) {
                return &o;
            }
        }
        return nullptr;
    }
    [[nodiscard]] bool drive_specific(std::uint16_t base, std::uint8_t si) const {
        return std::any_of(
            drive_.object_overrides.begin(), drive_.object_overrides.end(),
            [&](const drives::ObjectSpec& o) { return o.index == base && o.subindex == si; });
    }
    SubObject profile_sub(std::uint16_t base, std::uint8_t si, std::string name, DataType t,
                          Access a, char pdo, std::int64_t v) const {
        const drives::ObjectSpec* s = spec(base, si);
        if (s == nullptr) {
            return make_sub(si, std::move(name), t, a, pdo, v);
        }
        const bool own = drive_specific(base, si);
        const bool own_default = own && drive_.documents_defaults;
        SubObject out =
            make_sub(si, std::move(name), s->type, a, pdo, own_default ? s->default_value : v);
        if (own && s->has_limits) {
            out.low_limit = make_value(s->type, s->low);
            out.high_limit = make_value(s->type, s->high);
        }
        return out;
    }

    ObjectDictionary& od_;
    std::uint16_t offset_;
    const drives::Profile& drive_;
    std::vector<drives::ObjectSpec> objects_;
};

} // namespace

void DriveCore::install_objects() {
    const SimProfile& p = profile_;
    const auto offset = static_cast<std::uint16_t>(index(0x6000) - 0x6000);
    Installer in(od_, offset, *p.drive);
    using DT = DataType;
    const auto rw = Access::Rw;
    const auto ro = Access::Ro;
    const bool fio = p.name() == "fio";
    const auto vel = [&p](std::uint32_t v) { return static_cast<std::int64_t>(v); };

    if (p.drive->has_object(obj::kErrorCode)) { // AKD2G: no 603Fh (§5.6)
        in.var(obj::kErrorCode, "Error code", DT::Unsigned16, ro, 'T', 0);
    }
    in.var(obj::kControlword, "Controlword", DT::Unsigned16, rw, 'R', 0);
    in.var(obj::kStatusword, "Statusword", DT::Unsigned16, ro, 'T', 0);
    // Option codes (605Ah..605Eh, 6007h): which exist, defaults and ranges from the profile.
    const auto objects = drives::device_objects(*p.drive, 1);
    const auto option = [&](std::uint16_t base) {
        for (const auto& o : objects) {
            if (o.index == base && o.subindex == 0) {
                auto& s = in.var(base, std::string(o.name), o.type, o.access, '-', o.default_value);
                if (o.has_limits) {
                    in.range(s, o.low, o.high);
                }
                return;
            }
        }
    };
    option(obj::kQuickStopOption);
    if (p.has_option_objects()) {
        for (std::uint16_t base : {obj::kShutdownOption, obj::kDisableOperationOption,
                                   obj::kHaltOption, obj::kFaultReactionOption}) {
            option(base);
        }
    }
    if (axis_ == 0) {
        option(0x6007); // abort connection: one per device
    }
    in.var(obj::kModesOfOperation, "Modes of operation", DT::Integer8, rw, 'R', p.default_mode());
    in.var(obj::kModesOfOperationDisplay, "Modes of operation display", DT::Integer8, ro, 'T',
           p.default_mode());
    if (p.ds_bvs_objects) {
        in.var(obj::kPositionDemand, "Position demand value", DT::Integer32, ro, fio ? 'T' : '-',
               0);
    }
    in.var(0x6063, "Position actual internal value", DT::Integer32, ro, p.akd2g_objects ? 'T' : '-',
           0);
    in.var(obj::kPositionActual, "Position actual value", DT::Integer32, ro, 'T', 0);
    {
        auto& s = in.var(obj::kFollowingErrorWindow, "Following error window", DT::Unsigned32, rw,
                         '-', p.following_error_window);
        if (p.ds_bvs_objects && !fio) {
            in.range(s, 1, 2147483647);
        }
    }
    if (!p.ds_bvs_objects || fio) {
        in.var(obj::kFollowingErrorTimeout, "Following error time out", DT::Unsigned16, rw, '-',
               p.following_error_timeout);
    }
    if (p.ds_bvs_objects) {
        in.var(obj::kPositionWindow, "Position window", DT::Unsigned32, rw, '-', p.position_window);
        in.var(obj::kPositionWindowTime, "Position window time", DT::Unsigned16, rw, '-',
               p.position_window_time);
    }
    in.var(obj::kVelocityDemand, "Velocity demand value", DT::Integer32, ro, 'T', 0);
    in.var(obj::kVelocityActual, "Velocity actual value", DT::Integer32, ro, 'T', 0);
    in.var(0x606D, "Velocity window", DT::Unsigned16, rw, p.akd2g_objects ? 'R' : '-',
           p.velocity_window);
    in.var(0x606E, "Velocity window time", DT::Unsigned16, rw, p.akd2g_objects ? 'R' : '-',
           p.velocity_window_time);
    in.var(obj::kTargetTorque, "Target torque", DT::Integer16, rw, 'R', 0);
    in.var(obj::kMaxTorque, "Max torque", DT::Unsigned16, rw, p.akd2g_objects ? 'R' : '-', 1000);
    in.var(obj::kTorqueActual, "Torque actual value", DT::Integer16, ro, 'T', 0);
    if (p.ds_bvs_objects) {
        in.var(0x6078, "Current actual value", DT::Integer16, ro, 'T', 0);
    }
    in.var(obj::kTargetPosition, "Target position", DT::Integer32, rw, 'R', 0);
    in.var(obj::kHomeOffset, "Home offset", DT::Integer32, rw, '-', 0);
    in.record(obj::kSoftwarePositionLimit, "Software position limit", ObjectCode::Array,
              {in.sub(obj::kSoftwarePositionLimit, 1, "Min position limit", DT::Integer32, rw,
                      fio ? std::numeric_limits<std::int32_t>::min() : 0),
               in.sub(obj::kSoftwarePositionLimit, 2, "Max position limit", DT::Integer32, rw,
                      fio ? std::numeric_limits<std::int32_t>::max() : 0)});
    if (p.max_profile_velocity != 0) {
        in.var(obj::kMaxProfileVelocity, "Max profile velocity", DT::Unsigned32, rw, '-',
               vel(p.max_profile_velocity));
    }
    if (p.ds_bvs_objects) {
        in.range(in.var(0x6080, "Max motor speed", DT::Unsigned32, rw, '-', fio ? 30000 : 3000), 1,
                 fio ? 30000 : 25000);
    }
    in.var(obj::kProfileVelocity, "Profile velocity", DT::Unsigned32, rw,
           p.akd2g_objects ? 'R' : '-', vel(p.profile_velocity));
    in.var(obj::kProfileAcceleration, "Profile acceleration", DT::Unsigned32, rw,
           p.akd2g_objects ? 'R' : '-', vel(p.profile_acceleration));
    in.var(obj::kProfileDeceleration, "Profile deceleration", DT::Unsigned32, rw,
           p.akd2g_objects ? 'R' : '-', vel(p.profile_acceleration));
    if (p.ds_bvs_objects) {
        in.var(obj::kQuickStopDeceleration, "Quick stop deceleration", DT::Unsigned32, rw, '-',
               vel(p.quick_stop_deceleration));
        in.range(in.var(obj::kMotionProfileType, "Motion profile type", DT::Integer16, rw, '-',
                        fio ? 0 : 1),
                 0, fio ? 3 : 1);
        in.record(obj::kPositionEncoderResolution, "Position encoder resolution",
                  ObjectCode::Record,
                  {in.sub(obj::kPositionEncoderResolution, 1, "Encoder increments", DT::Unsigned32,
                          rw, static_cast<std::int64_t>(p.counts_per_rev)),
                   in.sub(obj::kPositionEncoderResolution, 2, "Motor revolutions", DT::Unsigned32,
                          rw, 1)});
    }
    if (p.akd2g_objects) {
        in.var(obj::kTorqueSlope, "Torque slope", DT::Unsigned32, rw, '-', 10000);
        in.record(obj::kGearRatio, "Gear ratio", ObjectCode::Record,
                  {in.sub(obj::kGearRatio, 1, "Motor revolutions", DT::Unsigned32, rw, 1),
                   in.sub(obj::kGearRatio, 2, "Shaft revolutions", DT::Unsigned32, rw, 1)});
        in.record(obj::kFeedConstant, "Feed constant", ObjectCode::Record,
                  {in.sub(obj::kFeedConstant, 1, "Feed", DT::Unsigned32, rw, 65536),
                   in.sub(obj::kFeedConstant, 2, "Shaft revolutions", DT::Unsigned32, rw, 1)});
    }
    in.var(obj::kHomingMethod, "Homing method", DT::Integer8, rw, '-', p.default_homing_method);
    in.record(obj::kHomingSpeeds, "Homing speeds", ObjectCode::Array,
              {in.sub(obj::kHomingSpeeds, 1, "Speed during search for switch", DT::Unsigned32, rw,
                      vel(p.homing_speed_switch)),
               in.sub(obj::kHomingSpeeds, 2, "Speed during search for zero", DT::Unsigned32, rw,
                      vel(p.homing_speed_zero))});
    in.var(obj::kHomingAcceleration, "Homing acceleration", DT::Unsigned32, rw, '-',
           vel(p.homing_acceleration));
    in.var(obj::kPositionOffset, "Position offset", DT::Integer32, rw, 'R', 0);
    in.var(obj::kVelocityOffset, "Velocity offset", DT::Integer32, rw, 'R', 0);
    in.var(obj::kTorqueOffset, "Torque offset", DT::Integer16, rw, 'R', 0);
    if (p.has_interpolation_period) {
        in.record(obj::kInterpolationTimePeriod, "Interpolation time period", ObjectCode::Record,
                  {in.sub(obj::kInterpolationTimePeriod, 1, "Interpolation time period value",
                          DT::Unsigned8, rw, p.akd2g_objects ? 2 : 1),
                   in.sub(obj::kInterpolationTimePeriod, 2, "Interpolation time index",
                          DT::Integer8, rw, -3)});
    }
    if (p.has_supported_homing_object) {
        std::vector<SubObject> subs;
        std::uint8_t si = 1;
        for (const std::int8_t m : p.drive->homing_methods) {
            subs.push_back(make_sub(si++, "Supported homing method", DT::Integer16, ro, '-', m));
        }
        in.record(0x60E3, "Supported homing methods", ObjectCode::Array, std::move(subs));
    }
    in.var(obj::kFollowingErrorActual, "Following error actual value", DT::Integer32, ro,
           p.akd2g_objects ? 'T' : '-', 0);
    if (p.akd2g_objects) {
        in.var(0x60FC, "Position demand internal value", DT::Integer32, ro, 'T', 0);
    }
    in.var(obj::kDigitalInputs, "Digital inputs", DT::Unsigned32, ro, 'T', 0);
    in.var(obj::kTargetVelocity, "Target velocity", DT::Integer32, rw, 'R', 0);
    in.var(obj::kSupportedDriveModes, "Supported drive modes", DT::Unsigned32,
           p.ds_bvs_objects ? Access::Const : ro, '-', p.supported_modes());

    // Every further object the drive profile describes for this axis (AKD2G 6096h/6097h, FIO
    // 60A8h/60A9h and 3202h, ...): as the profile gives it, so the simulated drive answers for
    // each object the master's profile says the drive has.
    for (const auto& s : drives::device_objects(*p.drive, axis_ + 1)) {
        if (od_.find(s.index, s.subindex) == nullptr) {
            drives::add_object(od_, s);
        }
    }
    if (p.akd2g_objects) {
        // Manufacturer axis objects: axis 2 at +0x100 (akd2g.md §4), named per axis as the
        // manual's object tables name them (AXIS1.CS.DEC, AXIS2.CS.DEC, ...).
        const auto m = static_cast<std::uint16_t>(mfr_index(0x5000) - 0x5000);
        const std::string ax = "AXIS" + std::to_string(axis_ + 1);
        // §5.3.82: all five sub-indices (a master reading the entry descriptions 1..highest
        // meets no gap).
        in.record(
            0x5002, ax + ".CS", ObjectCode::Record,
            {make_sub(1, ax + ".CS.STATE", DT::Unsigned8, ro, '-', 0),
             make_sub(2, ax + ".CS.DEC", DT::Unsigned32, rw, '-', vel(p.quick_stop_deceleration)),
             make_sub(3, ax + ".ZEROT", DT::Unsigned32, rw, '-', 0),
             make_sub(4, ax + ".ZEROV", DT::Integer32, rw, '-', 6553),
             make_sub(5, ax + ".ZEROACC", DT::Integer32, rw, '-', 0)},
            m);
        in.record(0x5007, ax + ".SAFE.STO", ObjectCode::Record,
                  {make_sub(1, ax + ".SAFE.STO.REPORTFAULT", DT::Unsigned8, rw, '-', 1),
                   make_sub(2, ax + ".SAFE.STO.ACTIVE", DT::Unsigned8, ro, 'T', 0)},
                  m);
        // §5.3.84: AXIS#.FAULT1..10, Unsigned16, read only: where the drive names the axis of a
        // fault (the EMCY message does not).
        std::vector<SubObject> faults;
        for (std::uint8_t i = 1; i <= kAxisFaultSlots; ++i) {
            faults.push_back(
                make_sub(i, ax + ".FAULT" + std::to_string(i), DT::Unsigned16, ro, '-', 0));
        }
        in.record(0x5004, ax + ".FAULT", ObjectCode::Record, std::move(faults), m);
        in.record(0x5016, ax + ".SETTLE", ObjectCode::Record,
                  {make_sub(1, ax + ".SETTLE.P", DT::Unsigned32, rw, '-', p.position_window)}, m);
    }
}

} // namespace codrive::sim
