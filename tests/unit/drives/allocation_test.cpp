// SPDX-License-Identifier: Apache-2.0
// Axis::on_cycle allocates nothing in steady cyclic operation (an enabled axis following CSP
// set-points), counted with a replaced operator new over 1000 cycles after warm-up.
#include "rig.hpp"

#include <gtest/gtest.h>

// One program-wide counting operator new (included once per program).
#include <codrive/testing/counting_new.hpp>

namespace codrive::drives::testing {
namespace {

using codrive::testing::g_allocations;
using codrive::testing::g_counting;

TEST(AxisAllocation, OnCycleOfAnEnabledAxisFollowingCspSetPointsAllocatesNothing) {
    Rig rig(akd2g_profile());
    rig.cycles(3);
    auto mode =
        rig.run([&](auto done) { rig.axis().set_mode(cia402::Mode::CyclicSyncPosition, done); });
    ASSERT_TRUE(mode.has_value()) << mode.error().message;
    auto enabled = rig.run([&](auto done) { rig.axis().enable(done); });
    ASSERT_TRUE(enabled.has_value()) << enabled.error().message;
    const std::int32_t start = rig.axis().position_actual().value_or(0);
    std::uint64_t allocations = 0;
    for (int k = 1; k <= 1100; ++k) {
        rig.clock.advance(std::chrono::milliseconds(1));
        rig.tr.apply_outputs();
        rig.dev.step();
        rig.tr.process();             // the fake transport and device are not under test
        const bool counted = k > 100; // warm-up
        const std::uint64_t before = g_allocations.load();
        g_counting = counted;
        rig.axis().set_target_position(start + k * 10);
        rig.axis().on_cycle(rig.clock.now());
        g_counting = false;
        allocations += g_allocations.load() - before;
    }
    EXPECT_EQ(allocations, 0U);
    EXPECT_EQ(rig.axis().state(), cia402::State::OperationEnabled);
    EXPECT_EQ(rig.axis().target_position(), start + 11000);
}

} // namespace
} // namespace codrive::drives::testing
