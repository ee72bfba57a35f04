// SPDX-License-Identifier: Apache-2.0
// Kollmorgen AKD2G: the objects of the manual's object tables (000_*.txt §5.2, §5.4; axis 2 by the
// profile offset) that the profile has no behaviour for, as the manual gives them (type, access,
// PDO mapping, default, range). The simulators install them from here; the conformance suite checks
// them against the manual.
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
    spec(0x1012, 0, "COB-ID Time Stamp", DT::Unsigned32, A::Rw, false, 0), // §5.2.13, line 8103
    spec(0x1026, 1, "StdIn", DT::Unsigned8, A::Rw, true, 0, true), // §5.2.17, line 8174
    spec(0x1026, 2, "StdOut", DT::Unsigned8, A::Ro, true, 0, true), // §5.2.17, line 8175
    spec(0x6073, 0, "Max current", DT::Unsigned16, A::Rw, false, 0), // §5.4.15.1, line 11893
    spec(0x6076, 0, "Motor rated torque", DT::Unsigned32, A::Ro, false, 0), // §5.4.16.1, line 11907
    spec(0x607B, 1, "Min position range limit", DT::Integer32, A::Rw, false, 0, true), // §5.4.19.1, line 11958
    spec(0x607B, 2, "Max position range limit", DT::Integer32, A::Rw, false, 0, true), // §5.4.19.1, line 11959
    spec(0x60E4, 1, "1st additional position actual value", DT::Integer32, A::Ro, true, 0, true), // §5.4.54.1, line 12684
    spec(0x60E4, 2, "2nd additional position actual value", DT::Integer32, A::Ro, true, 0, true), // §5.4.54.1, line 12685
    spec(0x60E4, 3, "3rd additional position actual value", DT::Integer32, A::Ro, true, 0, true), // §5.4.54.1, line 12686
    spec(0x60E4, 4, "4th additional position actual value", DT::Integer32, A::Ro, true, 0, true), // §5.4.54.1, line 12687
    spec(0x60E4, 5, "5th additional position actual value", DT::Integer32, A::Ro, true, 0, true), // §5.4.54.1, line 12688
    spec(0x60E8, 1, "1st additional gear ratio - motor revolutions", DT::Unsigned32, A::Rw, false, 0, true), // §5.4.55.1, line 12710
    spec(0x60E8, 2, "2nd additional gear ratio - motor revolutions", DT::Unsigned32, A::Rw, false, 0, true), // §5.4.55.1, line 12711
    spec(0x60E8, 3, "3rd additional gear ratio - motor revolutions", DT::Unsigned32, A::Rw, false, 0, true), // §5.4.55.1, line 12712
    spec(0x60E8, 4, "4th additional gear ratio - motor revolutions", DT::Unsigned32, A::Rw, false, 0, true), // §5.4.55.1, line 12713
    spec(0x60E8, 5, "5th additional gear ratio - motor revolutions", DT::Unsigned32, A::Rw, false, 0, true), // §5.4.55.1, line 12714
    spec(0x60E9, 1, "1st additional feed constant - feed", DT::Unsigned32, A::Rw, false, 0, true), // §5.4.56.1, line 12738
    spec(0x60E9, 2, "2nd additional feed constant - feed", DT::Unsigned32, A::Rw, false, 0, true), // §5.4.56.1, line 12739
    spec(0x60E9, 3, "3rd additional feed constant - feed", DT::Unsigned32, A::Rw, false, 0, true), // §5.4.56.1, line 12740
    spec(0x60E9, 4, "4th additional feed constant - feed", DT::Unsigned32, A::Rw, false, 0, true), // §5.4.56.1, line 12741
    spec(0x60E9, 5, "5th additional feed constant - feed", DT::Unsigned32, A::Rw, false, 0, true), // §5.4.56.1, line 12742
    spec(0x60ED, 1, "1st additional gear ratio - shaft revolutions", DT::Unsigned32, A::Rw, false, 0, true), // §5.4.57.1, line 12766
    spec(0x60ED, 2, "2nd additional gear ratio - shaft revolutions", DT::Unsigned32, A::Rw, false, 0, true), // §5.4.57.1, line 12767
    spec(0x60ED, 3, "3rd additional gear ratio - shaft revolutions", DT::Unsigned32, A::Rw, false, 0, true), // §5.4.57.1, line 12768
    spec(0x60ED, 4, "4th additional gear ratio - shaft revolutions", DT::Unsigned32, A::Rw, false, 0, true), // §5.4.57.1, line 12769
    spec(0x60ED, 5, "5th additional gear ratio - shaft revolutions", DT::Unsigned32, A::Rw, false, 0, true), // §5.4.57.1, line 12770
    spec(0x60EE, 1, "1st additional feed constant - shaft revolutions", DT::Unsigned32, A::Rw, false, 0, true), // §5.4.58.1, line 12794
    spec(0x60EE, 2, "2nd additional feed constant - shaft revolutions", DT::Unsigned32, A::Rw, false, 0, true), // §5.4.58.1, line 12795
    spec(0x60EE, 3, "3rd additional feed constant - shaft revolutions", DT::Unsigned32, A::Rw, false, 0, true), // §5.4.58.1, line 12796
    spec(0x60EE, 4, "4th additional feed constant - shaft revolutions", DT::Unsigned32, A::Rw, false, 0, true), // §5.4.58.1, line 12797
    spec(0x60EE, 5, "5th additional feed constant - shaft revolutions", DT::Unsigned32, A::Rw, false, 0, true), // §5.4.58.1, line 12798
};
// clang-format on

} // namespace

std::span<const ObjectSpec> akd2g_table_objects() {
    return kObjects;
}

} // namespace codrive::drives
