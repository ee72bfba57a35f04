// SPDX-License-Identifier: Apache-2.0
// The simulated slave's application cycle per sync mode (ETG.1020 §21.1.3.1): free run steps
// on its own timer, SM-synchronous (1C32h:01 = 1) only on the SM2 event of the master's frame.
#include <codrive/testing/sim_segment.hpp>

#include <gtest/gtest.h>

namespace codrive::ethercat {
namespace {

class SyncModeSim : public codrive::testing::SimSegmentTest {
protected:
    SyncModeSim() { segment_.add(sim::ecat::make_drive_slave("fio", 11)); }
    void to_op(std::uint16_t mode) {
        ASSERT_NO_FATAL_FAILURE(bring_up(AlState::PreOp));
        ASSERT_TRUE(master_.sdo_write<std::uint16_t>(0, 0x1C32, 1, mode)) << master_.last_error();
        ASSERT_TRUE(master_.set_state_all(AlState::Op)) << master_.last_error();
    }
    sim::ecat::EscSlave& slave() { return segment_.slave(0); }
};

TEST_F(SyncModeSim, SmSynchronousApplicationRunsOncePerOutputFrameAndWaitsWithoutOne) {
    to_op(1);
    EXPECT_TRUE(slave().sm_synchronous());
    const auto before = slave().application_cycles();
    for (int i = 0; i < 10; ++i) {
        ASSERT_TRUE(master_.exchange_process_data()) << master_.last_error();
    }
    EXPECT_EQ(slave().application_cycles(), before + 10) << "one cycle per SM2 event";
    // No frame: the application waits for the next SM2 event.
    clock_.advance(milliseconds(5));
    slave().idle(clock_.now());
    EXPECT_EQ(slave().application_cycles(), before + 10);
}

TEST_F(SyncModeSim, FreeRunApplicationRunsWithoutFrames) {
    to_op(0);
    EXPECT_FALSE(slave().sm_synchronous());
    const auto before = slave().application_cycles();
    clock_.advance(milliseconds(5));
    slave().idle(clock_.now());
    EXPECT_EQ(slave().application_cycles(), before + 1);
}

} // namespace
} // namespace codrive::ethercat
