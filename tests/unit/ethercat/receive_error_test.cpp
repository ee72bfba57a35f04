// SPDX-License-Identifier: Apache-2.0
// A receive that fails with an error of the link (ENETDOWN, say) rather than a timeout: the
// master gives the frame up like a lost one. The mailbox datagrams in it may have emptied a
// slave's SM1 on their way, so their channels ask for a repeat (ETG.1000.4 §6.7.2) instead of
// waiting for a message that is gone; the call reports the error with a sentence.
#include "faulty_wire_fixture.hpp"

#include <codrive/ethercat/error.hpp>

#include <gtest/gtest.h>

#include <optional>
#include <system_error>

namespace codrive::ethercat {
namespace {

const std::error_code kNetworkDown = std::make_error_code(std::errc::network_down);

class ReceiveError : public test::FaultyWireSegment {
protected:
    ReceiveError() {
        segment_.add(sim::ecat::make_drive_slave("fio", 11));
        segment_.add(sim::ecat::make_drive_slave("akd2g", 12));
    }
    void SetUp() override { bring_up(AlState::PreOp); }
    /// The slave's SM1 (its mailbox towards the master): an answered FPRD of it emptied it.
    [[nodiscard]] std::uint16_t sm1(std::size_t slave) const {
        return master_.slaves()[slave].sii.tx_mailbox_offset;
    }
    /// Queues an upload of `index`:`sub` whose outcome lands in `out`.
    void upload(std::size_t slave, std::uint16_t index, std::uint8_t sub,
                std::optional<CoeOutcome>& out) {
        ASSERT_TRUE(master_.sdo_upload_async(slave, index, sub, [&out](CoeOutcome o) {
            out = std::move(o);
        })) << master_.last_error();
    }
};

TEST_F(ReceiveError, TheCyclicFrameIsGivenUpAndTheMailboxAnswerInItIsAskedForAgain) {
    ASSERT_TRUE(master_.set_state_all(AlState::Op)) << master_.last_error();
    const ProcessDataStats start = master_.stats();
    const std::uint64_t repeats_before = master_.mailbox_repeats();
    std::optional<CoeOutcome> out;
    upload(0, 0x1018, 1, out);
    // The frame whose SM1 read took the slave's answer is never read: the socket fails.
    link_.fail_reads(sm1(0), 1, kNetworkDown);
    int errors = 0;
    std::string sentence;
    for (int cycle = 0; cycle < 200 && !out; ++cycle) {
        ASSERT_TRUE(master_.send_process_data()) << master_.last_error();
        auto r = master_.receive_process_data(clock_.now() + milliseconds(1));
        if (!r) {
            ++errors;
            EXPECT_EQ(r.error(), kNetworkDown) << "the link's own error, not NoResponse";
            sentence = master_.last_error();
        }
        clock_.advance(milliseconds(1));
    }
    ASSERT_EQ(link_.fail_reads_left(), 0) << "no frame carried an answered SM1 read";
    ASSERT_TRUE(out) << "the transfer did not end in 200 cycles";
    EXPECT_FALSE(out->error) << out->sentence;
    ASSERT_EQ(out->data.size(), 4U);
    EXPECT_EQ(get_le<std::uint32_t>(out->data.data()),
              *master_.sdo_read<std::uint32_t>(0, 0x1018, 1));
    EXPECT_EQ(errors, 1);
    EXPECT_NE(sentence.find("cannot receive"), std::string::npos) << sentence;
    EXPECT_NE(sentence.find("faulty wire"), std::string::npos) << sentence;
    EXPECT_EQ(master_.stats().receive_errors - start.receive_errors, 1U);
    EXPECT_EQ(master_.stats().lost_frames - start.lost_frames, 0U)
        << "a receive error is not a frame that failed to come back in time";
    EXPECT_GE(master_.mailbox_repeats() - repeats_before, 1U)
        << "the answer the failed frame took from SM1 came from a repeat";
}

TEST_F(ReceiveError, WhileSendsFailTimedOutTransfersStillEndOnTime) {
    ASSERT_TRUE(master_.set_state_all(AlState::Op)) << master_.last_error();
    std::optional<CoeOutcome> out;
    upload(0, 0x1018, 1, out);
    link_.fail_sends(kNetworkDown); // the interface goes down and stays down
    for (int cycle = 0; cycle < 1500 && !out; ++cycle) {
        // As the controller's cycle does: no wait for a frame that did not leave.
        auto s = master_.send_process_data();
        ASSERT_FALSE(s);
        EXPECT_EQ(s.error(), kNetworkDown);
        ASSERT_EQ(master_.last_error(),
                  "cyclic LRW frame not sent on faulty wire: cannot send: Network is down");
        clock_.advance(milliseconds(1));
    }
    ASSERT_TRUE(out) << "the transfer outlived its own timeout while the interface was down";
    EXPECT_TRUE(out->error);
    EXPECT_NE(out->sentence.find("slave 0 ("), std::string::npos) << out->sentence;
    EXPECT_NE(out->sentence.find("timed out"), std::string::npos) << out->sentence;
    EXPECT_EQ(master_.receive_process_data(clock_.now()).error(), EcatErrc::NotConfigured)
        << "no frame is awaited after a send that failed";
    link_.fail_sends({});
    auto back = master_.exchange_process_data();
    // The frame comes back; the FIO's SM watchdog ran out meanwhile, so its count may be short.
    EXPECT_TRUE(back || back.error() == EcatErrc::WorkingCounter) << master_.last_error();
}

TEST_F(ReceiveError, ALostFramesSentenceIsNotOverwrittenByACallbackItDelivers) {
    ASSERT_TRUE(master_.set_state_all(AlState::Op)) << master_.last_error();
    bool called = false;
    ASSERT_TRUE(master_.sdo_upload_async(0, 0x1018, 1, [&](CoeOutcome) {
        called = true;
        // Anything the callback does may leave a sentence of its own behind.
        EXPECT_FALSE(master_.sdo_upload_async(99, 0x1018, 1, [](CoeOutcome) {}));
    }));
    ASSERT_TRUE(master_.exchange_process_data()) << master_.last_error(); // the request goes
    clock_.advance(seconds(5)); // the transfer's time runs out before the next frame
    link_.garble_next(1);       // and that frame is lost
    ASSERT_TRUE(master_.send_process_data()) << master_.last_error();
    auto r = master_.receive_process_data(clock_.now() + milliseconds(1));
    ASSERT_FALSE(r);
    EXPECT_EQ(r.error(), EcatErrc::NoResponse);
    EXPECT_TRUE(called);
    EXPECT_EQ(master_.last_error().rfind("cyclic LRW frame lost on faulty wire", 0), 0U)
        << master_.last_error();
}

TEST_F(ReceiveError, AMailboxCycleThatFailsLosesNoOtherSlavesAnswer) {
    std::optional<CoeOutcome> long_one;
    std::optional<CoeOutcome> short_one;
    // Slave 0 reads its device name in segments, which keeps its channel busy; slave 1's
    // expedited answer is in the frame whose receive fails.
    upload(0, 0x1008, 0, long_one);
    upload(1, 0x1018, 1, short_one);
    link_.fail_reads(sm1(1), 1, kNetworkDown);
    master_.run_mailbox_until_idle(0);
    ASSERT_EQ(link_.fail_reads_left(), 0);
    ASSERT_TRUE(long_one);
    EXPECT_EQ(long_one->error, kNetworkDown) << "the caller's slave ends with the link's error";
    EXPECT_EQ(long_one->sentence.rfind("slave 0 (", 0), 0U) << long_one->sentence;
    EXPECT_NE(long_one->sentence.find("SDO upload 0x1008:00 failed: cannot receive on faulty wire"),
              std::string::npos)
        << long_one->sentence;
    EXPECT_FALSE(short_one) << "slave 1's transfer is not the caller's: it goes on";
    master_.run_mailbox_until_idle(1);
    ASSERT_TRUE(short_one);
    EXPECT_FALSE(short_one->error) << short_one->sentence;
    ASSERT_EQ(short_one->data.size(), 4U);
    EXPECT_EQ(get_le<std::uint32_t>(short_one->data.data()), 0x6AU) << "Kollmorgen";
    EXPECT_GE(master_.mailbox_repeats(), 1U);
}

} // namespace
} // namespace codrive::ethercat
