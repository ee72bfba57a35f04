// SPDX-License-Identifier: Apache-2.0
// ethercat::cyclic_shortfall(): what became of the cyclic frames when a drive's inputs did not
// come in, said from the master's counts; nothing when most frames brought them in.
#include <codrive/ethercat/cyclic_shortfall.hpp>

#include <gtest/gtest.h>

namespace codrive::ethercat {
namespace {

/// Counts as the master keeps them after the transition to OP.
ProcessDataStats at_op() {
    ProcessDataStats s;
    s.cycles = 40;
    s.input_frames = 12;
    s.lost_frames = 3;
    s.late_frames = 1;
    s.wkc_errors = 28;
    return s;
}

TEST(CyclicShortfall, FramesBackAfterTheirCycleAreCountedAndALongerCycleIsSuggested) {
    ProcessDataStats now = at_op();
    now.lost_frames += 2993; // every wait ended without its frame
    now.late_frames += 2991; // all but two were read by a later wait
    EXPECT_EQ(cyclic_shortfall(at_op(), now, microseconds(1000)),
              ": none of the 2993 cyclic frames since OP brought the inputs in (2991 came back "
              "after their 1000 µs cycle, 2 did not come back); the frames take longer than the "
              "1000 µs cycle to come back (a loaded host or a long segment): a longer cycle "
              "gives them time");
}

TEST(CyclicShortfall, AFewFramesInTimeAreSaidAsOnly) {
    ProcessDataStats now = at_op();
    now.cycles += 3;
    now.input_frames += 3;
    now.lost_frames += 1497;
    now.late_frames += 1497;
    EXPECT_EQ(cyclic_shortfall(at_op(), now, microseconds(250)),
              ": only 3 of the 1500 cyclic frames since OP brought the inputs in (1497 came back "
              "after their 250 µs cycle); the frames take longer than the 250 µs cycle to come "
              "back (a loaded host or a long segment): a longer cycle gives them time");
}

TEST(CyclicShortfall, ASilentSlaveAndAnInterfaceThatIsDownAreToldApartFromLateFrames) {
    ProcessDataStats now = at_op();
    now.cycles += 100;
    now.wkc_errors += 100; // back in time, a slave did not take part
    now.send_errors += 5;
    now.receive_errors += 2;
    EXPECT_EQ(cyclic_shortfall(at_op(), now, milliseconds(2)),
              ": none of the 107 cyclic frames since OP brought the inputs in (100 came back with "
              "a working counter other than expected, 2 were given up on a receive error, 5 could "
              "not be sent)");
}

TEST(CyclicShortfall, NothingWhenMostFramesBroughtTheInputsInOrNoneWasSent) {
    ProcessDataStats now = at_op();
    EXPECT_EQ(cyclic_shortfall(at_op(), now, microseconds(1000)), "");
    now.cycles += 60;
    now.input_frames += 60;
    now.lost_frames += 40;
    now.late_frames += 40;
    EXPECT_EQ(cyclic_shortfall(at_op(), now, microseconds(1000)), "")
        << "60 of 100 brought the inputs in: the cause is elsewhere";
}

} // namespace
} // namespace codrive::ethercat
