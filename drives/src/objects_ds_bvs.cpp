// SPDX-License-Identifier: Apache-2.0
// DS-BVS/BVM: the objects of the manual's object tables (003_*.txt §6.2) that the profile has no
// behaviour for, as the manual gives them (type, access, PDO mapping, default, range). The
// simulators install them from here; the conformance suite checks them against the manual.
#include "table_objects.hpp"

#include "object_spec_builders.hpp"

#include <array>
#include <vector>

namespace codrive::drives {
namespace {

using DT = DataType;
using A = Access;
using builders::limited;
using builders::spec;

// Names: where the table's Name cell is wrapped in the manual text ("Averaged Current (Moving
// Avera" / "aged 10step)"), the name is the section heading's (§6.2.52 "Averaged Current (Moving
// Averaged 10step)"): a master shows it from the SDO information.
// clang-format off
constexpr std::array kObjects{
    limited(spec(0x4000, 0, "Resistance", DT::Unsigned16, A::Rw, false, 0x1F4), 1, 65535), // §6.2.33, line 2908
    spec(0x4001, 0, "Inductance (Q-Axis Inductance)", DT::Unsigned32, A::Rw, false, 0x1F4), // §6.2.34, line 2926
    spec(0x4002, 0, "D-Axis Inductance", DT::Unsigned32, A::Rw, false, 0x1F4), // §6.2.35, line 2940
    spec(0x4003, 0, "Torque Constant", DT::Unsigned32, A::Rw, false, 0x124F8), // §6.2.36, line 2956
    spec(0x4004, 0, "Back-EMF Constant", DT::Unsigned32, A::Rw, false, 0x124F8), // §6.2.36, line 2970
    spec(0x4005, 0, "System Inertial", DT::Unsigned32, A::Rw, false, 0x186A0), // §6.2.38, line 2986
    spec(0x4006, 0, "Coulomb (Static) Friction", DT::Unsigned32, A::Rw, false, 0), // §6.2.39, line 2999
    spec(0x4007, 0, "Viscos Friction", DT::Unsigned32, A::Rw, false, 0), // §6.2.39, line 3013
    spec(0x4008, 0, "Position Sensor Type", DT::Unsigned8, A::Rw, false, 0), // §6.2.41, line 3031
    spec(0x4009, 0, "Position Sensor Polarity", DT::Unsigned8, A::Rw, false, 0), // §6.2.42, line 3051
    spec(0x400A, 0, "Hall Sensor Pole Pair", DT::Unsigned8, A::Rw, false, 0), // §6.2.43, line 3074
    spec(0x4100, 0, "Motor Phase", DT::Unsigned16, A::Rw, false, 0), // §6.2.45, line 3137
    limited(spec(0x4101, 0, "Electric Angel Offset", DT::Unsigned16, A::Rw, false, 0), 0, 3600), // §6.2.46, line 3159
    limited(spec(0x4107, 0, "Hall Sensor Pattern", DT::Unsigned8, A::Ro, false, 0), 1, 6), // §6.2.46, line 3173
    limited(spec(0x4205, 1, "D-Axis Current Cotroller P-Gain", DT::Unsigned32, A::Rw, false, 0x3E8, true), 0, 100000000), // §6.2.48.1, line 3202
    limited(spec(0x4205, 4, "Q-Axis Current Cotroller P-Gain", DT::Unsigned32, A::Rw, false, 0x3E8, true), 0, 100000000), // §6.2.48.3, line 3232
    limited(spec(0x4205, 5, "Q-Axis Current Cotroller I-Gain", DT::Unsigned32, A::Rw, false, 0x3E8, true), 0, 100000000), // §6.2.48.4, line 3246
    limited(spec(0x4206, 0, "Current Cotroller Bandwidth", DT::Unsigned16, A::Rw, false, 0x7D0), 1000, 10000), // §6.2.49, line 3262
    spec(0x4207, 0, "Target Current", DT::Integer32, A::Rw, true, 0), // §6.2.50, line 3276
    spec(0x4208, 0, "Actual Current", DT::Integer32, A::Ro, true, 0), // §6.2.51, line 3292
    spec(0x4209, 0, "Averaged Current (Moving Averaged 10step)", DT::Integer32, A::Ro, false, 0), // §6.2.52, line 3310
    limited(spec(0x4300, 1, "Velocity Controller P-Gain", DT::Unsigned32, A::Rw, false, 0x64, true), 0, 100000000), // §6.2.53.1, line 3335
    limited(spec(0x4300, 2, "Velocity Controller I-Gain", DT::Unsigned32, A::Rw, false, 0x64, true), 0, 1000000), // §6.2.53.2, line 3353
    limited(spec(0x4300, 4, "Velocity Feed-Forward Gain", DT::Unsigned8, A::Rw, false, 0x32, true), 0, 250), // §6.2.53.3, line 3369
    limited(spec(0x4300, 5, "Acceleration Feed-Forward Gain", DT::Unsigned8, A::Rw, false, 0x32, true), 0, 250), // §6.2.53.4, line 3387
    spec(0x4301, 0, "Velocity Controller Bandwidth", DT::Unsigned16, A::Rw, false, 0xC8), // §6.2.54, line 3401
    spec(0x4302, 2, "Max Current", DT::Unsigned32, A::Ro, false, 2, true), // §6.2.55.2, line 3448
    spec(0x4302, 3, "Over Load Duration Time", DT::Unsigned16, A::Rw, false, 0x3E8, true), // §6.2.55.3, line 3474
    spec(0x4302, 4, "I2T Energy Setpoint Value", DT::Unsigned32, A::Ro, false, 0, true), // §6.2.55.4, line 3488
    spec(0x4302, 5, "I2T Energy Actual Value", DT::Unsigned32, A::Ro, false, 0, true), // §6.2.55.4, line 3502
    limited(spec(0x4310, 0, "Velocity kalman Filter Covariance", DT::Unsigned32, A::Rw, false, 0x1F4), 1, 1000), // §6.2.56, line 3518
    limited(spec(0x4311, 0, "External Load Torque Feed-Forward Gain", DT::Unsigned8, A::Rw, false, 0x32), 0, 100), // §6.2.57, line 3532
    limited(spec(0x4312, 0, "External Load Torque Deadzone", DT::Unsigned8, A::Rw, false, 5), 0, 100), // §6.2.58, line 3548
    spec(0x4313, 0, "Load Torque", DT::Integer32, A::Ro, false, 0), // §6.2.59, line 3562
    limited(spec(0x4314, 0, "Load Torque Threshold", DT::Unsigned32, A::Rw, false, 0), 0, 2147483647), // §6.2.60, line 3576
    spec(0x4321, 0, "Velocity Auto-Tuning Acceleration", DT::Unsigned32, A::Rw, false, 0x3E8), // §6.2.61, line 3594
    spec(0x4322, 0, "Velocity Auto-Tuning Velocity", DT::Unsigned32, A::Rw, false, 0x1F4), // §6.2.62, line 3610
    spec(0x4323, 0, "Velocity Auto-Tuning Position", DT::Integer32, A::Rw, false, 500), // §6.2.63, line 3628
    limited(spec(0x4400, 1, "Position Controller P-Gain", DT::Integer32, A::Rw, false, 30000, true), 0, 100000000), // §6.2.64.1, line 3653
    limited(spec(0x4400, 2, "Position Controller I-Gain", DT::Integer32, A::Rw, false, 0, true), 0, 100000000), // §6.2.64.2, line 3671
    limited(spec(0x4400, 3, "Position Controller D-Gain", DT::Integer32, A::Rw, false, 0, true), 0, 100000000), // §6.2.64.3, line 3687
    spec(0x4600, 0, "Temperature", DT::Unsigned8, A::Ro, false, 0), // §6.2.66, line 3707
    spec(0x4601, 0, "Regenerator Clamp Cut-off Voltage", DT::Unsigned16, A::Rw, false, 0x3C), // §6.2.67, line 3721
    spec(0x4610, 1, "Brake Type", DT::Unsigned8, A::Rw, false, 0, true), // §6.2.68.1, line 3746
    spec(0x4610, 2, "Brake Polarity", DT::Unsigned8, A::Rw, false, 0, true), // §6.2.68.2, line 3767
    limited(spec(0x4610, 3, "Brake On Delay Time", DT::Unsigned16, A::Rw, false, 0, true), 0, 10000), // §6.2.68.3, line 3785
    limited(spec(0x4610, 4, "Brake Off Delay Time", DT::Unsigned16, A::Rw, false, 0, true), 0, 10000), // §6.2.68.4, line 3801
    spec(0x4610, 5, "Min. Motor Speed for Brake On", DT::Unsigned16, A::Rw, false, 0, true), // §6.2.68.5, line 3819: range 10..500 excludes the default 0 (docs)
    limited(spec(0x4610, 6, "Tum On Voltage", DT::Unsigned8, A::Rw, false, 0xC, true), 0, 24), // §6.2.68.6, line 3835
    limited(spec(0x4610, 7, "On Hold Voltage", DT::Unsigned8, A::Rw, false, 0, true), 0, 24), // §6.2.68.7, line 3853
    spec(0x4620, 1, "Minimum Collision Detection Position", DT::Integer32, A::Rw, false, 0, true), // §6.2.69.1, line 3876
    spec(0x4620, 2, "Maximum Collision Detection Position", DT::Integer32, A::Rw, false, 0, true), // §6.2.69.1, line 3890
    limited(spec(0x4700, 2, "Target Motion Index", DT::Unsigned16, A::Rw, true, 0x4710, true), 0x4710, 0x4719), // §6.2.70.1, line 3917
    limited(spec(0x4701, 0, "Actual Motion Index", DT::Unsigned16, A::Ro, true, 0x4710), 0x4710, 0x4719), // §6.2.71, line 3935
    spec(0x4702, 1, "Motion Error", DT::Unsigned32, A::Ro, false, 0, true), // §6.2.72.2, line 3978
    spec(0x4702, 2, "Motion Error", DT::Unsigned32, A::Ro, false, 0, true), // §6.2.72.2, line 3978
    spec(0x4702, 3, "Motion Error", DT::Unsigned32, A::Ro, false, 0, true), // §6.2.72.2, line 3978
    spec(0x4702, 4, "Motion Error", DT::Unsigned32, A::Ro, false, 0, true), // §6.2.72.2, line 3978
    spec(0x4702, 5, "Motion Error", DT::Unsigned32, A::Ro, false, 0, true), // §6.2.72.2, line 3978
    spec(0x4702, 6, "Motion Error", DT::Unsigned32, A::Ro, false, 0, true), // §6.2.72.2, line 3978
    spec(0x4702, 7, "Motion Error", DT::Unsigned32, A::Ro, false, 0, true), // §6.2.72.2, line 3978
    spec(0x4702, 8, "Motion Error", DT::Unsigned32, A::Ro, false, 0, true), // §6.2.72.2, line 3978
    spec(0x4702, 9, "Motion Error", DT::Unsigned32, A::Ro, false, 0, true), // §6.2.72.2, line 3978
    spec(0x4702, 10, "Motion Error", DT::Unsigned32, A::Ro, false, 0, true), // §6.2.72.2, line 3978
    limited(spec(0x4702, 0, "Number of Motion Error History", DT::Unsigned8, A::Ro, false, 0, true), 0, 10), // §6.2.72.1, line 3960: a count, 0..10
    spec(0x5001, 0, "UART Baudrate", DT::Unsigned8, A::Rw, false, 4), // §6.2.75, line 4327
    spec(0x5010, 1, "Analog Input 0 ~ 3", DT::Unsigned16, A::Ro, false, 0, true), // §6.2.77.1, line 4394
    spec(0x5010, 2, "Analog Input 0 ~ 3", DT::Unsigned16, A::Ro, false, 0, true), // §6.2.77.1, line 4394
    spec(0x5010, 3, "Analog Input 0 ~ 3", DT::Unsigned16, A::Ro, false, 0, true), // §6.2.77.1, line 4394
    spec(0x5010, 4, "Analog Input 0 ~ 3", DT::Unsigned16, A::Ro, false, 0, true), // §6.2.77.1, line 4394
    limited(spec(0x6042, 0, "VL Mode Target Velocity", DT::Integer16, A::Rw, true, 0), 0, 32767), // §6.2.81, line 4641
    limited(spec(0x6043, 0, "VL Mode Demand Velocity", DT::Integer16, A::Ro, true, 0), 0, 32767), // §6.2.83, line 4657
    limited(spec(0x6044, 0, "VL Mode Actual Velocity", DT::Integer16, A::Ro, true, 0), 0, 32767), // §6.2.84, line 4671
    spec(0x6046, 1, "VL Mode Velocity Min. Value", DT::Unsigned32, A::Rw, false, 1, true), // §6.2.85.1, line 4694
    spec(0x6046, 2, "VL Mode Velocity Max. Value", DT::Unsigned32, A::Rw, false, 0, true), // §6.2.85.2, line 4708
    spec(0x6048, 1, "VL Mode Acceleration Delta Speed", DT::Unsigned32, A::Rw, false, 0, true), // §6.2.86.1, line 4731
    limited(spec(0x6048, 2, "VL Mode Acceleration Delta Time", DT::Unsigned16, A::Rw, false, 1, true), 1, 65535), // §6.2.86.2, line 4745
    spec(0x6049, 1, "VL Mode Deceleration Delta Speed", DT::Unsigned32, A::Rw, false, 0, true), // §6.2.87, line 4766
    limited(spec(0x6049, 2, "VL Mode Deceleration Delta Time", DT::Unsigned16, A::Rw, false, 1, true), 1, 65535), // §6.2.87.2, line 4782
    spec(0x604A, 1, "VL Mode Quick Stop Deceleration Delta Speed", DT::Unsigned32, A::Rw, false, 0, true), // §6.2.88, line 4803
    limited(spec(0x604A, 2, "VL Mode Quick Stop Deceleration Delta Time", DT::Unsigned16, A::Rw, false, 1, true), 1, 65535), // §6.2.88.2, line 4819
    spec(0x6073, 0, "Maximum Current", DT::Unsigned16, A::Rw, false, 0x7D0), // §6.2.108, line 5197
    spec(0x6075, 0, "Motor Rated Current", DT::Unsigned32, A::Rw, false, 0x3E8), // §6.2.109, line 5215
    spec(0x6076, 0, "Motor Rated Torque", DT::Unsigned32, A::Rw, false, 0), // §6.2.110, line 5242: range 1..1000000 excludes the default 0 (docs)
    spec(0x6078, 0, "Current Actual Value", DT::Integer16, A::Ro, true, 0), // §6.2.112, line 5276
    limited(spec(0x6079, 0, "DC Link Circuit Voltage", DT::Unsigned32, A::Ro, false, 0), 0, 500000), // §6.2.113, line 5290
    limited(spec(0x6089, 0, "Position Notation Index", DT::Integer8, A::Rw, false, 0), 0, 0), // §6.2.124, line 5516
    limited(spec(0x608A, 0, "Position Dimension Index", DT::Unsigned8, A::Rw, false, 0xAC), 172, 172), // §6.2.125, line 5532
    limited(spec(0x608B, 0, "Velocity Notation Index", DT::Integer8, A::Rw, false, 0), 0, 0), // §6.2.126, line 5548
    limited(spec(0x608C, 0, "Velocity Dimension Index", DT::Unsigned8, A::Rw, false, 0xA4), 164, 164), // §6.2.127, line 5566
    limited(spec(0x608D, 0, "Acceleration Notation Index", DT::Integer8, A::Rw, false, 0), 0, 0), // §6.2.128, line 5582
    limited(spec(0x608E, 0, "Acceleration Dimension Index", DT::Unsigned8, A::Rw, false, 0xA4), 164, 164), // §6.2.129, line 5598
    limited(spec(0x60A4, 0, "S-Curve Profile Jerk", DT::Unsigned32, A::Rw, false, 0x2710), 1, 2147483647), // §6.2.134.1, line 5752
    limited(spec(0x60C5, 0, "Maximum Acceleration", DT::Unsigned32, A::Rw, false, 0xFFFFFFFF), 1, 4294967295), // §6.2.138, line 5828
    limited(spec(0x60C6, 0, "Maximum Deceleration", DT::Unsigned32, A::Rw, false, 0xFFFFFFFF), 1, 4294967295), // §6.2.139, line 5846
    spec(0x60FE, 1, "Physical Outputs", DT::Unsigned32, A::Rw, true, 0, true), // §6.2.143.1, line 5947
    spec(0x60FE, 2, "Output Mask", DT::Unsigned32, A::Rw, true, 0, true), // §6.2.143.2, line 5972
    spec(0x6402, 0, "Motor Type", DT::Unsigned16, A::Rw, false, 1), // §6.2.145, line 6004
};
// clang-format on

// §6.2.73: motion tables 0 to 9 (4710h-4719h), each with the same entries; 4710h as listed.
// clang-format off
constexpr std::array kMotion{
    spec(0x4710, 1, "Motion Mode of Operation", DT::Integer8, A::Rw, false, 1, true), // §6.2.73.2, line 4021
    spec(0x4710, 2, "Motion Target", DT::Integer32, A::Rw, false, 0, true), // §6.2.73.3, line 4052
    spec(0x4710, 3, "Motion Parameter 0", DT::Integer32, A::Rw, false, 0, true), // §6.2.73.4, line 4074
    spec(0x4710, 4, "Motion Parameter 1", DT::Integer32, A::Rw, false, 0, true), // §6.2.73.5, line 4098
    spec(0x4710, 5, "Motion Parameter 2", DT::Integer32, A::Rw, false, 0, true), // §6.2.73.6, line 4119
    spec(0x4710, 6, "Motion Parameter 3", DT::Integer32, A::Rw, false, 0, true), // §6.2.73.7, line 4143
    spec(0x4710, 8, "Condition Value of Next Motion-A", DT::Integer32, A::Rw, false, 0, true), // §6.2.73.9, line 4181
    spec(0x4710, 9, "Index of Next Motion-A", DT::Integer32, A::Rw, false, 0, true), // §6.2.73.10, line 4211
    spec(0x4710, 10, "Condition Type of Next Motion-B", DT::Integer32, A::Rw, false, 0, true), // §6.2.73.11, line 4235
    spec(0x4710, 11, "Condition Value of Next Motion-B", DT::Integer32, A::Rw, false, 0, true), // §6.2.73.12, line 4253
    spec(0x4710, 12, "Index of Next Motion-B", DT::Integer32, A::Rw, false, 0, true), // §6.2.73.13, line 4281
};
// clang-format on

std::vector<ObjectSpec> make_objects() {
    std::vector<ObjectSpec> out(kObjects.begin(), kObjects.end());
    for (std::uint16_t table = 0; table < 10; ++table) {
        for (ObjectSpec s : kMotion) {
            s.index = static_cast<std::uint16_t>(s.index + table);
            out.push_back(s);
        }
    }
    return out;
}

} // namespace

std::span<const ObjectSpec> ds_bvs_table_objects() {
    static const std::vector<ObjectSpec> objects = make_objects();
    return objects;
}

} // namespace codrive::drives
