// SPDX-License-Identifier: Apache-2.0
// The in-process EtherCAT segment the master's unit tests run on: a Master on a FakeClock whose
// frames reach simulated slaves through a SegmentLink. A fixture adds its slaves in its
// constructor (sim::ecat::make_drive_slave) and brings them up with bring_up().
#pragma once

#include <codrive/ethercat/error.hpp>
#include <codrive/ethercat/master.hpp>
#include <codrive/sim/ecat/drive_profiles.hpp>
#include <codrive/sim/ecat/segment.hpp>

#include <codrive/core/time.hpp>

#include <gtest/gtest.h>

#include <cstddef>
#include <cstdint>

namespace codrive::testing {

class SimSegmentTest : public ::testing::Test {
protected:
    /// Scans the segment and brings every slave to `state`; a failure is fatal for the test and
    /// carries the master's sentence.
    void bring_up(ethercat::AlState state) {
        ASSERT_TRUE(master_.scan()) << master_.last_error();
        ASSERT_TRUE(master_.set_state_all(state)) << master_.last_error();
    }

    /// One control cycle as the controller runs it: the frame may take half of `period`, then
    /// every slave's application (and its SM watchdog) runs and the clock moves to the next
    /// cycle's start. Counts in `late_cycles_` the cycles whose frame took longer than that.
    Result<std::uint16_t> control_cycle(Duration period) {
        const TimePoint start = clock_.now();
        Result<std::uint16_t> r = fail(ethercat::EcatErrc::NotConfigured);
        if (auto s = master_.send_process_data(); s) {
            r = master_.receive_process_data(start + period / 2);
        }
        if (clock_.now() - start > period / 2) {
            ++late_cycles_;
        }
        for (std::size_t i = 0; i < segment_.size(); ++i) {
            (void)segment_.slave(i).tick(clock_.now());
        }
        clock_.set(start + period);
        return r;
    }

    FakeClock clock_;
    sim::ecat::EcatSegment segment_;
    sim::ecat::SegmentLink link_{segment_, clock_};
    ethercat::Master master_{link_, clock_};
    int late_cycles_ = 0;
};

} // namespace codrive::testing
