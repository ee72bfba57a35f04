// SPDX-License-Identifier: Apache-2.0
// Kuhnke FIO Drive Control profile (EtherCAT only): identity, modes, SI user units (60A8h/60A9h),
// the error-number table (1003h bits 31..24, 30 rows) and the error-code table (18 rows).
#include "layouts.hpp"
#include "object_spec_builders.hpp"
#include "table_objects.hpp"

#include <codrive/drives/profile.hpp>

#include <array>
#include <vector>

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

// §7.12.4.3-§7.12.4.13: the objects of each 1010h/1011h category. §7.12.4.4 lists 6040h
// (controlword) under "application", but §7.12.4.2 says control words are never saved: left out.
constexpr std::array<std::uint16_t, 11> kCommObjects{0x1600, 0x1601, 0x1602, 0x1603, 0x1A00, 0x1A01,
                                                     0x1A02, 0x1A03, 0x1C12, 0x1C13, 0x2102};
constexpr std::array<std::uint16_t, 86> kAppObjects{
    0x2034, 0x2035, 0x2036, 0x2037, 0x2038, 0x203A, 0x203D, 0x203E, 0x203F, 0x2057, 0x2058,
    0x205B, 0x2084, 0x2290, 0x2291, 0x2800, 0x3210, 0x3212, 0x3240, 0x3242, 0x3243, 0x3250,
    0x3252, 0x3700, 0x3701, 0x4013, 0x6042, 0x6046, 0x6048, 0x6049, 0x604A, 0x604C, 0x605A,
    0x605B, 0x605C, 0x605D, 0x605E, 0x6060, 0x6065, 0x6066, 0x6067, 0x6068, 0x606D, 0x606E,
    0x6071, 0x6072, 0x607A, 0x607B, 0x607C, 0x607D, 0x607E, 0x607F, 0x6081, 0x6082, 0x6083,
    0x6084, 0x6085, 0x6086, 0x6087, 0x6091, 0x6092, 0x6096, 0x6097, 0x6098, 0x6099, 0x609A,
    0x60A2, 0x60A4, 0x60A8, 0x60A9, 0x60B0, 0x60B1, 0x60B2, 0x60C1, 0x60C2, 0x60C4, 0x60C5,
    0x60C6, 0x60E8, 0x60E9, 0x60ED, 0x60EE, 0x60F2, 0x60F8, 0x60FE, 0x60FF};
constexpr std::array<std::uint16_t, 1> kCustomerObjects{0x2701};
constexpr std::array<std::uint16_t, 4> kDriveObjects{0x3202, 0x3203, 0x6073, 0x6080};
constexpr std::array<std::uint16_t, 11> kTuningObjects{
    0x2030, 0x2031, 0x203B, 0x2059, 0x3390, 0x33A0, 0x6075, 0x608F, 0x6090, 0x60E6, 0x60EB};
constexpr std::array<std::uint16_t, 3> kEthernetObjects{0x2010, 0x2011, 0x2012};
// §7.12.4.15 (sub-indexes 01h..06h and 0Ch save; §7.13.7 lists 07h..0Bh and 0Dh without a
// category: they are in 1010h/1011h but hold no objects here).
constexpr std::array<StoreCategory, 7> kStoreCategories{{
    {0x01, "all", "all categories", {}},
    {0x02, "comm", "communication objects", kCommObjects},
    {0x03, "app", "application objects", kAppObjects},
    {0x04, "customer", "customer objects", kCustomerObjects},
    {0x05, "drive", "drive objects", kDriveObjects},
    {0x06, "tuning", "tuning objects", kTuningObjects},
    {0x0C, "ethernet", "Ethernet configuration", kEthernetObjects},
}};

// §7.13.11-§7.13.18: the default PDO maps (mapping entry = index << 16 | sub << 8 | bits).
// 1603h "Output Control" repeats 1602h's 60420010h in the manual: kept as written.
constexpr std::array<std::uint32_t, 4> kRx1600{0x60400010, 0x607A0020, 0x32020020, 0x60600008};
constexpr std::array<std::uint32_t, 2> kRx1601{0x607A0020, 0x60810020};
constexpr std::array<std::uint32_t, 1> kRx1602{0x60420010};
constexpr std::array<std::uint32_t, 1> kRx1603{0x60420010};
constexpr std::array<std::uint32_t, 3> kTx1A00{0x60410010, 0x60640020, 0x60610008};
constexpr std::array<std::uint32_t, 1> kTx1A01{0x60640020};
constexpr std::array<std::uint32_t, 1> kTx1A02{0x60440010};
constexpr std::array<std::uint32_t, 3> kTx1A03{0x60FD0020, 0x64020120, 0x64020220};
constexpr std::array<DefaultPdoMap, 8> kDefaultMaps{{
    {0x1600, kRx1600},
    {0x1601, kRx1601},
    {0x1602, kRx1602},
    {0x1603, kRx1603},
    {0x1A00, kTx1A00},
    {0x1A01, kTx1A01},
    {0x1A02, kTx1A02},
    {0x1A03, kTx1A03},
}};

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
    // The profile's own objects, then those of the manual's tables (objects_fio.cpp).
    static const std::vector<ObjectSpec> objects = joined(kOverrides, fio_table_objects());
    p.object_overrides = objects;
    p.documents_defaults = true; // §7.13: every object lists "Default Value"
    p.absent_objects = kAbsent;
    p.quirks.canopen = false;
    p.quirks.remote_bit9_always_set = true;
    p.quirks.si_unit_objects = true;
    p.default_pdo_maps = kDefaultMaps;
    p.quirks.csp_bit8_synchronised = true;        // §7.8.1.4
    p.quirks.statusword_bit15_closed_loop = true; // §7.13 6041h CLA
    p.persistence.categories = kStoreCategories;
    p.persistence.highest_subindex = 0x0D;    // §7.13.7/§7.13.8: sub 0 = 0Dh
    p.persistence.store_read_before_save = 0; // §7.13.7 default 0; "1" once saved (§7.12.4.15)
    p.persistence.restore_restarts = true;    // §7.12.4.16: restarts after clearing
    return p;
}

} // namespace

const Profile& fio_profile() {
    static const Profile p = make_fio();
    return p;
}

} // namespace codrive::drives
