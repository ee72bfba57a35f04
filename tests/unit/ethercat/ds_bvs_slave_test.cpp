// SPDX-License-Identifier: Apache-2.0
// The simulated DS-BVS EtherCAT slave's error objects against its manual, through the master
// in-process (FakeClock): 1029h and the 4080h error history exist over CoE as on CAN.
#include <codrive/sim/sim_device.hpp>
#include <codrive/testing/sim_segment.hpp>

#include <gtest/gtest.h>

namespace codrive::ethercat {
namespace {

using sim::ecat::make_drive_slave;

class DsBvsSlave : public codrive::testing::SimSegmentTest {
protected:
    DsBvsSlave() { segment_.add(make_drive_slave("ds-bvs", 3)); }
    void SetUp() override { bring_up(AlState::PreOp); }
};

TEST_F(DsBvsSlave, ErrorBehaviour1029hHasTheManualsDefaults) {
    // §6.2.12: communication and application error behaviour, both default 1.
    EXPECT_EQ(master_.sdo_read<std::uint8_t>(0, 0x1029, 0).value_or(0), 2);
    EXPECT_EQ(master_.sdo_read<std::uint8_t>(0, 0x1029, 1).value_or(0), 1);
    EXPECT_EQ(master_.sdo_read<std::uint8_t>(0, 0x1029, 2).value_or(0), 1);
}

TEST_F(DsBvsSlave, AFaultLandsIn4080hWhichOnlyZeroClears) {
    // §6.2.44: the newest error code at sub 1, sub 0 counts; ten entries.
    EXPECT_EQ(master_.sdo_read<std::uint8_t>(0, 0x4080, 0).value_or(0xFF), 0);
    EXPECT_FALSE(master_.sdo_read<std::uint16_t>(0, 0x4080, 11)) << "no eleventh entry";
    ASSERT_TRUE(
        master_.sdo_write<std::uint8_t>(0, sim::kControlObject, sim::kControlOverCurrent, 1))
        << master_.last_error();
    clock_.advance(std::chrono::milliseconds(10));
    ASSERT_TRUE(master_.sdo_read<std::uint8_t>(0, 0x1001, 0)) << master_.last_error();
    EXPECT_EQ(master_.sdo_read<std::uint8_t>(0, 0x4080, 0).value_or(0), 1);
    const auto code = master_.sdo_read<std::uint16_t>(0, 0x4080, 1);
    ASSERT_TRUE(code) << master_.last_error();
    EXPECT_EQ(*code, master_.sdo_read<std::uint16_t>(0, 0x603F, 0).value_or(0))
        << "4080h:01 holds the error code 603Fh shows";
    EXPECT_NE(*code, 0);
    // CiA 301 §7.5.2.4: only 0 may be written to sub 0, and it clears the history.
    EXPECT_FALSE(master_.sdo_write<std::uint8_t>(0, 0x4080, 0, 1));
    EXPECT_TRUE(master_.sdo_write<std::uint8_t>(0, 0x4080, 0, 0)) << master_.last_error();
    EXPECT_EQ(master_.sdo_read<std::uint8_t>(0, 0x4080, 0).value_or(0xFF), 0);
}

} // namespace
} // namespace codrive::ethercat
