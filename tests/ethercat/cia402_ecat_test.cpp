// SPDX-License-Identifier: Apache-2.0
// The CiA 402 scenario over EtherCAT on veth: the steps of <codrive/testing/cia402_scenario.hpp>
// (the same ones the vcan test runs over CANopen) against a simulated FIO and AKD2G in
// codrive-ecat-sim; only the transport (CoeTransport), the cycle driver and the fault injection
// path (the simulator's 2FF0h control object, over CoE instead of CANopen SDO) differ.
#include "veth_segment.hpp"

#include <codrive/testing/ecat_cia402_rig.hpp>

#include <codrive/core/time.hpp>

#include <thread>

namespace codrive::testing {
namespace {

/// Cycle of the process data loop. The simulated drives integrate real time between frames, so
/// a late cycle only makes the next step longer.
constexpr Duration kPeriod = milliseconds(2);

TEST_F(EcatVethTest, Cia402ScenarioRunsOnFioAndAkd2gOverCoe) {
    start({"--slave", "fio", "--slave", "akd2g"});
    if (IsSkipped() || HasFatalFailure()) {
        return;
    }
    EcatCia402Rig rig(*master_, RealClock::instance(), kPeriod,
                      [](TimePoint t) { std::this_thread::sleep_until(t); });
    ASSERT_TRUE(rig.bring_up({"fio", "akd2g"}));
    // Same path, same tolerance and same 4-cycle latency window as in-process, in real time.
    run_fio_akd2g_scenario(rig);
}

} // namespace
} // namespace codrive::testing
