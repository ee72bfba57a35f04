// SPDX-License-Identifier: Apache-2.0
// The fixture the master's fault tests share: a Master on a FakeClock whose frames pass a
// FaultyWire to a simulated segment. A derived fixture adds its drives in its constructor and
// brings them up in SetUp().
#pragma once

#include "faulty_wire.hpp"

#include <codrive/ethercat/master.hpp>
#include <codrive/sim/ecat/drive_profiles.hpp>
#include <codrive/sim/ecat/segment.hpp>

#include <gtest/gtest.h>

namespace codrive::ethercat::test {

class FaultyWireSegment : public ::testing::Test {
protected:
    /// Scans the segment and brings every slave to `state`; a failure ends the test with the
    /// master's sentence.
    void bring_up(AlState state) {
        ASSERT_TRUE(master_.scan()) << master_.last_error();
        ASSERT_TRUE(master_.set_state_all(state)) << master_.last_error();
    }

    FakeClock clock_;
    sim::ecat::EcatSegment segment_;
    sim::ecat::SegmentLink segment_link_{segment_, clock_};
    FaultyWire link_{segment_link_, clock_};
    Master master_{link_, clock_};
};

} // namespace codrive::ethercat::test
