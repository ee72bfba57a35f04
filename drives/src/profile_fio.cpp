// SPDX-License-Identifier: Apache-2.0
// Kuhnke FIO Drive Control profile (EtherCAT only): identity, modes, SI user units (60A8h/60A9h),
// the error-number table (1003h bits 31..24, 30 rows) and the error-code table (18 rows).
#include "layouts.hpp"
#include "object_spec_builders.hpp"

#include <codrive/drives/profile.hpp>

#include <array>

namespace codrive::drives {
namespace {

using DT = DataType;
using A = Access;

// Manual E 822 §7.13 (1003h): error codes.
constexpr std::array<FaultRow, 18> kFaults{{
    {0x1000, "", "general error", 0x01},
    {0x2300, "", "current at controller output too high", 0x02},
    {0x3100, "", "over/under-voltage at controller input", 0x04},
    {0x4200, "", "temperature error in control unit", 0x08},
    {0x5540, "", "interlock error (60FDh bit 3 = 0)", 0x01},
    {0x6010, "", "software reset (watchdog)", 0x01},
    {0x6100, "", "internal software error, generic", 0x01},
    {0x6320, "", "nominal current not set (BLDC)", 0x01},
    {0x7212, "", "motor blocked", 0x01},
    {0x7305, "", "sensorless encoder error", 0x01},
    {0x7306, "", "Hall encoder error", 0x01},
    {0x7307, "", "incremental encoder error", 0x01},
    {0x7600, "", "flash storage full or corrupted", 0x01},
    {0x8000, "", "fieldbus monitoring error", 0x10},
    {0x8100, "", "fieldbus monitoring error", 0x10},
    {0x8400, "", "speed monitoring: slippage error too large", 0x20},
    {0x8611, "", "position monitoring: following error too large", 0x20},
    {0x8612, "", "position monitoring: limit switch exceeded", 0x20},
}};

// Manual §7.13 (1003h): error numbers. The code paired with each number is not documented; the
// typical codes are the spec's inferred pairs (used by the simulator only).
constexpr std::array<ErrorNumberRow, 30> kErrorNumbers{{
    {0x01, "input voltage too high", 0x3100},
    {0x02, "output current too high", 0x2300},
    {0x03, "input voltage too low", 0x3100},
    {0x04, "fieldbus error", 0x8000},
    {0x05, "motor turning in wrong direction although the block is enabled", 0x1000},
    {0x06, "CANopen only: NMT master node-guarding request too late", 0x8100},
    {0x07, "sensor 1 electrical fault/defective hardware", 0x7305},
    {0x08, "sensor 2 fault", 0x7306},
    {0x09, "sensor 3 fault", 0x7307},
    {0x0A, "warning: positive limit switch and tolerance range exceeded", 0x8612},
    {0x0B, "warning: negative limit switch and tolerance range exceeded", 0x8612},
    {0x0C, "device temperature above 80 degrees C", 0x4200},
    {0x0D, "following error (6065h/6066h) exceeded", 0x8611},
    {0x0E, "non-volatile storage full, restart needed for clean-up", 0x7600},
    {0x0F, "motor blocked", 0x7212},
    {0x10, "non-volatile storage corrupted, restart needed", 0x7600},
    {0x11, "CANopen only: slave too slow sending PDOs", 0x8100},
    {0x12, "sensor n (> 3) fault", 0x7305},
    {0x13, "CANopen only: PDO not processed (length error)", 0x8100},
    {0x14, "CANopen only: PDO length exceeded", 0x8100},
    {0x15, "non-volatile storage full, restart needed", 0x7600},
    {0x16, "nominal current must be set (203Bh:01)", 0x6320},
    {0x17, "parameter error (encoder resolution, pole pair count)", 0x1000},
    {0x18, "output current too high (adjust PI parameters)", 0x2300},
    {0x19, "internal software error", 0x6100},
    {0x1A, "current too high on digital output", 0x2300},
    {0x1B, "CANopen only: unexpected SYNC length", 0x8100},
    {0x1C, "motor running during EtherCAT state change", 0x8000},
    {0x1D, "speed monitoring: slip error too large", 0x8400},
    {0x2E, "interlock error: 60FDh bit 3 = 0", 0x5540},
}};

// §7.2.1: 6060h accepts -2..6 and 8..10; 6502h = 0x3AF (IP not available).
constexpr std::array<ManufacturerMode, 2> kManufacturerModes{{
    {-1, "clock/direction"},
    {-2, "auto setup"},
}};
constexpr std::array<std::int8_t, 51> kHoming{
    1,  2,  3,   4,   5,   6,   7,   8,   9,   10,  11,  12,  13,  14,  17,  18,  19,
    20, 21, 22,  23,  24,  25,  26,  27,  28,  29,  30,  33,  34,  35,  -1,  -2,  -7,
    -8, -9, -10, -11, -12, -13, -14, -17, -18, -23, -24, -25, -26, -27, -28, -29, -30};
constexpr std::array<std::int16_t, 5> kQuickStop{0, 1, 2, 5, 6};

// EtherCAT only; the CAN-sized layouts serve the CoE transport (the default 11-byte RxPDO1 with
// 3202h is also valid there).
constexpr std::array kLayouts{layouts::pp,  layouts::pv,  layouts::pt, layouts::hm,
                              layouts::csp, layouts::csv, layouts::cst};

constexpr std::array<std::uint16_t, 1> kAbsent{0x60C1};

using builders::limited;
using builders::spec;

// §7.13 defaults that differ from the generic set.
constexpr std::array kOverrides{
    // §7.13.52: motor drive submode select, UNSIGNED32, rw, RX-PDO, default 00000000h (in the
    // default RxPDO 1600h).
    spec(0x3202, 0, "Motor drive submode select", DT::Unsigned32, A::Rww, true, 0),
    limited(spec(0x6007, 0, "Abort connection option code", DT::Integer16, A::Rw, false, -1), -1,
            3),
    spec(0x605A, 0, "Quick stop option code", DT::Integer16, A::Rw, false, 1),
    limited(spec(0x605B, 0, "Shutdown option code", DT::Integer16, A::Rw, false, 1), 0, 1),
    limited(spec(0x605C, 0, "Disable operation option code", DT::Integer16, A::Rw, false, 1), 0, 1),
    limited(spec(0x605D, 0, "Halt option code", DT::Integer16, A::Rw, false, 1), 1, 2),
    limited(spec(0x605E, 0, "Fault reaction option code", DT::Integer16, A::Rw, false, 2), 1, 2),
    limited(spec(0x6060, 0, "Modes of operation", DT::Integer8, A::Rww, true, 0), -2, 10),
    spec(0x6065, 0, "Following error window", DT::Unsigned32, A::Rw, true, 256),
    spec(0x6066, 0, "Following error time out", DT::Unsigned16, A::Rw, true, 100),
    spec(0x6067, 0, "Position window", DT::Unsigned32, A::Rw, true, 10),
    spec(0x6068, 0, "Position window time", DT::Unsigned16, A::Rw, true, 100),
    spec(0x6072, 0, "Max torque", DT::Unsigned16, A::Rww, true, 0),
    spec(0x607A, 0, "Target position", DT::Integer32, A::Rww, true, 4000),
    spec(0x607F, 0, "Max profile velocity", DT::Unsigned32, A::Rw, true, 30000),
    spec(0x6080, 0, "Max motor speed", DT::Unsigned32, A::Rw, true, 30000),
    spec(0x6081, 0, "Profile velocity", DT::Unsigned32, A::Rww, true, 500),
    spec(0x6083, 0, "Profile acceleration", DT::Unsigned32, A::Rww, true, 500),
    spec(0x6084, 0, "Profile deceleration", DT::Unsigned32, A::Rww, true, 500),
    spec(0x6085, 0, "Quick stop deceleration", DT::Unsigned32, A::Rw, true, 5000),
    spec(0x608F, 1, "Encoder increments", DT::Unsigned32, A::Rw, false, 2000, true),
    spec(0x6098, 0, "Homing method", DT::Integer8, A::Rw, true, 35),
    spec(0x6099, 1, "Speed during search for switch", DT::Unsigned32, A::Rw, true, 50, true),
    spec(0x6099, 2, "Speed during search for zero", DT::Unsigned32, A::Rw, true, 1, true),
    spec(0x609A, 0, "Homing acceleration", DT::Unsigned32, A::Rw, true, 500),
    // 60A8h/60A9h: bits 31..24 exponent, 23..16 unit, (15..8 time unit). Defaults: 0.1 degree,
    // revolutions per minute (§7.2.3).
    spec(0x60A8, 0, "SI unit position", DT::Unsigned32, A::Rw, true, 0xFF410000LL),
    spec(0x60A9, 0, "SI unit velocity", DT::Unsigned32, A::Rw, false, 0x00B44700LL),
    limited(spec(0x60C2, 2, "Interpolation time index", DT::Integer8, A::Rw, false, -3, true), -3,
            -3),
    spec(0x6502, 0, "Supported drive modes", DT::Unsigned32, A::Ro, true, 0x3AF),
};

Profile make_fio() {
    Profile p;
    p.name = "fio";
    p.title = "Kuhnke FIO Drive Control";
    p.identity.device_type = 0x00060192; // servo + stepper
    p.identity.device_type_mask = 0xFFFFFFFF;
    p.identity.vendor_id = 0x0048554B;    // "KUH"
    p.identity.product_code = 0x0002BA67; // 178791
    p.identity.product_code_mask = 0xFFFFFFFF;
    p.max_axes = 1;
    p.supported_modes = 0x3AF;
    p.manufacturer_modes = kManufacturerModes;
    p.homing_methods = kHoming;
    p.quick_stop_options = kQuickStop;
    p.default_quick_stop_option = 1;
    p.faults = kFaults;
    p.error_history_depth = 8; // §7.13.3: 1003h sub-indexes 01h..08h
    p.error_numbers = kErrorNumbers;
    p.layouts = kLayouts;
    p.object_overrides = kOverrides;
    p.documents_defaults = true; // §7.13: every object lists "Default Value"
    p.absent_objects = kAbsent;
    p.quirks.canopen = false;
    p.quirks.remote_bit9_always_set = true;
    p.quirks.si_unit_objects = true;
    return p;
}

} // namespace

const Profile& fio_profile() {
    static const Profile p = make_fio();
    return p;
}

} // namespace codrive::drives
