// SPDX-License-Identifier: Apache-2.0
// Kollmorgen AKD2G profile: identity, dual-axis offsets, modes, CAN PDO layouts, quirks and the
// complete EMCY ↔ fault/warning table (manual §4.3.1, 185 rows: 123 faults, 62 warnings).
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

// AKD2G manual §4.3.1 "EMCY error codes" (one EMCY per fault and per warning; 0000h when all
// are cleared). Order as printed.
constexpr std::array<FaultRow, 185> kFaults{{
    {0x3110, "F2015", "Bus over voltage FPGA"},
    {0x3120, "F2000", "Vbus read is out of thresholds"},
    {0x3130, "F2008", "Bus capacitor overloaded"},
    {0x3180, "W2008", "Bus capacitor overloaded"},
    {0x3181, "F2014", "AC input phase loss"},
    {0x3182, "F2016", "Gate supply under voltage"},
    {0x3183, "W1000", "Fan stalled"},
    {0x3190, "F1005", "Unrecognized FPGA fault"},
    {0x3191, "F1006", "FPGA cyclic read fault"},
    {0x3210, "F2006", "Bus over voltage"},
    {0x3220, "F2007", "Bus under voltage"},
    {0x3280, "W2007", "Bus under voltage"},
    {0x3281, "W2010", "Regen energy critical"},
    {0x3282, "F2013", "Regen short circuit"},
    {0x3283, "W2006", "Bus over voltage"},
    {0x37AD, "F4030", "SFA model does not support feedback type"},
    {0x4210, "F2500", "Control over temperature sensor"},
    {0x4310, "F2501", "Power over temperature sensor"},
    {0x4382, "F1001", "Power board type mismatch detected"},
    {0x4390, "W2500", "Control Over Temp Sensor"},
    {0x4391, "W2501", "Power Over Temp Sensor"},
    {0x4394, "W2502", "Control Under Temp Sensor"},
    {0x4395, "W2503", "Power Under Temp Sensor"},
    {0x4398, "F2502", "Control under temperature sensor"},
    {0x4399, "F2503", "Power under temperature sensor"},
    {0x5580, "F1100", "NV Memory Data (might occur when downloading firmware)"},
    {0x5588, "F1101", "Flash directory error"},
    {0x5590, "F1102", "Identity read failed"},
    {0x5591, "F1103", "Invalid MAC Address"},
    {0x55A1, "F1104", "Power board factory settings file read failed"},
    {0x55A2, "F1105", "Power board updateable settings file read failed"},
    {0x55B0, "F1106", "Failure reading Control Board FPGA EDS file"},
    {0x55B1, "F1107", "Power Board Resident FPGA not valid"},
    {0x55B2, "F1108", "Power Board Operational FPGA not valid"},
    {0x55B3, "F1109", "Failure reading Power Board FPGA EDS"},
    {0x55C4, "F1002", "Power Board Communication fault"},
    {0x55C5, "F1003", "Power Board FPGA not configured"},
    {0x6080, "F3000", "Issued command timed out"},
    {0x6380, "F5005", "Drive motor parameters setup incomplete"},
    {0x6381, "F3001", "Failed to default parameters"},
    {0x7180, "F5000", "Motor overheated"},
    {0x7184, "F5003", "Brake applied when it should be released"},
    {0x7186, "W5000", "Motor Temperature high"},
    {0x7187, "F2011", "Voltage exceeds motors rating"},
    {0x7188, "F2009", "Regen near capacity, could not prevent over voltage"},
    {0x7189, "F5004", "Brake released when it should be applied"},
    {0x718A, "F2018", "Broken Wire Connection to Motor"},
    {0x7190, "F5001", "Brake 1 current out of range"},
    {0x7191, "W5001", "Brake override active"},
    {0x7192, "F5002", "Brake 2 current out of range"},
    {0x7193, "F5006", "Temperature sensor detected open circuit"},
    {0x7194, "W5007", "Brake override active but no brake configured"},
    {0x7380, "F4100", "Feedback: Parity fault"},
    {0x7381, "F4101", "Feedback: Overrun fault"},
    {0x7382, "F4102", "Feedback: Framing fault"},
    {0x7383, "F4103", "Feedback: CRC fault"},
    {0x7384, "F4104", "Feedback: Communication Timeout fault"},
    {0x7385, "F4105", "Feedback: Initialization sequence fault"},
    {0x7386, "F4106", "Feedback: Temperature fault"},
    {0x7387, "F4107", "Feedback: Battery fault"},
    {0x7388, "F4108", "Feedback: Sensor fault"},
    {0x7389, "F4109", "Feedback: Device-unique fault 0"},
    {0x738A, "F4110", "Feedback: Device-unique fault 1"},
    {0x738B, "F4111", "Feedback: Analog Signal fault"},
    {0x738C, "F4112", "Feedback: Broken Wire fault"},
    {0x738D, "F4113", "Feedback: Power Supply fault"},
    {0x738E, "F4114", "Feedback: Illegal Hall state (111, 000)"},
    {0x738F, "F4115", "Failed to set feedback type"},
    {0x7392, "F4116", "Failed to read motor parameters from feedback device"},
    {0x7393, "F4117", "SFA communication fault"},
    {0x7394, "F4118", "SFA over current"},
    {0x7395, "F4119", "SFA under voltage"},
    {0x7396, "F4120", "Feedback: Safety fault"},
    {0x7397, "F3004", "Operation in Position Mode with Halls Only feedback not allowed"},
    {0x7398, "F4121", "Feedback: Watchdog fault"},
    {0x7399, "F4122", "Unrecognized feedback fault"},
    {0x739A, "F4123", "SFA Resident FPGA not valid"},
    {0x739B, "F4124", "SFA Operational FPGA not valid"},
    {0x739C, "F4125", "SFA FPGA file read failed"},
    {0x739D, "F4126", "SFA Factory file read failed"},
    {0x739E, "W4100", "Feedback parity"},
    {0x739F, "W4101", "Feedback overrun"},
    {0x73A0, "W4102", "Feedback framing"},
    {0x73A1, "W4103", "Feedback CRC"},
    {0x73A2, "W4104", "Feedback communication timeout"},
    {0x73A3, "W4105", "Feedback initialization sequence"},
    {0x73A4, "W4106", "Feedback temperature"},
    {0x73A5, "W4107", "Feedback battery"},
    {0x73A6, "W4108", "Feedback sensor"},
    {0x73A7, "W4109", "Feedback device-unique warning 0"},
    {0x73A8, "W4110", "Feedback device-unique warning 1"},
    {0x73A9, "W4111", "Gearing feedback source fault"},
    {0x73C0, "F5500", "Wake and Shake - Insufficient movement"},
    {0x73C1, "F5501", "Wake and Shake - Excess movement"},
    {0x73C2, "F5502", "Wake and Shake - Fine-Coarse delta too large"},
    {0x73C3, "F5503", "Wake and Shake - Over speed"},
    {0x73C4, "F5504", "Wake and Shake - Loop angle delta too large"},
    {0x73C5, "F5505", "Wake and Shake - Commutation not initialized"},
    {0x73C6, "F5506", "Wake and Shake - Motor U phase missing"},
    {0x73C7, "F5507", "Wake and Shake - Motor V phase missing"},
    {0x73C8, "F5508", "Wake and Shake - Motor W phase missing"},
    {0x73C9, "W5500", "Wake & Shake configured or active"},
    {0x73D0, "F5509", "Wake and Shake - Validating Positive Movement Failed"},
    {0x73D1, "F5510", "Wake and Shake - Validating Negative Movement Failed"},
    {0x73D2, "F5511", "Wake and Shake - Validating Comm. angle timed out"},
    {0x73D3, "F5512", "Wake and Shake - Validating Comm. angle moved too far - Bad Comm Angle"},
    {0x73D4, "F5513", "Wake and Shake - Validating Comm. angle required more than MOTOR.ICONT"},
    {0x73D5, "F6002",
     "Invalid commutation detected - motor accelerating in the wrong direction. Motor phase may be "
     "incorrect"},
    {0x8130, "F7002", "Fieldbus Heartbeat lost"},
    {0x8180, "W7000", "Fieldbus Error Passive"},
    {0x8311, "F2017", "Motor Foldback"},
    {0x8331, "F2001", "Drive Foldback"},
    {0x8380, "W2001", "Drive foldback imminent! Reduce Load"},
    {0x8381, "W2002", "Motor foldback imminent! Reduce Load"},
    {0x8382, "W2003", "Motor I2t load! Reduce load"},
    {0x8383, "W6008",
     "Using derivative of position when using sensorless feedback type in position mode"},
    {0x8384, "W6004", "Zero velocity when using induction sensorless feedback type in torque mode"},
    {0x8385, "W6027", "Current Command Saturated"},
    {0x8386, "F5514", "Wake and Shake - Limit Switch Hit"},
    {0x8480, "F6000", "Over speed"},
    {0x8481, "F6005", "Emergency timeout occurred"},
    {0x8582, "W6006", "Positive Limit Switch triggered"},
    {0x8583, "W6007", "Negative Limit Switch triggered"},
    {0x8611, "F6001", "Following error magnitude fault"},
    {0x8685, "F6003", "Instability during autotune"},
    {0x8688, "W6000", "Velocity Limit Violation, Exceeding Max Limit"},
    {0x8689, "W6009", "Following Motion Failed; Check Motion Parameters"},
    {0x868A, "W6010", "Target Position crossed due to Stop command"},
    {0x86A0, "W6011", "Homing Index pulse not found"},
    {0x86A1, "W6012", "Home switch not found"},
    {0x86A3, "W6014", "Motion Task Activation Failed"},
    {0x86A4, "W6015", "Homing Failed"},
    {0x86A5, "F6004", "Target position was overshoot due to invalid motion task activation"},
    {0x86A8, "W6017", "Motion task target position is out of modulo-range"},
    {0x86A9, "W6018", "Motion task target position is out of software-limits"},
    {0x86AA, "W6019", "Invalid bit-combination in the motion-task control-word"},
    {0x86AB, "W6020", "1:1 profile can not be triggered on-the-fly"},
    {0x86AC, "W6021", "Customer profile table is not initialized"},
    {0x86AD, "W6022", "Motion task activation is currently pending"},
    {0x86AE, "W6002", "Homing is needed"},
    {0x86AF, "W6023", "Homing maximum distance exceeded"},
    {0x8780, "F7001", "Fieldbus Sync frames lost"},
    {0x8781, "W7001", "PLL unlocked"},
    {0x8782, "F7003", "PLL failed to acquire lock"},
    {0x8783, "F7004", "PLL lost lock"},
    {0x8784, "F7005", "Fieldbus cyclic setpoints missing"},
    {0x8785, "F7006", "Only on CAN drives: CAN hardware initialization failed"},
    {0x8AF0, "W6025", "Homing and feedback mismatch"},
    {0xFF00, "W2011", "No Power on IO 24V Rail"},
    {0xFF01, "F7000", "Fieldbus Communication lost"},
    {0xFF02, "F2004", "Iu current offset limit exceeded"},
    {0xFF03, "F2005", "Iv current offset limit exceeded"},
    {0xFF04, "F2010", "Regen over power"},
    {0xFF05, "F3100", "MechaWare Model failed to connect Analog Input, fix model"},
    {0xFF06, "F3101", "MechaWare Model failed to connect Analog Output, fix model"},
    {0xFF07, "F2002", "Output over current"},
    {0xFF08, "F2003", "Current sensor short circuit"},
    {0xFF09, "F3002", "Assert check failed"},
    {0xFF0A, "F2012", "Power stage fault"},
    {0xFF0B, "F9000", "Safe torque off"},
    {0xFF0C, "W9000", "Safe torque off"},
    {0xFF0D, "F1000", "Firmware and FPGA versions are not compatible"},
    {0xFF0E, "W6001", "Exceeding following error magnitude warning level"},
    {0xFF10, "W6003", "OPMODE incompatible with CMDSOURCE"},
    {0xFF11, "F1004", "Failed to initialize the system"},
    {0xFF12, "F5100", "IL.FBSOURCE has unidentified feedback selected"},
    {0xFF13, "F5101", "VL.FBSOURCE has unidentified feedback selected"},
    {0xFF14, "F5102", "PL.FBSOURCE has unidentified feedback selected"},
    {0xFF15, "F1007", "A Factory MechaWare model failed to load"},
    {0xFF16, "F1008", "A User MechaWare model failed to load"},
    {0xFF17, "W6028", "Gear feedback source is invalid"},
    {0xFF18, "F6028", "Gearing feedback source is invalid"},
    {0xFF19, "F6006", "Current home mode requires HOME.IPEAK to be set"},
    {0xFF1A, "W6026", "Current homing mode requires HOME.IPEAK to be set by user"},
    {0xFF50, "F9002", "SMM Communication Failed"},
    {0xFF51, "F9003", "Incorrect safety card detected"},
    {0xFF52, "F9004", "Safe torque off pulse and standard lines don't match"},
    {0xFF53, "F9005", "Simultaneity Fault: Safe torque off lines don't match each other"},
    {0xFF54, "W9011", "SMM I/O failure detected"},
    {0xFF55, "F9006", "SMM in failed state"},
    {0xFF56, "W9008", "Brake Test Time Overflow"},
    {0xFF57, "W9009", "SMM Over Temperature"},
    {0xFF58, "W9010", "SMM State Not Operational"},
    {0xFF59, "W9007", "Safe brake parameters inconsistent"},
    {0xFF5A, "F9007", "Safe brake parameters inconsistent"},
}};

// Modes (§5.5): 6502h = 0xAD (PP, PV, PT, HM, CSP). CSV (9) is accepted in 6060h although
// 6502h bit 8 says it is not supported [AMB-13]; analog modes -1/-2 are manufacturer modes.
constexpr std::array<std::int8_t, 1> kExtraModes{9};
constexpr std::array<ManufacturerMode, 2> kManufacturerModes{{
    {-1, "analog torque"},
    {-2, "analog velocity"},
}};
// §5.7 supported 6098h methods.
constexpr std::array<std::int8_t, 15> kHoming{-4, -3, -2, -1, 1,  2,  8, 12,
                                              17, 18, 24, 28, 33, 34, 35};
// §5.4: 605Ah values 1, 2 (default), 5, 6.
constexpr std::array<std::int16_t, 4> kQuickStop{1, 2, 5, 6};

// CAN layouts: the EtherCAT default 1A00h (6041h + 6064h + 60F4h = 10 bytes) does not fit a CAN
// frame [AMB-10]; codrive writes these 8-byte maps on every boot because the AKD2G does not
// store them (§5.2.11). Axis 1 uses RPDO1/TPDO1, axis 2 RPDO2/TPDO2 (first_pdo + axis - 1).
constexpr std::array kLayouts{layouts::pp, layouts::pv,  layouts::pt,
                              layouts::hm, layouts::csp, layouts::csv};

// §5.6: objects the AKD2G does not have (position window → SETTLE.P, quick-stop decel →
// CS.DEC, no 605Bh..605Eh, no 608Fh (fixed 2^32 counts/rev), no IP data).
constexpr std::array<std::uint16_t, 14> kAbsent{0x6007, 0x603F, 0x605B, 0x605C, 0x605D,
                                                0x605E, 0x6062, 0x6067, 0x6068, 0x607E,
                                                0x607F, 0x6085, 0x6086, 0x608F};

using builders::limited;
using builders::spec;

// §5.6 types/defaults that differ from the generic set.
constexpr std::array kOverrides{
    limited(spec(0x605A, 0, "Quick stop option code", DT::Integer16, A::Rw, false, 2), 1, 6),
    spec(0x6072, 0, "Max torque", DT::Unsigned16, A::Rww, true, 1000),
    spec(0x6081, 0, "Profile velocity", DT::Unsigned32, A::Rw, true, 0),
    spec(0x6083, 0, "Profile acceleration", DT::Unsigned32, A::Rw, true, 0),
    spec(0x6084, 0, "Profile deceleration", DT::Unsigned32, A::Rw, true, 0),
    spec(0x606D, 0, "Velocity window", DT::Unsigned16, A::Rw, true, 0),
    spec(0x606E, 0, "Velocity window time", DT::Unsigned16, A::Rw, true, 0),
    spec(0x6092, 1, "Feed", DT::Unsigned32, A::Rw, false, 65536, true), // 2^16 counts/rev
    spec(0x6502, 0, "Supported drive modes", DT::Unsigned32, A::Ro, false, 0xAD),
    spec(0x60E0, 0, "Positive torque limit", DT::Unsigned16, A::Rw, true, 0),
    spec(0x60E1, 0, "Negative torque limit", DT::Unsigned16, A::Rw, true, 0),
    spec(0x60FC, 0, "Position demand internal value", DT::Integer32, A::Ro, true, 0),
    // §5.3.84 AXIS#.FAULT1..10 (axis 2 at 5104h): the faults of one axis.
    spec(0x5004, 1, "AXIS#.FAULT1", DT::Unsigned16, A::Ro, false, 0, true),
    spec(0x5004, 2, "AXIS#.FAULT2", DT::Unsigned16, A::Ro, false, 0, true),
    spec(0x5004, 3, "AXIS#.FAULT3", DT::Unsigned16, A::Ro, false, 0, true),
    spec(0x5004, 4, "AXIS#.FAULT4", DT::Unsigned16, A::Ro, false, 0, true),
    spec(0x5004, 5, "AXIS#.FAULT5", DT::Unsigned16, A::Ro, false, 0, true),
    spec(0x5004, 6, "AXIS#.FAULT6", DT::Unsigned16, A::Ro, false, 0, true),
    spec(0x5004, 7, "AXIS#.FAULT7", DT::Unsigned16, A::Ro, false, 0, true),
    spec(0x5004, 8, "AXIS#.FAULT8", DT::Unsigned16, A::Ro, false, 0, true),
    spec(0x5004, 9, "AXIS#.FAULT9", DT::Unsigned16, A::Ro, false, 0, true),
    spec(0x5004, 10, "AXIS#.FAULT10", DT::Unsigned16, A::Ro, false, 0, true),
    // §4.1.5 touch probes, object pages §5.4.36-§5.4.41 (all PDO mappable; positions in the
    // units of 6064h).
    spec(0x60B8, 0, "Touch probe function", DT::Unsigned16, A::Rww, true, 0),
    spec(0x60B9, 0, "Touch probe status", DT::Unsigned16, A::Ro, true, 0),
    spec(0x60BA, 0, "Touch probe 1 position positive value", DT::Integer32, A::Ro, true, 0),
    spec(0x60BB, 0, "Touch probe 1 position negative value", DT::Integer32, A::Ro, true, 0),
    spec(0x60BC, 0, "Touch probe 2 position positive value", DT::Integer32, A::Ro, true, 0),
    spec(0x60BD, 0, "Touch probe 2 position negative value", DT::Integer32, A::Ro, true, 0),
};

Profile make_akd2g() {
    Profile p;
    p.name = "akd2g";
    p.title = "Kollmorgen AKD2G";
    p.identity.device_type = 0x00020192; // CAN; 0x000A0192 with FSoE on CoE (§5.2.1)
    p.identity.device_type_mask = 0x0000FFFF;
    p.identity.vendor_id = 0x0000006A;
    p.identity.product_code = 0x11210100;      // dual axis, SIL2 STO (§5.2.16, derived example)
    p.identity.product_code_mask = 0xF0000000; // family 1 = AKD2G standalone
    p.identity.axes_mask = 0x00F00000;
    p.identity.axes_shift = 20;
    p.axis_offset = 0x800;
    p.manufacturer_axis_offset = 0x100;
    p.axis_fault_list = 0x5004; // §5.3.84 AXIS#.FAULT1..10 (5104h for axis 2)
    p.axis_fault_slots = 10;
    p.max_axes = 2;
    p.supported_modes = 0xAD;
    p.extra_modes = kExtraModes;
    p.manufacturer_modes = kManufacturerModes;
    p.homing_methods = kHoming;
    p.quick_stop_options = kQuickStop;
    p.default_quick_stop_option = 2;
    p.faults = kFaults;
    p.error_history_depth = 10; // §5.2.3: 1003h holds at most 10 entries
    p.layouts = kLayouts;
    // The profile's own objects, then those of the manual's tables (objects_akd2g.cpp).
    static const std::vector<ObjectSpec> objects = joined(kOverrides, akd2g_table_objects());
    p.object_overrides = objects;
    p.absent_objects = kAbsent;
    p.fault_code_in_1003 = true; // §5.2.3: no 603Fh; 1003h:01 = the last EMCY's first 4 bytes
    p.quirks.pdo_maps_volatile = true;
    // §5.2.31: "Dynamic mapping allows the content of the PDO to be changed while the drive is
    // running": mapping writes are not limited to NMT pre-operational.
    p.quirks.pdo_mapping_preop_only = false;
    p.quirks.sto_in_statusword_bit8 = true;
    p.quirks.voltage_bit4_is_dc_bus = true;
    p.quirks.has_shutdown_option_codes = false;
    p.quirks.halt_ignored_in_csp = true;
    p.quirks.fixed_encoder_increments = 0;       // 2^32: see units (does not fit U32)
    p.quirks.internal_counts_per_rev = 1U << 12; // §5.4.6, PSCALE 20
    p.quirks.heartbeat_consumer_sub0_type = DataType::Unsigned32; // §5.2.14 table
    return p;
}

} // namespace

const Profile& akd2g_profile() {
    static const Profile p = make_akd2g();
    return p;
}

} // namespace codrive::drives
