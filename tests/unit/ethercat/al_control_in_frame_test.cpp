// SPDX-License-Identifier: Apache-2.0
// AL control writes riding in the cyclic frame (Master::queue_al_control): a slave that left OP
// is acknowledged and brought back while the LRW goes on, a lost frame repeats the write.
#include <codrive/testing/sim_segment.hpp>

#include <gtest/gtest.h>

namespace codrive::ethercat {
namespace {

class AlControlInFrame : public codrive::testing::SimSegmentTest {
protected:
    AlControlInFrame() {
        segment_.add(sim::ecat::make_drive_slave("fio", 11));
        segment_.add(sim::ecat::make_drive_slave("ds-bvs", 22));
    }
    void SetUp() override {
        ASSERT_NO_FATAL_FAILURE(bring_up(AlState::Op));
        ASSERT_TRUE(master_.exchange_process_data()) << master_.last_error();
    }
    /// One cyclic frame; the AL status probes it carried, if any.
    std::optional<Master::AlProbe> cycle(std::size_t slave) {
        (void)master_.exchange_process_data();
        if (!master_.take_al_probes()) {
            return std::nullopt;
        }
        return master_.al_probes()[slave];
    }
};

TEST_F(AlControlInFrame, ASlaveThatLeftOpIsAcknowledgedAndBroughtBackWithinTheCycle) {
    // A local error (ETG.1000.6 §6.4.1.3): slave 0 drops to SAFE-OP + 0x001A.
    ASSERT_TRUE(segment_.slave(0).leave_op(0x001A));
    auto w = master_.exchange_process_data();
    ASSERT_FALSE(w);
    EXPECT_EQ(master_.last_wkc_mismatch(), std::uint16_t{4}); // slave 0 reads inputs only
    auto probe = cycle(0); // the next frame carries the AL status reads
    ASSERT_TRUE(probe);
    EXPECT_EQ(probe->status.state, AlState::SafeOp);
    EXPECT_TRUE(probe->status.error);
    EXPECT_EQ(probe->status.code, 0x001A);
    // Acknowledge (SAFE-OP + bit 4); the first frame carrying it is lost on the wire: the
    // write stays queued and the next frame brings it.
    ASSERT_TRUE(master_.queue_al_control(0, 0x0014));
    link_.drop_next(1);
    EXPECT_FALSE(master_.exchange_process_data());
    EXPECT_TRUE((segment_.slave(0).reg16(0x0130) & kAlErrorFlag) != 0) << "nothing arrived";
    (void)master_.exchange_process_data();
    EXPECT_EQ(segment_.slave(0).reg16(0x0130) & kAlErrorFlag, 0) << "acknowledged";
    EXPECT_EQ(segment_.slave(0).state(), AlState::SafeOp);
    // OP requested in the cyclic frame: the working counter is full again.
    ASSERT_TRUE(master_.queue_al_control(0, 0x0008));
    (void)master_.exchange_process_data();
    EXPECT_EQ(segment_.slave(0).state(), AlState::Op);
    w = master_.exchange_process_data();
    ASSERT_TRUE(w) << master_.last_error();
    EXPECT_EQ(*w, master_.expected_wkc());
    EXPECT_EQ(segment_.slave(1).state(), AlState::Op) << "the other slave never left OP";
}

TEST_F(AlControlInFrame, UnknownSlaveOrNothingToWriteIsRefused) {
    EXPECT_FALSE(master_.queue_al_control(2, 0x0008));
    EXPECT_FALSE(master_.queue_al_control(0, 0));
}

} // namespace
} // namespace codrive::ethercat
