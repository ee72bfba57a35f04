// SPDX-License-Identifier: Apache-2.0
// Master::mailbox_read(), the blocking read outside cyclic operation: a read whose frame comes
// back after its deadline has emptied SM1 on its way, so the master asks the slave to send that
// message again (ETG.1000.4 §6.7.2) after every such read while the read has time left, as the
// cyclic mailbox channel does; the message is not lost however many reads in a row come late.
#include "faulty_wire_fixture.hpp"

#include <codrive/ethercat/error.hpp>

#include <gtest/gtest.h>

namespace codrive::ethercat {
namespace {

class BlockingMailboxRead : public test::FaultyWireSegment {
protected:
    BlockingMailboxRead() { segment_.add(sim::ecat::make_drive_slave("akd2g", 22)); }
    void SetUp() override { bring_up(AlState::PreOp); }
    /// An expedited SDO upload request of 1018h:01 (vendor ID) in SM0 (ETG.1000.6 §5.6.2.4).
    void ask_vendor_id() {
        MailboxMessage m;
        m.header.type = MailboxType::Coe;
        m.header.counter = 1;
        m.payload.assign(10, 0);
        put_le<std::uint16_t>(m.payload.data(), coe_header(CoeService::SdoRequest));
        m.payload[2] = 0x40; // initiate upload request
        put_le<std::uint16_t>(m.payload.data() + 3, 0x1018);
        m.payload[5] = 0x01;
        m.header.length = static_cast<std::uint16_t>(m.payload.size());
        ASSERT_TRUE(master_.mailbox_write(0, m)) << master_.last_error();
    }
};

TEST_F(BlockingMailboxRead, SixLateReadsInARowStillBringTheAnswer) {
    ask_vendor_id();
    link_.delay_reads(master_.slaves()[0].sii.tx_mailbox_offset, 6);
    const std::uint64_t repeats_before = master_.mailbox_repeats();
    auto m = master_.mailbox_read(0, milliseconds(500));
    ASSERT_TRUE(m) << master_.last_error();
    EXPECT_EQ(link_.held(), 6);
    EXPECT_EQ(master_.mailbox_repeats() - repeats_before, 6U) << "one repeat per late read";
    ASSERT_GE(m->payload.size(), 10U);
    EXPECT_EQ(m->payload[2], 0x43) << "expedited upload response, 4 bytes";
    EXPECT_EQ(get_le<std::uint32_t>(m->payload.data() + 6), 0x6AU) << "Kollmorgen";
    EXPECT_EQ(master_.stats().late_other_frames, 6U) << "late, but no cyclic frame was lost";
    EXPECT_EQ(master_.stats().late_frames, 0U);
    EXPECT_EQ(master_.stats().unreadable_frames, 0U);
}

TEST_F(BlockingMailboxRead, RepeatsAfterTheDeadlineAreCountedInTheMinimumNotAdded) {
    // frame_retries (3) repeats at least, in all: a 30 ms read has time for one late read
    // (20 ms frame timeout) and its repeat, then gets two more, not three more (each repeat
    // may wait up to mailbox_timeout for its acknowledge, so "three more" after the deadline
    // could hold a short read for seconds).
    ask_vendor_id();
    link_.delay_reads(master_.slaves()[0].sii.tx_mailbox_offset, 1000);
    const std::uint64_t repeats_before = master_.mailbox_repeats();
    auto m = master_.mailbox_read(0, milliseconds(30));
    ASSERT_FALSE(m);
    EXPECT_EQ(master_.mailbox_repeats() - repeats_before, 3U);
}

TEST_F(BlockingMailboxRead, APollWithNoTimeLeftStillAsksAgainAFewTimes) {
    // poll_mailboxes() reads with a zero timeout: it still repeats up to frame_retries times,
    // so one late frame does not lose a message the slave already sent.
    ask_vendor_id();
    link_.delay_reads(master_.slaves()[0].sii.tx_mailbox_offset, 1);
    auto m = master_.mailbox_read(0, Duration::zero());
    ASSERT_TRUE(m) << master_.last_error();
    EXPECT_EQ(link_.held(), 1);
}

TEST_F(BlockingMailboxRead, ALostAnswerAfterTheDeadlineIsATimeoutNamingTheSlave) {
    ask_vendor_id();
    // More late reads than a 20 ms read has time for: each costs a frame timeout and a repeat.
    link_.delay_reads(master_.slaves()[0].sii.tx_mailbox_offset, 1000);
    auto m = master_.mailbox_read(0, milliseconds(20));
    ASSERT_FALSE(m);
    EXPECT_EQ(m.error(), EcatErrc::MailboxTimeout);
    EXPECT_NE(master_.last_error().find("slave 0"), std::string::npos) << master_.last_error();
    EXPECT_LT(link_.held(), 1000);
}

} // namespace
} // namespace codrive::ethercat
