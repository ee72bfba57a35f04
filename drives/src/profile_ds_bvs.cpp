// SPDX-License-Identifier: Apache-2.0
// DS-BVS/BVM profile: modes incl. manufacturer modes, CAN PDO layouts (no predefined mapping),
// read-only PDO COB-IDs, fixed units and the complete 603Fh/EMCY table (manual §6.2.79, 14 rows).
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

// §6.2.79 (0x603F list): the complete table; also the EMCY codes. Error register bits as printed.
constexpr std::array<FaultRow, 14> kFaults{{
    {0x1000, "", "Generic error", 0x01},
    {0x2310, "", "Over current", 0x02},
    {0x3210, "", "Over voltage", 0x04},
    {0x3220, "", "Under voltage", 0x04},
    {0x4210, "", "Over temperature", 0x08},
    {0x5210, "", "Current detection error", 0x01},
    {0x6100, "", "Internal software error", 0x20},
    {0x7300, "", "Serial encoder communication error", 0x01},
    {0x7305, "", "Encoder disconnection error", 0x01},
    {0x7310, "", "Over speed error", 0x20},
    {0x8400, "", "Maximum velocity error fault", 0x01},
    {0x8611, "", "Following error", 0x20},
    {0xFF01, "", "Hall sensor error", 0x80},
    {0xFF02, "", "Over load error (I2T)", 0x20},
}};

// §3: 6502h = 0x3AF claims VL (bit 1) and PT (bit 3) but 6060h lists neither [spec §8.21].
constexpr std::array<std::int8_t, 2> kRejected{2, 4};
constexpr std::array<ManufacturerMode, 5> kManufacturerModes{{
    {-8, "position regulation (PRM)"},
    {-9, "velocity regulation (VRM)"},
    {-10, "torque regulation (TRM)"},
    {-12, "current regulation (CRM)"},
    {-128, "motion sequence (MSM)"},
}};
// Manual §6.2.140 (0x60E3): sub-indexes 01h..07h hold 17, 18, 23, 27, 37, -3, -4 in this order.
constexpr std::array<std::int8_t, 7> kHoming{17, 18, 23, 27, 37, -3, -4};
constexpr std::array<std::int16_t, 5> kQuickStop{0, 1, 2, 5, 6};
// §6.2.78 (0x6007): 0 no action, 1 reserved, 2 disable voltage, 3 quick stop, 4.. reserved.
constexpr std::array<std::int16_t, 3> kAbortConnection{0, 2, 3};

// No predefined CAN mapping (1600h/1A00h sub 0 = 0): the master writes these in pre-op.
// 6060h is Rx-mappable and 6061h Tx-mappable (§1.8), so the generic layouts fit.
constexpr std::array kLayouts{layouts::pp,  layouts::pv,  layouts::hm,
                              layouts::csp, layouts::csv, layouts::cst};

// Units are fixed (counts, RPM, RPM/s): no factor group; no 60C2h; no 6066h/6087h/607Eh; no IP.
constexpr std::array<std::uint16_t, 9> kAbsent{0x6066, 0x607E, 0x6087, 0x6091, 0x6092,
                                               0x6096, 0x6097, 0x60C1, 0x60C2};

using builders::limited;
using builders::spec;

// §4.3 defaults, ranges and PDO flags that differ from the generic set.
// §6.2.76 0x5002: 1 (10 kbps) and 7 (800 kbps) "Not supported", 0 "None".
constexpr std::array<BitRateCode, 6> kBitRates{
    {{2, 20}, {3, 50}, {4, 125}, {5, 250}, {6, 500}, {8, 1000}}};

constexpr std::array kOverrides{
    // §6.2.74 0x5000 "ID for CAN, UART": 1..127, default 1, Backup YES, effective after restart.
    limited(spec(0x5000, 0, "ID for CAN, UART", DT::Unsigned8, A::Rw, false, 1), 1, 127),
    // §6.2.76 0x5002 "CAN Bitrate": code 0..8 (table), default 5 = 250 kbps, Backup YES.
    limited(spec(0x5002, 0, "CAN Bitrate", DT::Unsigned8, A::Rw, false, 5), 0, 8),
    limited(spec(0x6007, 0, "Abort connection option code", DT::Integer16, A::Rw, false, 0), 0, 3),
    limited(spec(0x605A, 0, "Quick stop option code", DT::Integer16, A::Rw, false, 6), 0, 6),
    limited(spec(0x605B, 0, "Shutdown option code", DT::Integer16, A::Rw, false, 0), 0, 1),
    limited(spec(0x605C, 0, "Disable operation option code", DT::Integer16, A::Rw, false, 1), 0, 1),
    // §6.2.92: 0 disable drive function, 1 slow-down ramp, 2 quick-stop ramp, 3/4 not supported.
    limited(spec(0x605D, 0, "Halt option code", DT::Integer16, A::Rw, false, 1), 0, 2),
    limited(spec(0x605E, 0, "Fault reaction option code", DT::Integer16, A::Rw, false, 0), 0, 0),
    spec(0x6060, 0, "Modes of operation", DT::Integer8, A::Rww, true, 3),
    spec(0x6061, 0, "Modes of operation display", DT::Integer8, A::Ro, true, 3),
    spec(0x6062, 0, "Position demand value", DT::Integer32, A::Ro, false, 0),
    spec(0x6063, 0, "Position actual internal value", DT::Integer32, A::Ro, false, 0),
    limited(spec(0x6065, 0, "Following error window", DT::Unsigned32, A::Rw, false, 100000), 1,
            2147483647),
    spec(0x6067, 0, "Position window", DT::Unsigned32, A::Rw, false, 5),
    spec(0x6068, 0, "Position window time", DT::Unsigned16, A::Rw, false, 10),
    spec(0x606D, 0, "Velocity window", DT::Unsigned32, A::Rw, false, 30),
    spec(0x606E, 0, "Velocity window time", DT::Unsigned16, A::Rw, false, 30),
    limited(spec(0x6072, 0, "Maximum torque", DT::Unsigned16, A::Rw, false, 1000), 1, 2000),
    spec(0x607F, 0, "Max profile velocity", DT::Unsigned32, A::Rw, false, 1000),
    limited(spec(0x6080, 0, "Max motor speed", DT::Unsigned32, A::Rw, false, 3000), 1, 25000),
    spec(0x6081, 0, "Profile velocity", DT::Unsigned32, A::Rw, false, 1000),
    spec(0x6083, 0, "Profile acceleration", DT::Unsigned32, A::Rw, false, 1000),
    spec(0x6084, 0, "Profile deceleration", DT::Unsigned32, A::Rw, false, 1000),
    spec(0x6085, 0, "Quick stop deceleration", DT::Unsigned32, A::Rw, false, 1000),
    limited(spec(0x6086, 0, "Motion profile type", DT::Integer16, A::Rw, false, 1), 0, 1),
    limited(spec(0x608F, 1, "Position encoder increments", DT::Unsigned32, A::Rw, false, 500, true),
            400, 40000),
    limited(spec(0x608F, 2, "Position encoder motor revolutions", DT::Unsigned32, A::Rw, false, 1,
                 true),
            1, 1),
    spec(0x6098, 0, "Homing method", DT::Integer8, A::Rw, false, 17),
    limited(spec(0x6099, 1, "Speed for switch search", DT::Unsigned32, A::Rw, false, 100, true), 1,
            25000),
    limited(spec(0x6099, 2, "Speed for zero search", DT::Unsigned32, A::Rw, false, 10, true), 1,
            25000),
    // §6.2.133: range 1..4294967295.
    limited(spec(0x609A, 0, "Homing acceleration", DT::Unsigned32, A::Rw, false, 10000), 1,
            4294967295LL),
    spec(0x60F4, 0, "Following error actual value", DT::Integer32, A::Ro, false, 0),
    spec(0x6502, 0, "Supported drive modes", DT::Unsigned32, A::Const, false, 0x3AF),
};

Profile make_ds_bvs() {
    Profile p;
    p.name = "ds-bvs";
    p.title = "DS-BVS/BVM servo drive";
    p.identity.device_type = 0x00020192;
    p.identity.device_type_mask = 0xFFFFFFFF;
    p.identity.device_name = "DS-BV"; // vendor id not documented: match 1008h
    p.max_axes = 1;
    p.supported_modes = 0x3AF;
    p.rejected_modes = kRejected;
    p.manufacturer_modes = kManufacturerModes;
    p.homing_methods = kHoming;
    p.quick_stop_options = kQuickStop;
    p.default_quick_stop_option = 6;
    p.abort_connection_options = kAbortConnection;
    p.default_mode = 3;
    p.faults = kFaults;
    p.error_history_index = 0x4080; // §6.2.44; the §6.1.3 entries overview lists no 1003h
    p.error_history_depth = 10;     // §6.2.44: 4080h error codes 01h..0Ah
    p.layouts = kLayouts;
    // The profile's own objects, then those of the manual's tables (objects_ds_bvs.cpp).
    static const std::vector<ObjectSpec> objects = joined(kOverrides, ds_bvs_table_objects());
    p.object_overrides = objects;
    p.documents_defaults = true; // chapter 6.2: every object lists "Default Value"
    p.absent_objects = kAbsent;
    // §6.2.14-§6.2.17: every PDO mapping object says "Backup NO": 1010h does not store them.
    p.quirks.pdo_maps_volatile = true;
    // §6.2.7 (0x1011): restore only in NMT pre-operational and device state power disabled.
    p.quirks.restore_needs_preop_power_disabled = true;
    p.quirks.pdo_cob_ids_read_only = true;
    p.quirks.empty_default_pdo_maps = true;
    p.quirks.max_pdo_entries = 10;
    p.quirks.switch_on_needs_bit3_clear = true;
    p.quirks.remote_bit9_always_set = true;
    p.quirks.interpolation_period_object = false;
    p.quirks.error_behaviour_1029 = true;
    p.commissioning.node_id_object = 0x5000;  // §6.2.74
    p.commissioning.bit_rate_object = 0x5002; // §6.2.76
    p.commissioning.bit_rates = kBitRates;
    return p;
}

} // namespace

const Profile& ds_bvs_profile() {
    static const Profile p = make_ds_bvs();
    return p;
}

} // namespace codrive::drives
