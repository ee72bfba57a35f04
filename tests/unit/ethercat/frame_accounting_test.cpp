// SPDX-License-Identifier: Apache-2.0
// What the master counts for a cyclic frame that does not come back as awaited: lost when its
// deadline passes, late when a later cycle reads it after all, unreadable when what arrives is
// not a late frame of ours (garbled on the wire, or a copy of one already read). The controller
// and the FoE veth test tell "the host was slow" from "the wire failed" by these counters.
#include "faulty_wire_fixture.hpp"

#include <gtest/gtest.h>

namespace codrive::ethercat {
namespace {

class FrameAccounting : public test::FaultyWireSegment {
protected:
    FrameAccounting() { segment_.add(sim::ecat::make_drive_slave("fio", 11)); }
    void SetUp() override {
        bring_up(AlState::Op);
        ASSERT_TRUE(master_.exchange_process_data()) << master_.last_error();
        start_ = master_.stats();
    }
    /// Cyclic frames at a 1 ms cycle, as a real-time loop runs them.
    void cycles(int n) {
        for (int i = 0; i < n; ++i) {
            (void)master_.send_process_data();
            (void)master_.receive_process_data(clock_.now() + milliseconds(1));
            clock_.advance(microseconds(500));
        }
    }
    [[nodiscard]] std::uint64_t lost() const {
        return master_.stats().lost_frames - start_.lost_frames;
    }
    [[nodiscard]] std::uint64_t late() const {
        return master_.stats().late_frames - start_.late_frames;
    }
    [[nodiscard]] std::uint64_t unreadable() const {
        return master_.stats().unreadable_frames - start_.unreadable_frames;
    }
    ProcessDataStats start_;
};

TEST_F(FrameAccounting, FramesThatComeBackAfterTheirCycleAreLostThenLateNeverUnreadable) {
    segment_link_.delay_returns(200, 5);
    cycles(500);
    segment_link_.delay_returns(0, 0);
    cycles(1); // reads the last late frame, if the last cycle's was one
    ASSERT_GT(segment_link_.delayed(), 50U);
    EXPECT_EQ(lost(), segment_link_.delayed());
    EXPECT_EQ(late(), segment_link_.delayed()) << "every lost frame came back";
    EXPECT_EQ(unreadable(), 0U);
}

TEST_F(FrameAccounting, AGarbledFrameIsLostAndUnreadableNotLate) {
    link_.garble_next(3);
    cycles(10);
    EXPECT_EQ(lost(), 3U) << "the awaited frame came back but not as sent: the cycle lost it";
    EXPECT_EQ(unreadable(), 3U);
    EXPECT_EQ(late(), 0U);
    EXPECT_EQ(master_.stats().consecutive_lost, 0U) << "the cycles after it work";
}

TEST_F(FrameAccounting, ACopyOfAFrameAlreadyReadIsUnreadableNotLate) {
    link_.repeat_next(4);
    cycles(10);
    // Each copy arrives while the next cycle waits: that cycle drops it and reads its own frame.
    EXPECT_EQ(lost(), 0U);
    EXPECT_EQ(late(), 0U);
    EXPECT_EQ(unreadable(), 4U);
}

TEST_F(FrameAccounting, ALateFrameIsLateOnceEvenIfItsCopyFollows) {
    segment_link_.delay_returns(1000, 1); // every frame after its cycle
    cycles(1);
    segment_link_.delay_returns(0, 0);
    link_.repeat_next(1); // the late frame comes back twice
    cycles(3);
    EXPECT_EQ(lost(), 1U);
    EXPECT_EQ(late(), 1U);
    EXPECT_EQ(unreadable(), 1U) << "the copy of a frame already read";
}

TEST_F(FrameAccounting, ALateFrameOfABlockingCallIsNotCountedAgainstTheCycle) {
    // A register read outside the cycle loses its first attempt (the frame comes back after
    // the deadline) and succeeds with the second; the late copy is read by that second wait.
    link_.delay_reads(0x0130, 1); // AL status: an FPRD of 0x0130, its first attempt late
    ASSERT_TRUE(master_.read_al_status(0)) << master_.last_error();
    EXPECT_EQ(link_.held(), 1);
    EXPECT_EQ(master_.stats().late_other_frames - start_.late_other_frames, 1U);
    EXPECT_EQ(late(), 0U) << "no cyclic frame was lost";
    EXPECT_EQ(lost(), 0U);
    EXPECT_EQ(unreadable(), 0U);
}

} // namespace
} // namespace codrive::ethercat
