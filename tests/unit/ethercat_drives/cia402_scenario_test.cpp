// SPDX-License-Identifier: Apache-2.0
// The CiA 402 scenario over CoE in-process: the same steps as the veth test (ethercat_tests) and
// the vcan test, against the simulated FIO and AKD2G on a FakeClock — deterministic, no sockets.
#include <codrive/sim/ecat/drive_profiles.hpp>
#include <codrive/sim/ecat/segment.hpp>
#include <codrive/testing/ecat_cia402_rig.hpp>

#include <gtest/gtest.h>

namespace codrive::testing {
namespace {

TEST(CoeCia402Scenario, FioAndAkd2gRunTheWholeScenarioInProcess) {
    FakeClock clock;
    sim::ecat::EcatSegment segment;
    segment.add(sim::ecat::make_drive_slave("fio", 1));
    segment.add(sim::ecat::make_drive_slave("akd2g", 2));
    sim::ecat::SegmentLink link(segment, clock);
    ethercat::Master master(link, clock);
    EcatCia402Rig rig(master, clock, milliseconds(2), [&clock](TimePoint t) {
        if (clock.now() < t) {
            clock.set(t);
        }
    });
    ASSERT_TRUE(rig.bring_up({"fio", "akd2g"}));
    run_fio_akd2g_scenario(rig);
    EXPECT_EQ(rig.bad_cycles(), 0U);
}

} // namespace
} // namespace codrive::testing
