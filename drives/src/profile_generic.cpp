// SPDX-License-Identifier: Apache-2.0
// The generic CiA 402 profile and the standard object set (types and access per CiA 402-2).
#include "layouts.hpp"

#include <codrive/drives/profile.hpp>

#include <array>

namespace codrive::drives {
namespace {

using DT = DataType;
using A = Access;

constexpr ObjectSpec var(std::uint16_t index, std::string_view name, DataType type, Access access,
                         bool pdo, std::int64_t def = 0) {
    ObjectSpec s;
    s.index = index;
    s.name = name;
    s.type = type;
    s.access = access;
    s.pdo = pdo;
    s.default_value = def;
    return s;
}

constexpr ObjectSpec sub(std::uint16_t index, std::uint8_t subindex, std::string_view name,
                         DataType type, Access access, bool pdo, std::int64_t def = 0) {
    ObjectSpec s = var(index, name, type, access, pdo, def);
    s.subindex = subindex;
    s.record = true;
    return s;
}

// CiA 402-2 object list. Rww = mappable into RPDOs, Rwr/Ro+pdo = into TPDOs.
constexpr std::array kObjects{
    var(0x6007, "Abort connection option code", DT::Integer16, A::Rw, false, 1),
    var(0x603F, "Error code", DT::Unsigned16, A::Ro, true),
    var(0x6040, "Controlword", DT::Unsigned16, A::Rww, true),
    var(0x6041, "Statusword", DT::Unsigned16, A::Ro, true),
    var(0x605A, "Quick stop option code", DT::Integer16, A::Rw, false, 2),
    var(0x605B, "Shutdown option code", DT::Integer16, A::Rw, false, 0),
    var(0x605C, "Disable operation option code", DT::Integer16, A::Rw, false, 1),
    var(0x605D, "Halt option code", DT::Integer16, A::Rw, false, 1),
    var(0x605E, "Fault reaction option code", DT::Integer16, A::Rw, false, 2),
    var(0x6060, "Modes of operation", DT::Integer8, A::Rww, true),
    var(0x6061, "Modes of operation display", DT::Integer8, A::Ro, true),
    var(0x6062, "Position demand value", DT::Integer32, A::Ro, true),
    var(0x6063, "Position actual internal value", DT::Integer32, A::Ro, true),
    var(0x6064, "Position actual value", DT::Integer32, A::Ro, true),
    var(0x6065, "Following error window", DT::Unsigned32, A::Rw, false),
    var(0x6066, "Following error time out", DT::Unsigned16, A::Rw, false),
    var(0x6067, "Position window", DT::Unsigned32, A::Rw, false),
    var(0x6068, "Position window time", DT::Unsigned16, A::Rw, false),
    var(0x606B, "Velocity demand value", DT::Integer32, A::Ro, true),
    var(0x606C, "Velocity actual value", DT::Integer32, A::Ro, true),
    var(0x606D, "Velocity window", DT::Unsigned16, A::Rw, false),
    var(0x606E, "Velocity window time", DT::Unsigned16, A::Rw, false),
    var(0x6071, "Target torque", DT::Integer16, A::Rww, true),
    var(0x6072, "Max torque", DT::Unsigned16, A::Rw, true),
    var(0x6077, "Torque actual value", DT::Integer16, A::Ro, true),
    var(0x607A, "Target position", DT::Integer32, A::Rww, true),
    var(0x607C, "Home offset", DT::Integer32, A::Rw, false),
    sub(0x607D, 1, "Min position limit", DT::Integer32, A::Rw, false, -2147483648LL),
    sub(0x607D, 2, "Max position limit", DT::Integer32, A::Rw, false, 2147483647LL),
    var(0x607E, "Polarity", DT::Unsigned8, A::Rw, false),
    var(0x607F, "Max profile velocity", DT::Unsigned32, A::Rw, false, 0xFFFFFFFFLL),
    var(0x6081, "Profile velocity", DT::Unsigned32, A::Rww, true),
    var(0x6083, "Profile acceleration", DT::Unsigned32, A::Rww, true),
    var(0x6084, "Profile deceleration", DT::Unsigned32, A::Rww, true),
    var(0x6085, "Quick stop deceleration", DT::Unsigned32, A::Rw, false),
    var(0x6086, "Motion profile type", DT::Integer16, A::Rw, false),
    var(0x6087, "Torque slope", DT::Unsigned32, A::Rw, false),
    sub(0x608F, 1, "Encoder increments", DT::Unsigned32, A::Rw, false, 1),
    sub(0x608F, 2, "Motor revolutions", DT::Unsigned32, A::Rw, false, 1),
    sub(0x6091, 1, "Motor revolutions", DT::Unsigned32, A::Rw, false, 1),
    sub(0x6091, 2, "Shaft revolutions", DT::Unsigned32, A::Rw, false, 1),
    sub(0x6092, 1, "Feed", DT::Unsigned32, A::Rw, false, 1),
    sub(0x6092, 2, "Shaft revolutions", DT::Unsigned32, A::Rw, false, 1),
    sub(0x6096, 1, "Numerator", DT::Unsigned32, A::Rw, false, 1),
    sub(0x6096, 2, "Divisor", DT::Unsigned32, A::Rw, false, 1),
    sub(0x6097, 1, "Numerator", DT::Unsigned32, A::Rw, false, 1),
    sub(0x6097, 2, "Divisor", DT::Unsigned32, A::Rw, false, 1),
    var(0x6098, "Homing method", DT::Integer8, A::Rw, false),
    sub(0x6099, 1, "Speed during search for switch", DT::Unsigned32, A::Rw, false),
    sub(0x6099, 2, "Speed during search for zero", DT::Unsigned32, A::Rw, false),
    var(0x609A, "Homing acceleration", DT::Unsigned32, A::Rw, false),
    var(0x60B0, "Position offset", DT::Integer32, A::Rww, true),
    var(0x60B1, "Velocity offset", DT::Integer32, A::Rww, true),
    var(0x60B2, "Torque offset", DT::Integer16, A::Rww, true),
    sub(0x60C1, 1, "Interpolation data record 1", DT::Integer32, A::Rww, true),
    sub(0x60C2, 1, "Interpolation time period value", DT::Unsigned8, A::Rw, false, 1),
    sub(0x60C2, 2, "Interpolation time index", DT::Integer8, A::Rw, false, -3),
    var(0x60F4, "Following error actual value", DT::Integer32, A::Ro, true),
    var(0x60FD, "Digital inputs", DT::Unsigned32, A::Ro, true),
    var(0x60FF, "Target velocity", DT::Integer32, A::Rww, true),
    var(0x6502, "Supported drive modes", DT::Unsigned32, A::Ro, false, 0x3ED),
};

constexpr std::array kGenericLayouts{layouts::pp, layouts::pv,  layouts::pt,  layouts::hm,
                                     layouts::ip, layouts::csp, layouts::csv, layouts::cst};
constexpr std::array<std::int8_t, 37> kGenericHoming{
    1,  2,  3,  4,  5,  6,  7,  8,  9,  10, 11, 12, 13, 14, 15, 16, 17, 18, 19,
    20, 21, 22, 23, 24, 25, 26, 27, 28, 29, 30, 31, 32, 33, 34, 35, 36, 37};
constexpr std::array<std::int16_t, 9> kGenericQuickStop{0, 1, 2, 3, 4, 5, 6, 7, 8};

Profile make_generic() {
    Profile p;
    p.name = "generic";
    p.title = "generic CiA 402 drive";
    p.identity.device_type = 0x00000192; // CiA 402 in bits 0..15; no vendor
    p.identity.device_type_mask = 0x0000FFFF;
    p.max_axes = 1;
    p.supported_modes = 0x3ED; // PP, PV, PT, HM, IP, CSP, CSV, CST (discovered from 6502h)
    p.homing_methods = kGenericHoming;
    p.quick_stop_options = kGenericQuickStop;
    p.default_quick_stop_option = 2;
    p.layouts = kGenericLayouts;
    return p;
}

} // namespace

std::span<const ObjectSpec> generic_objects() {
    return kObjects;
}

const Profile& generic_profile() {
    static const Profile p = make_generic();
    return p;
}

const Profile& canopen_device_profile() {
    static const Profile p = [] {
        Profile d;
        d.name = "canopen-device";
        d.title = "CANopen device, not a CiA 402 drive";
        d.max_axes = 0;
        return d;
    }();
    return p;
}

} // namespace codrive::drives
