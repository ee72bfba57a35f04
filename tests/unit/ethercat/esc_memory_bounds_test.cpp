// SPDX-License-Identifier: Apache-2.0
// The simulated ESC against sync managers whose area runs past its 64 KiB of memory: their
// start and length are 16 bits each, so a master may configure such an SM (fuzz_slave_replies
// did, from a corrupted SII: regressions/slave_replies/sm3_area_past_esc_memory). The simulator
// moves process data only inside its memory, and goes on answering.
#include <codrive/ethercat/registers.hpp>
#include <codrive/testing/sim_segment.hpp>

#include <gtest/gtest.h>

#include <array>

namespace codrive::ethercat {
namespace {

using sim::ecat::make_drive_slave;

class EscMemoryBounds : public codrive::testing::SimSegmentTest {
protected:
    EscMemoryBounds() { segment_.add(make_drive_slave("akd2g", 1)); }
    void SetUp() override { bring_up(AlState::SafeOp); }

    /// SM `n` enabled at `start` for `length` bytes, its control byte kept.
    void place_sm(unsigned n, std::uint16_t start, std::uint16_t length) {
        auto control = master_.read_registers(0, reg::sm(n) + 4, 1);
        ASSERT_TRUE(control) << master_.last_error();
        const std::array<std::uint8_t, 8> sm = {static_cast<std::uint8_t>(start),
                                                static_cast<std::uint8_t>(start >> 8),
                                                static_cast<std::uint8_t>(length),
                                                static_cast<std::uint8_t>(length >> 8),
                                                (*control)[0],
                                                0,
                                                SyncManager::kActivateEnable,
                                                0};
        ASSERT_TRUE(master_.write_registers(0, reg::sm(n), sm)) << master_.last_error();
    }
};

TEST_F(EscMemoryBounds, InputsOfAnSmPastTheEndOfMemoryStopAtTheEnd) {
    place_sm(3, 0xFFF8, 0x0100);
    // Every frame the slave processes packs its inputs: under ASan a write past the memory
    // ended the process here.
    for (int i = 0; i < 3; ++i) {
        EXPECT_TRUE(master_.read_registers(0, reg::kAlStatus, 2)) << master_.last_error();
    }
}

TEST_F(EscMemoryBounds, OutputsOfAnSmPastTheEndOfMemoryAreReadOnlyInside) {
    place_sm(2, 0xFFF8, 0x0100);
    for (int i = 0; i < 3; ++i) {
        EXPECT_TRUE(master_.read_registers(0, reg::kAlStatus, 2)) << master_.last_error();
    }
    EXPECT_TRUE(master_.set_state_all(AlState::Op) || !master_.last_error().empty());
}

} // namespace
} // namespace codrive::ethercat
