// SPDX-License-Identifier: Apache-2.0
// Kuhnke FIO Drive Control: the objects of the manual's object tables (004_*.txt §7.13) that the
// profile has no behaviour for, as the manual gives them (type, access, PDO mapping, default,
// range). The simulators install them from here; the conformance suite checks them against the
// manual.
#include "table_objects.hpp"

#include "object_spec_builders.hpp"

#include <array>

namespace codrive::drives {
namespace {

using DT = DataType;
using A = Access;
using builders::limited;
using builders::spec;

// clang-format off
constexpr std::array kObjects{
    spec(0x2010, 0, "IP Configuration", DT::Unsigned32, A::Rw, false, 0), // §7.13.25, line 4144
    spec(0x2011, 0, "Static IP Address", DT::Unsigned32, A::Rw, false, 0xC0A800C7), // §7.13.26, line 4170
    spec(0x2012, 0, "Static IP Subnet Mask", DT::Unsigned32, A::Rw, false, 0), // §7.13.27, line 4198
    spec(0x2014, 0, "Current IP Address", DT::Unsigned32, A::Ro, false, 0), // §7.13.28, line 4226
    spec(0x2015, 0, "Current Subnet Mask", DT::Unsigned32, A::Ro, false, 0), // §7.13.29, line 4241
    spec(0x2030, 0, "Pole Pair Count", DT::Unsigned32, A::Rw, false, 0x32), // §7.13.30, line 4256
    spec(0x2032, 0, "Max Motor Speed", DT::Unsigned32, A::Rw, false, 0x30D40), // §7.13.32, line 4287
    spec(0x2034, 0, "Upper Voltage Warning Limit", DT::Unsigned32, A::Rw, false, 0x13C68), // §7.13.33, line 4307
    spec(0x2035, 0, "Lower Voltage Warning", DT::Unsigned32, A::Rw, false, 0), // §7.13.34, line 4324
    spec(0x2036, 0, "Open Loop Current Reduction Idle Time", DT::Unsigned32, A::Rw, false, 0x3E8), // §7.13.35, line 4341
    spec(0x2037, 0, "Open Loop Current Reduction Value/Factor", DT::Integer32, A::Rw, false, 0), // §7.13.36, line 4356
    spec(0x2038, 1, "Close Brake Idle Time", DT::Unsigned32, A::Rw, false, 0x3E8, true), // §7.13.37, line 4386
    spec(0x2038, 2, "Shut Down Power Idle Time", DT::Unsigned32, A::Rw, false, 0x3E8, true), // §7.13.37, line 4395
    spec(0x2038, 3, "Open Brake Delay Time", DT::Unsigned32, A::Rw, false, 0x3E8, true), // §7.13.37, line 4404 ("readwriteonly")
    spec(0x2038, 4, "Start Operation Delay Time", DT::Unsigned32, A::Rw, false, 0x3E8, true), // §7.13.37, line 4413
    spec(0x2038, 5, "PWM Frequency", DT::Unsigned32, A::Rw, false, 0, true), // §7.13.37, line 4422 ("readwriteonly")
    limited(spec(0x2038, 6, "PWM Duty Cycle", DT::Unsigned32, A::Rw, false, 100, true), 2, 100), // §7.13.37, line 4431 ("readwriteonly")
    spec(0x2039, 1, "I_d", DT::Integer32, A::Ro, false, 0, true), // §7.13.38, line 4468
    spec(0x2039, 2, "I_q", DT::Integer32, A::Ro, false, 0, true), // §7.13.38, line 4477
    spec(0x2039, 3, "I_a", DT::Integer32, A::Ro, false, 0, true), // §7.13.38, line 4486
    spec(0x2039, 4, "I_b", DT::Integer32, A::Ro, false, 0, true), // §7.13.38, line 4495
    spec(0x203A, 1, "Minimum Current for Block Detection", DT::Unsigned32, A::Rw, false, 0xFFFFFFBA, true), // §7.13.39, line 4532
    spec(0x203A, 2, "Period of Blocking", DT::Unsigned32, A::Rw, false, 0xC8, true), // §7.13.39, line 4541
    spec(0x203B, 1, "Motor Rated Current", DT::Unsigned32, A::Rw, false, 0, true), // §7.13.40, line 4570
    spec(0x203B, 2, "Maximum Duration fo Peak Current", DT::Unsigned32, A::Rw, false, 0, true), // §7.13.40, line 4577
    spec(0x203B, 3, "Threshold", DT::Unsigned32, A::Rw, false, 0, true), // §7.13.40, line 4584
    spec(0x203B, 4, "CalcValue", DT::Unsigned32, A::Rw, false, 0, true), // §7.13.40, line 4591
    spec(0x203B, 5, "Limited Current", DT::Unsigned32, A::Rw, false, 0, true), // §7.13.40, line 4600
    spec(0x203B, 6, "Status", DT::Unsigned32, A::Rw, false, 0, true), // §7.13.40, line 4607
    spec(0x203D, 0, "Torque Window", DT::Unsigned16, A::Rw, true, 0), // §7.13.41, line 4633
    spec(0x203E, 0, "Torque Window Time Out", DT::Unsigned16, A::Rw, true, 0), // §7.13.42, line 4651
    spec(0x203F, 0, "Max Slippage Time Out", DT::Unsigned16, A::Rw, true, 0x64), // §7.13.43, line 4667
    spec(0x2057, 0, "Clock Direction Multiplier", DT::Integer32, A::Rw, false, 128), // §7.13.44, line 4687
    spec(0x2058, 0, "Clock Direction Divider", DT::Integer32, A::Rw, false, 1), // §7.13.45, line 4702
    spec(0x2059, 0, "Encoder Configuration", DT::Integer32, A::Rw, false, 0), // §7.13.46, line 4717
    spec(0x2084, 0, "Bootup Delay", DT::Unsigned32, A::Rw, false, 0), // §7.13.47, line 4733
    spec(0x2101, 0, "Fieldbus Module Availability", DT::Integer32, A::Ro, false, 32), // §7.13.48, line 4746
    spec(0x2102, 0, "Fieldbus Module", DT::Integer32, A::Rw, false, 32), // §7.13.49, line 4761
    spec(0x3210, 1, "Position Loop, Proportional Gain (closed Loop)", DT::Integer32, A::Rw, false, 0, true), // §7.13.57, line 5270
    spec(0x3210, 2, "Position Loop, Integral Gain (closed Loop)", DT::Integer32, A::Rw, false, 0, true), // §7.13.57, line 5279
    spec(0x3210, 3, "Velocity Loop, Proportional Gain (closed Loop)", DT::Integer32, A::Rw, false, 0, true), // §7.13.57, line 5288
    spec(0x3210, 4, "Velocity Loop, Integral Gain (closed Loop)", DT::Integer32, A::Rw, false, 0, true), // §7.13.57, line 5297
    spec(0x3210, 5, "Flux Current Loop, Proportional Gain (closed Loop)", DT::Integer32, A::Rw, false, 0, true), // §7.13.57, line 5306
    spec(0x3210, 6, "Flux Current Loop, Integral Gain (closed Loop)", DT::Integer32, A::Rw, false, 0, true), // §7.13.57, line 5315
    spec(0x3210, 7, "Torque Current Loop, Proportional Gain (closed Loop)", DT::Integer32, A::Rw, false, 0, true), // §7.13.57, line 5324
    spec(0x3210, 8, "Torque Current Loop, Integral Gain (closed Loop)", DT::Integer32, A::Rw, false, 0, true), // §7.13.57, line 5333
    spec(0x3210, 9, "Torque Current Loop, Proportional Gain (open Loop)", DT::Integer32, A::Rw, false, 0, true), // §7.13.57, line 5342
    spec(0x3210, 10, "Torque Current Loop, Integral Gain (open Loop)", DT::Integer32, A::Rw, false, 0, true), // §7.13.57, line 5351
    spec(0x3210, 11, "Velocity Feed Forward Factor In Per Mille", DT::Integer32, A::Rw, false, 0x3E8, true), // §7.13.57, line 5360
    spec(0x3210, 12, "Acceleration Feed Forward Factor", DT::Integer32, A::Rw, false, 0, true), // §7.13.57, line 5369
    // §7.13.57 line 5263: sub 0 = 0Ch, the highest of the entries 01h..0Ch the section lists.
    spec(0x3210, 0, "Highest Sub-index Supported", DT::Unsigned8, A::Ro, false, 0x0C, true),
    spec(0x3240, 1, "Special Function Enable", DT::Unsigned32, A::Rw, true, 0, true), // §7.13.59, line 5482
    spec(0x3240, 2, "Function Inverted", DT::Unsigned32, A::Rw, true, 0, true), // §7.13.59, line 5489
    spec(0x3240, 3, "Force Enable", DT::Unsigned32, A::Rw, true, 0, true), // §7.13.59, line 5496
    spec(0x3240, 4, "Force Value", DT::Unsigned32, A::Rw, true, 0, true), // §7.13.59, line 5503
    spec(0x3240, 5, "Raw Value", DT::Unsigned32, A::Rw, true, 0, true), // §7.13.59, line 5512
    spec(0x3240, 6, "Input Range Select", DT::Unsigned32, A::Rw, true, 0, true), // §7.13.59, line 5519
    spec(0x3240, 7, "Differential Select", DT::Unsigned32, A::Rw, true, 0, true), // §7.13.59, line 5526
    spec(0x3250, 1, "Special Function Enable", DT::Unsigned32, A::Rw, true, 0xF0001, true), // §7.13.63, line 5770
    spec(0x3250, 2, "Function Inverted", DT::Unsigned32, A::Rw, true, 0, true), // §7.13.63, line 5777
    spec(0x3250, 3, "Force Enable", DT::Unsigned32, A::Rw, true, 0, true), // §7.13.63, line 5784
    spec(0x3250, 4, "Force Value", DT::Unsigned32, A::Rw, true, 0, true), // §7.13.63, line 5791
    spec(0x3250, 5, "Raw Value", DT::Unsigned32, A::Rw, true, 0, true), // §7.13.63, line 5798
    limited(spec(0x3700, 0, "Deviation Error Option Code", DT::Integer16, A::Rw, false, -1), -1, 2), // §7.13.68, line 6055
    limited(spec(0x3701, 0, "Limit Switch Error Option Code", DT::Integer16, A::Rw, false, -1), -1, 6), // §7.13.69, line 6085
    spec(0x6042, 0, "VI Target Velocity", DT::Integer16, A::Rw, true, 200), // §7.13.81, line 6509
    spec(0x6043, 0, "VI Velocity Demand", DT::Integer16, A::Rw, true, 0), // §7.13.82, line 6524
    spec(0x6044, 0, "VI Velocity Actual Value", DT::Integer16, A::Ro, true, 0), // §7.13.83, line 6539
    spec(0x6046, 1, "MinAmount", DT::Unsigned32, A::Rw, true, 0, true), // §7.13.84, line 6573
    spec(0x6046, 2, "MaxAmount", DT::Unsigned32, A::Rw, false, 0, true), // §7.13.84, line 6582
    spec(0x6048, 1, "DeltaSpeed", DT::Unsigned32, A::Rw, true, 0x1F4, true), // §7.13.85, line 6616
    spec(0x6048, 2, "DeltaTime", DT::Unsigned16, A::Rw, true, 1, true), // §7.13.85, line 6625
    spec(0x6049, 1, "DeltaSpeed", DT::Unsigned32, A::Rw, true, 0x1F4, true), // §7.13.86, line 6656
    spec(0x6049, 2, "DeltaTime", DT::Unsigned16, A::Rw, true, 1, true), // §7.13.86, line 6665
    spec(0x604A, 1, "DeltaSpeed", DT::Unsigned32, A::Rw, true, 0x1388, true), // §7.13.87, line 6696
    spec(0x604A, 2, "DeltaTime", DT::Unsigned16, A::Rw, true, 1, true), // §7.13.87, line 6705
    spec(0x604C, 1, "VI Dimension Factor Numerator", DT::Integer32, A::Rw, true, 1, true), // §7.13.88, line 6736
    spec(0x604C, 2, "VI Dimension Factor enumerator", DT::Integer32, A::Rw, true, 60, true), // §7.13.88, line 6745
    spec(0x606F, 0, "Velocity threshold", DT::Unsigned16, A::Rw, true, 0), // §7.13.107, line 7113
    spec(0x6070, 0, "Velocity Window", DT::Unsigned16, A::Rw, true, 0), // §7.13.108, line 7131
    limited(spec(0x6073, 0, "Max Current", DT::Integer16, A::Ro, true, 0), 0, 1000), // §7.13.111, line 7179
    spec(0x6074, 0, "Torque Demand", DT::Integer16, A::Ro, true, 0), // §7.13.112, line 7193
    spec(0x6075, 0, "Motor Rated Current", DT::Unsigned32, A::Rw, false, 0), // §7.13.113, line 7208
    spec(0x607B, 1, "Min Position Range Limit", DT::Integer32, A::Rw, true, -2147483648, true), // §7.13.116, line 7271
    spec(0x607B, 2, "Max Position Range Limit", DT::Integer32, A::Rw, true, 2147483647, true), // §7.13.116, line 7280
    spec(0x6082, 0, "End Velocity", DT::Unsigned32, A::Rw, true, 0), // §7.13.123, line 7425
    spec(0x60A4, 1, "Begin Acceleration Jerk", DT::Unsigned32, A::Rw, false, 0x3E8, true), // §7.13.139, line 7865
    spec(0x60A4, 2, "End Acceleration Jerk", DT::Unsigned32, A::Rw, false, 0x3E8, true), // §7.13.139, line 7874
    spec(0x60A4, 3, "Begin Deceleration Jerk", DT::Unsigned32, A::Rw, false, 0x3E8, true), // §7.13.139, line 7883
    spec(0x60A4, 4, "End Deceleration Jerk", DT::Unsigned32, A::Rw, false, 0x3E8, true), // §7.13.139, line 7892
    spec(0x60C5, 0, "Max Acceleration", DT::Unsigned32, A::Rw, true, 0x1388), // §7.13.148, line 8159
    spec(0x60C6, 0, "Max Deceleration", DT::Unsigned32, A::Rw, true, 0x1388), // §7.13.149, line 8176
    spec(0x60F2, 0, "Position Option Code", DT::Unsigned16, A::Rw, true, 0), // §7.13.158, line 8483
    spec(0x60F8, 0, "Max Slippage", DT::Integer32, A::Rw, true, 400), // §7.13.160, line 8558
    spec(0x60FA, 0, "Control Effort", DT::Integer32, A::Ro, true, 0), // §7.13.161, line 8579
    spec(0x60FC, 0, "Position Demand Internal Value", DT::Integer32, A::Ro, true, 0), // §7.13.162, line 8596
    // §7.13.164: a RECORD, sub 0 = 01h; the table prints the entry's sub-index as 00h.
    spec(0x60FE, 1, "Digital Outputs #1", DT::Unsigned32, A::Rw, true, 0, true), // §7.13.164, line 8658
    spec(0x60FE, 0, "Highest Sub-index Supported", DT::Unsigned8, A::Ro, false, 1, true), // §7.13.164, line 8651
};
// clang-format on

} // namespace

std::span<const ObjectSpec> fio_table_objects() {
    return kObjects;
}

} // namespace codrive::drives
