// SPDX-License-Identifier: Apache-2.0
// A send that finds no room (ENOBUFS: the interface's queue dropped the frame; EAGAIN: the
// socket's send buffer is full). The link returns at once, never waits for room; the master
// treats the frame as one that did not leave: a blocking call counts the attempt as lost and
// sends again, a mailbox transfer waits a poll interval and goes on until its own timeout, and
// each failure that outlasts its bound says what happened. An interface that is down still
// fails a call at once.
#include "faulty_wire_fixture.hpp"

#include <codrive/ethercat/error.hpp>

#include <gtest/gtest.h>

#include <system_error>

namespace codrive::ethercat {
namespace {

const std::error_code kQueueFull = std::make_error_code(std::errc::no_buffer_space);

class TransmitQueueFull : public test::FaultyWireSegment {
protected:
    TransmitQueueFull() { segment_.add(sim::ecat::make_drive_slave("fio", 11)); }
    void SetUp() override { bring_up(AlState::PreOp); }
};

TEST(TransmitQueueFullError, NamesTheErrorsOfAFullQueueAndNoOther) {
    EXPECT_TRUE(transmit_queue_full(std::make_error_code(std::errc::no_buffer_space)));
    EXPECT_TRUE(
        transmit_queue_full(std::make_error_code(std::errc::resource_unavailable_try_again)));
    EXPECT_FALSE(transmit_queue_full(std::make_error_code(std::errc::network_down)));
    EXPECT_FALSE(transmit_queue_full(std::make_error_code(std::errc::no_such_device)));
    EXPECT_FALSE(transmit_queue_full({}));
}

TEST_F(TransmitQueueFull, ABlockingCallSendsAgainAfterTwoFramesFoundNoRoom) {
    const std::uint64_t before = master_.stats().send_errors;
    link_.fail_sends(kQueueFull, 2); // three attempts: the third one leaves
    auto st = master_.read_al_status(0);
    ASSERT_TRUE(st) << master_.last_error();
    EXPECT_EQ(st->state, AlState::PreOp);
    EXPECT_EQ(master_.stats().send_errors - before, 2U);
}

TEST_F(TransmitQueueFull, ABlockingCallWhoseQueueStaysFullEndsWithASentence) {
    link_.fail_sends(kQueueFull);
    const TimePoint start = clock_.now();
    auto st = master_.read_al_status(0);
    ASSERT_FALSE(st);
    EXPECT_EQ(st.error(), kQueueFull);
    EXPECT_EQ(master_.last_error(),
              "cannot send on faulty wire: No buffer space available (the transmit queue was "
              "still full at the last of 3 attempts of 20.0 ms)");
    EXPECT_EQ(clock_.now() - start, milliseconds(60)) << "each attempt's time passes, no more";
}

TEST_F(TransmitQueueFull, AnInterfaceThatIsDownFailsABlockingCallAtOnce) {
    link_.fail_sends(std::make_error_code(std::errc::network_down));
    const TimePoint start = clock_.now();
    auto st = master_.read_al_status(0);
    ASSERT_FALSE(st);
    EXPECT_EQ(master_.last_error(), "cannot send on faulty wire: Network is down");
    EXPECT_EQ(clock_.now(), start);
}

TEST_F(TransmitQueueFull, AnSdoTransferWaitsForRoomAndCompletes) {
    const auto expected = master_.sdo_read<std::uint32_t>(0, 0x1018, 1);
    ASSERT_TRUE(expected) << master_.last_error();
    link_.fail_sends(kQueueFull, 5);
    auto got = master_.sdo_read<std::uint32_t>(0, 0x1018, 1);
    ASSERT_TRUE(got) << master_.last_error();
    EXPECT_EQ(*got, *expected);
    EXPECT_EQ(master_.stats().send_errors, 5U);
}

TEST_F(TransmitQueueFull, AnSdoTransferWhoseQueueStaysFullTimesOutCountingTheFramesNotSent) {
    link_.fail_sends(kQueueFull);
    const TimePoint start = clock_.now();
    auto got = master_.sdo_upload(0, 0x1018, 1);
    ASSERT_FALSE(got);
    EXPECT_EQ(got.error(), EcatErrc::MailboxTimeout);
    const std::string& sentence = master_.last_error();
    EXPECT_EQ(sentence.rfind("slave 0 (FIO Drive Control): CoE SDO upload 0x1018:01 timed out "
                             "after 1000 ms (",
                             0),
              0U)
        << sentence;
    EXPECT_NE(sentence.find("(request not sent; "), std::string::npos)
        << "no request frame left, so none was lost: " << sentence;
    EXPECT_NE(sentence.find(" of its frames could not be sent)"), std::string::npos) << sentence;
    EXPECT_LT(clock_.now() - start, milliseconds(1100)) << "the transfer's own timeout bounds it";
}

// A mailbox read whose first attempt found no room cannot have emptied SM1: unlike a read whose
// frame left and was lost, it asks the slave for no repeat (which would make it send its last
// message again).
TEST_F(TransmitQueueFull, AMailboxReadThatNeverLeftAsksForNoRepeat) {
    const std::uint64_t repeats = master_.mailbox_repeats();
    link_.fail_sends(kQueueFull, 1);
    master_.poll_mailboxes();
    EXPECT_EQ(master_.stats().send_errors, 1U) << "the poll's first read found no room";
    EXPECT_EQ(master_.mailbox_repeats(), repeats);
}

TEST_F(TransmitQueueFull, TheCycleGoesOnWithoutTheFrameAndSaysWhy) {
    ASSERT_TRUE(master_.set_state_all(AlState::Op)) << master_.last_error();
    link_.fail_sends(kQueueFull, 1);
    auto s = master_.send_process_data();
    ASSERT_FALSE(s);
    EXPECT_EQ(s.error(), kQueueFull);
    EXPECT_EQ(master_.last_error(),
              "cyclic LRW frame not sent on faulty wire: cannot send: No buffer space available");
    auto next = master_.exchange_process_data();
    EXPECT_TRUE(next || next.error() == EcatErrc::WorkingCounter) << master_.last_error();
    EXPECT_EQ(master_.stats().lost_frames, 0U) << "a frame that never left is not lost";
}

} // namespace
} // namespace codrive::ethercat
