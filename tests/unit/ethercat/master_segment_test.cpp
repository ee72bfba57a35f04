// SPDX-License-Identifier: Apache-2.0
// The master against simulated slaves in-process (FakeClock, no sockets): bring-up, ESM,
// CoE SDO transfers, SDO information, emergencies, process data, faults and DC.
#include <codrive/ethercat/registers.hpp>
#include <codrive/testing/sim_segment.hpp>

#include <codrive/core/sdo_abort.hpp>

#include <gtest/gtest.h>

namespace codrive::ethercat {
namespace {

using sim::ecat::make_drive_slave;
using sim::ecat::SegmentLink;

class EcatMasterSegment : public codrive::testing::SimSegmentTest {
protected:
    EcatMasterSegment() {
        segment_.add(make_drive_slave("fio", 11));
        segment_.add(make_drive_slave("akd2g", 22));
        segment_.add(make_drive_slave("ds-bvs", 33));
    }
    void scan() { ASSERT_TRUE(master_.scan()) << master_.last_error(); }
};

TEST_F(EcatMasterSegment, ScanCountsSlavesAssignsAddressesAndReadsIdentityFromSii) {
    scan();
    ASSERT_EQ(master_.slaves().size(), 3U);
    const auto& s = master_.slaves();
    EXPECT_EQ(s[0].sii.vendor_id, 0x0048554BU);
    EXPECT_EQ(s[0].sii.product_code, 0x0002BA67U);
    EXPECT_EQ(s[0].sii.serial, 11U);
    EXPECT_EQ(s[1].sii.vendor_id, 0x6AU);
    EXPECT_EQ(s[1].display_name(), "AKD2G");
    EXPECT_EQ(s[2].display_name(), "DS-BVS");
    EXPECT_EQ(s[2].station_address, 0x1003);
    EXPECT_EQ(segment_.slave(2).station_address(), 0x1003);
    EXPECT_EQ(s[0].sii.rx_mailbox_size, 128);
    EXPECT_TRUE(s[0].sii.has_coe());
    EXPECT_TRUE(s[0].has_dc);
    EXPECT_EQ(s[1].state, AlState::Init);
}

/// The segment's wire, with the first answer's first working counter overwritten: the broadcast
/// read that counts the slaves comes back with a count the segment does not have.
class MiscountingLink final : public IEcatLink {
public:
    MiscountingLink(SegmentLink& inner, std::uint16_t count) : inner_(inner), count_(count) {}
    VoidResult send(std::span<const std::uint8_t> frame) override { return inner_.send(frame); }
    Result<std::size_t> receive(std::span<std::uint8_t> buffer, TimePoint deadline) override {
        auto got = inner_.receive(buffer, deadline);
        // Ethernet header (14), EtherCAT header (2), datagram header (10), 2 data bytes: wkc.
        if (got && !done_ && *got >= 30 && buffer[16] == 0x07) {
            buffer[28] = static_cast<std::uint8_t>(count_);
            buffer[29] = static_cast<std::uint8_t>(count_ >> 8);
            done_ = true;
        }
        return got;
    }
    void idle(Duration d) override { inner_.idle(d); }
    [[nodiscard]] std::string name() const override { return "eth9"; }

private:
    SegmentLink& inner_;
    std::uint16_t count_;
    bool done_ = false;
};

TEST_F(EcatMasterSegment, ACountPastTheEndOfTheSegmentIsNamedWithThePositionThatDoesNotAnswer) {
    MiscountingLink wire(link_, 5);
    Master master(wire, clock_);
    auto scanned = master.scan();
    ASSERT_FALSE(scanned);
    EXPECT_EQ(scanned.error(), EcatErrc::WorkingCounter);
    EXPECT_EQ(master.last_error(),
              "the broadcast read on eth9 counted 5 slaves, but position 3 does not answer: a "
              "slave left the segment during the scan or the count was corrupted");
    EXPECT_TRUE(master.slaves().empty());
}

TEST_F(EcatMasterSegment, ACountAboveMaxSlavesIsRefusedBeforeAnyPositionIsProbed) {
    MiscountingLink wire(link_, 48879);
    Master master(wire, clock_);
    link_.record(true);
    auto scanned = master.scan();
    ASSERT_FALSE(scanned);
    EXPECT_NE(master.last_error().find("counted 48879 slaves, more than the 512 this master "
                                       "accepts (MasterConfig::max_slaves)"),
              std::string::npos)
        << master.last_error();
    EXPECT_EQ(link_.sent().size(), 1U); // the broadcast read alone, not 764 probing frames
}

TEST_F(EcatMasterSegment, ScanReportsTheStateThePreviousMasterLeftBeforeResettingToInit) {
    bring_up(AlState::Op);
    ASSERT_TRUE(master_.exchange_process_data()) << master_.last_error();
    // The previous master stops: after 100 ms without outputs the SM watchdog of every slave
    // expires (SAFE-OP + error flag; 0x001B, the AKD2G writes no code).
    clock_.advance(milliseconds(50));
    for (std::size_t i = 0; i < segment_.size(); ++i) {
        segment_.slave(i).tick(clock_.now());
    }
    clock_.advance(milliseconds(120));
    for (std::size_t i = 0; i < segment_.size(); ++i) {
        EXPECT_TRUE(segment_.slave(i).tick(clock_.now())) << i;
    }
    // The old master, had it come back, would see a short working counter (inputs only) and
    // the reason in words.
    auto wkc = master_.exchange_process_data();
    ASSERT_FALSE(wkc);
    EXPECT_EQ(master_.diagnose_wkc(3),
              "cyclic LRW working counter 3, expected 9: slave 0 (FIO Drive Control) is in "
              "SAFE-OP with AL status code 0x001B (sync manager watchdog); slave 1 (AKD2G) is in "
              "SAFE-OP with AL status code 0x0000 (no error); slave 2 (DS-BVS) is in "
              "SAFE-OP with AL status code 0x001B (sync manager watchdog)");
    Master next{link_, clock_};
    ASSERT_TRUE(next.scan()) << next.last_error();
    for (const auto& s : next.slaves()) {
        EXPECT_EQ(s.found_state, AlState::SafeOp) << s.position;
        EXPECT_TRUE(s.found_error) << s.position;
        // The AKD2G reports no code but 0x0011 and 0x0017 (manual §3.1, "No other codes are
        // supported"): it leaves OP with the error flag and code 0x0000.
        EXPECT_EQ(s.found_code, s.position == 1 ? 0x0000 : 0x001B) << s.position;
        EXPECT_EQ(s.state, AlState::Init) << "scan resets every slave to INIT";
    }
    // A clean segment is found in INIT without an error.
    Master third{link_, clock_};
    ASSERT_TRUE(third.scan()) << third.last_error();
    EXPECT_EQ(third.slaves()[0].found_state, AlState::Init);
    EXPECT_FALSE(third.slaves()[0].found_error);
}

TEST_F(EcatMasterSegment, StateMachineReachesOpThroughEveryState) {
    bring_up(AlState::Op);
    for (std::size_t i = 0; i < segment_.size(); ++i) {
        EXPECT_EQ(segment_.slave(i).state(), AlState::Op);
        EXPECT_EQ(master_.slaves()[i].state, AlState::Op);
    }
    ASSERT_TRUE(master_.set_state_all(AlState::Init)) << master_.last_error();
    EXPECT_EQ(segment_.slave(1).state(), AlState::Init);
}

TEST_F(EcatMasterSegment, DirectJumpFromInitToOpIsRefusedWithAlStatusText) {
    scan();
    auto r = master_.request_state(0, AlState::Op);
    ASSERT_FALSE(r);
    EXPECT_EQ(r.error(), EcatErrc::StateChangeRefused);
    EXPECT_EQ(master_.last_error(),
              "slave 0 (FIO Drive Control): state change INIT → OP refused with AL status code "
              "0x0011 (invalid requested state change); the slave stays in INIT");
    // The error was acknowledged: a valid request now succeeds.
    EXPECT_TRUE(master_.request_state(0, AlState::PreOp)) << master_.last_error();
}

TEST_F(EcatMasterSegment, RefusedSafeOpReportsTheSlavesAlStatusCode) {
    scan();
    segment_.slave(1).faults().refuse[AlState::SafeOp] = al_code::kInvalidDcSyncConfig;
    auto r = master_.set_state_all(AlState::Op);
    ASSERT_FALSE(r);
    EXPECT_NE(master_.last_error().find("slave 1 (AKD2G): state change PRE-OP → SAFE-OP refused "
                                        "with AL status code 0x0030 (invalid DC SYNC "
                                        "configuration)"),
              std::string::npos)
        << master_.last_error();
}

TEST_F(EcatMasterSegment, SafeOpIsRefusedWhenSyncManagerLengthsDoNotMatchTheMapping) {
    scan();
    ASSERT_TRUE(master_.set_state_all(AlState::PreOp));
    // Program SM2 with a wrong length by hand.
    SyncManager sm2;
    sm2.start = 0x1100;
    sm2.length = 3;
    sm2.control = 0x64;
    sm2.activate = 1;
    ASSERT_TRUE(master_.write_registers(0, reg::sm(2), sm2.encode()));
    auto r = master_.request_state(0, AlState::SafeOp);
    ASSERT_FALSE(r);
    EXPECT_NE(master_.last_error().find("0x001D (invalid output configuration)"),
              std::string::npos);
}

TEST_F(EcatMasterSegment, ExpeditedUploadReadsIdentity) {
    scan();
    ASSERT_TRUE(master_.set_state_all(AlState::PreOp));
    auto vendor = master_.sdo_read<std::uint32_t>(1, 0x1018, 1);
    ASSERT_TRUE(vendor) << master_.last_error();
    EXPECT_EQ(*vendor, 0x6AU);
    auto serial = master_.sdo_read<std::uint32_t>(2, 0x1018, 4);
    ASSERT_TRUE(serial);
    EXPECT_EQ(*serial, 33U);
}

TEST_F(EcatMasterSegment, NormalUploadReadsDeviceName) {
    scan();
    ASSERT_TRUE(master_.set_state_all(AlState::PreOp));
    auto name = master_.sdo_upload(0, 0x1008, 0);
    ASSERT_TRUE(name) << master_.last_error();
    EXPECT_EQ(std::string(name->begin(), name->end()), "FIO Drive Control");
}

TEST_F(EcatMasterSegment, SegmentedDownloadAndUploadRoundTripALongString) {
    scan();
    ASSERT_TRUE(master_.set_state_all(AlState::PreOp));
    std::string text;
    for (int i = 0; i < 40; ++i) {
        text += "segment-" + std::to_string(i) + ";";
    }
    ASSERT_GT(text.size(), 300U);
    const std::vector<std::uint8_t> bytes(text.begin(), text.end());
    ASSERT_TRUE(master_.sdo_download(2, sim::ecat::kScratchStringIndex, 0, bytes))
        << master_.last_error();
    auto back = master_.sdo_upload(2, sim::ecat::kScratchStringIndex, 0);
    ASSERT_TRUE(back) << master_.last_error();
    EXPECT_EQ(std::string(back->begin(), back->end()), text);
}

TEST_F(EcatMasterSegment, AbortCodeComesBackAsSharedSdoAbortWithSentence) {
    scan();
    ASSERT_TRUE(master_.set_state_all(AlState::PreOp));
    auto r = master_.sdo_upload(0, 0x2345, 7);
    ASSERT_FALSE(r);
    EXPECT_EQ(r.error(), SdoAbort::NoObject);
    EXPECT_EQ(master_.last_error(), "slave 0 (FIO Drive Control): SDO upload 0x2345:07 aborted "
                                    "0x06020000 (" +
                                        std::string(sdo_abort_describe(0x06020000)) + ")");
    auto w = master_.sdo_write<std::uint32_t>(1, 0x1018, 1, 5);
    ASSERT_FALSE(w);
    EXPECT_EQ(w.error(), SdoAbort::ReadOnly);
}

TEST_F(EcatMasterSegment, CompleteAccessReadsAWholeRecord) {
    scan();
    ASSERT_TRUE(master_.set_state_all(AlState::PreOp));
    auto r = master_.sdo_upload(0, 0x1018, 0, true);
    ASSERT_TRUE(r) << master_.last_error();
    // Sub 0 padded to 16 bits (ETG.1000.6 §5.6.2.1; ESI: sub 1 at bit offset 16), then 1..4.
    ASSERT_EQ(r->size(), 2U + 4 * 4);
    EXPECT_EQ((*r)[0], 4);
    EXPECT_EQ((*r)[1], 0);
    EXPECT_EQ(get_le<std::uint32_t>(r->data() + 2), 0x0048554BU);
    EXPECT_EQ(get_le<std::uint32_t>(r->data() + 14), 11U);
    // From sub 1: the entries alone, no sub 0.
    auto from1 = master_.sdo_upload(0, 0x1018, 1, true);
    ASSERT_TRUE(from1) << master_.last_error();
    ASSERT_EQ(from1->size(), 4U * 4);
    EXPECT_EQ(get_le<std::uint32_t>(from1->data()), 0x0048554BU);
}

TEST_F(EcatMasterSegment, PdoAssignmentIsPreOpOnlyAndConfigurable) {
    scan();
    ASSERT_TRUE(master_.set_state_all(AlState::PreOp));
    // FIO: map only controlword + target velocity, status + velocity.
    std::vector<PdoMapping> rx{{0x1601, {{0x6040, 0, 16}, {0x60FF, 0, 32}}}};
    std::vector<PdoMapping> tx{{0x1A01, {{0x6041, 0, 16}, {0x606C, 0, 32}}}};
    ASSERT_TRUE(master_.configure_pdos(0, rx, tx)) << master_.last_error();
    auto a = master_.read_pdo_assignment(0);
    ASSERT_TRUE(a);
    ASSERT_EQ(a->first.size(), 1U);
    EXPECT_EQ(a->first[0].index, 0x1601);
    EXPECT_EQ(a->first[0].bits(), 48U);
    ASSERT_TRUE(master_.set_state_all(AlState::SafeOp)) << master_.last_error();
    EXPECT_EQ(master_.slaves()[0].output_bytes, 6);
    EXPECT_EQ(master_.slaves()[0].input_bytes, 6);
    auto w = master_.sdo_write<std::uint8_t>(0, 0x1C12, 0, 0);
    ASSERT_FALSE(w);
    EXPECT_EQ(w.error(), SdoAbort::DataTransferState);
}

TEST_F(EcatMasterSegment, SdoInformationListsObjectsAndDescribesEntries) {
    scan();
    ASSERT_TRUE(master_.set_state_all(AlState::PreOp));
    auto list = master_.sdo_info_object_list(1);
    ASSERT_TRUE(list) << master_.last_error();
    EXPECT_GT(list->size(), 40U); // several fragments at 128-byte mailboxes
    EXPECT_NE(std::find(list->begin(), list->end(), 0x6041), list->end());
    auto obj = master_.sdo_info_object(1, 0x1018);
    ASSERT_TRUE(obj);
    EXPECT_EQ(obj->name, "Identity object");
    EXPECT_EQ(obj->max_subindex, 4);
    auto entry = master_.sdo_info_entry(1, 0x6041, 0);
    ASSERT_TRUE(entry);
    EXPECT_EQ(entry->name, "Statusword");
    EXPECT_EQ(entry->bit_length, 16);
    EXPECT_NE(entry->access & 0x0080, 0); // TxPDO mappable
    auto missing = master_.sdo_info_object(1, 0x7777);
    ASSERT_FALSE(missing);
    EXPECT_EQ(missing.error(), SdoAbort::NoObject);
}

TEST_F(EcatMasterSegment, MailboxTimeoutIsASentenceNamingSlaveAndObject) {
    scan();
    ASSERT_TRUE(master_.set_state_all(AlState::PreOp));
    segment_.slave(2).faults().mailbox_silent = true;
    master_.config().mailbox_timeout = milliseconds(50);
    const auto before = clock_.now();
    auto r = master_.sdo_upload(2, 0x1018, 1);
    ASSERT_FALSE(r);
    EXPECT_EQ(r.error(), EcatErrc::MailboxTimeout);
    EXPECT_EQ(master_.last_error(), "slave 2 (DS-BVS): CoE SDO upload 0x1018:01 timed out after 50 "
                                    "ms (mailbox silent)");
    EXPECT_GE(clock_.now() - before, milliseconds(50));
}

TEST_F(EcatMasterSegment, LostFramesAreRetried) {
    scan();
    link_.drop_next(2);
    auto st = master_.read_al_status(1);
    ASSERT_TRUE(st) << master_.last_error();
    EXPECT_EQ(st->state, AlState::Init);
    link_.drop_next(10);
    auto lost = master_.read_al_status(1);
    ASSERT_FALSE(lost);
    EXPECT_EQ(lost.error(), EcatErrc::NoResponse);
    EXPECT_NE(master_.last_error().find("no EtherCAT frame came back"), std::string::npos);
}

TEST_F(EcatMasterSegment, LostMailboxAnswerIsRecoveredWithTheRepeatRequest) {
    scan();
    ASSERT_TRUE(master_.set_state_all(AlState::PreOp));
    // The frame that read the SDO answer out of SM1 is lost on its way back: without the
    // repeat protocol the answer is gone and the upload times out.
    link_.lose_mailbox_answers(1, 1);
    auto vendor = master_.sdo_read<std::uint32_t>(1, 0x1018, 1);
    ASSERT_TRUE(vendor) << master_.last_error();
    EXPECT_EQ(*vendor, 0x6AU);
    EXPECT_EQ(master_.mailbox_repeats(), 1U);
    EXPECT_EQ(segment_.slave(1).mailbox_repeats(), 1U);
    // Every segment answer of a segmented upload lost once.
    std::string text;
    for (int i = 0; i < 20; ++i) {
        text += "repeat request toggles|";
    }
    ASSERT_TRUE(
        master_.sdo_download(1, 0x5FFF, 0, std::vector<std::uint8_t>(text.begin(), text.end())))
        << master_.last_error();
    link_.lose_mailbox_answers(1, 4);
    auto back = master_.sdo_upload(1, 0x5FFF, 0);
    ASSERT_TRUE(back) << master_.last_error();
    EXPECT_EQ(std::string(back->begin(), back->end()), text);
    EXPECT_EQ(master_.mailbox_repeats(), 5U);
}

TEST_F(EcatMasterSegment, RepeatAfterAFrameLostOnTheWayOutDropsTheDuplicate) {
    scan();
    ASSERT_TRUE(master_.set_state_all(AlState::PreOp));
    ASSERT_TRUE(master_.sdo_read<std::uint32_t>(0, 0x1018, 2)) << master_.last_error();
    // The next mailbox read is lost before it reaches the slave, SM1 being empty: the master
    // cannot tell that from a lost answer, so it asks for a repeat; the slave writes its last
    // message again, which the master already has (same counter) and drops.
    link_.drop_next(1);
    auto m = master_.mailbox_read(0, milliseconds(10));
    ASSERT_FALSE(m);
    EXPECT_EQ(m.error(), EcatErrc::MailboxTimeout);
    EXPECT_EQ(master_.mailbox_repeats(), 1U);
    EXPECT_EQ(segment_.slave(0).mailbox_repeats(), 1U);
    auto product = master_.sdo_read<std::uint32_t>(0, 0x1018, 2);
    ASSERT_TRUE(product) << master_.last_error();
    EXPECT_EQ(*product, 0x0002BA67U);
}

TEST_F(EcatMasterSegment, CyclicLrwKeepsTheExpectedWorkingCounterAndMovesTheDrive) {
    bring_up(AlState::Op);
    EXPECT_EQ(master_.expected_wkc(), 9);
    // FIO outputs: 6040 (2) 607A (4) 3202 (4) 6060 (1); inputs 6041 (2) 6064 (4) 6061 (1).
    auto out = master_.outputs(0);
    ASSERT_EQ(out.size(), 11U);
    const std::array<std::uint16_t, 4> cws{0x06, 0x07, 0x0F, 0x0F};
    for (std::uint16_t cw : cws) {
        put_le<std::uint16_t>(out.data(), cw);
        out[10] = 8; // CSP
        for (int i = 0; i < 3; ++i) {
            auto w = master_.exchange_process_data();
            ASSERT_TRUE(w) << master_.last_error();
        }
    }
    EXPECT_EQ(get_le<std::uint16_t>(master_.inputs(0).data()) & 0x6F, 0x27); // operation enabled
    for (int i = 1; i <= 1000; ++i) {
        put_le<std::int32_t>(out.data() + 2, i * 10);
        auto w = master_.exchange_process_data();
        ASSERT_TRUE(w) << master_.last_error();
        EXPECT_EQ(*w, 9);
        clock_.advance(microseconds(1000));
    }
    EXPECT_EQ(master_.stats().wkc_errors, 0U);
    // The simulated drive (sim DriveCore) follows the CSP targets; inputs lag one cycle.
    for (int i = 0; i < 50; ++i) {
        ASSERT_TRUE(master_.exchange_process_data());
        clock_.advance(microseconds(1000));
    }
    EXPECT_NEAR(get_le<std::int32_t>(master_.inputs(0).data() + 2), 10000, 100);
}

// A slave whose SM watchdog expired drops to SAFE-OP + 0x001B by itself; set_state_all(OP)
// reads every slave's AL status instead of trusting the states it set, acknowledges the error
// and brings that slave back (ETG.1000.6 §6.4.1.3), the others staying in OP.
TEST_F(EcatMasterSegment, SetStateAllBringsASlaveThatFellToSafeOpBackToOp) {
    bring_up(AlState::Op);
    ASSERT_TRUE(master_.exchange_process_data()) << master_.last_error();
    clock_.advance(milliseconds(150)); // no process data for 150 ms: only slave 1 notices
    ASSERT_TRUE(segment_.slave(1).tick(clock_.now()));
    ASSERT_EQ(segment_.slave(1).state(), AlState::SafeOp);
    EXPECT_EQ(master_.slaves()[1].state, AlState::Op) << "the cache does not know yet";
    ASSERT_FALSE(master_.exchange_process_data());
    ASSERT_TRUE(master_.set_state_all(AlState::Op)) << master_.last_error();
    for (std::size_t i = 0; i < segment_.size(); ++i) {
        EXPECT_EQ(segment_.slave(i).state(), AlState::Op) << i;
        EXPECT_EQ(master_.slaves()[i].state, AlState::Op) << i;
    }
    auto w = master_.exchange_process_data();
    ASSERT_TRUE(w) << master_.last_error();
    EXPECT_EQ(*w, 9);
}

TEST_F(EcatMasterSegment, SilentSlaveDropsTheWorkingCounterAndIsNamed) {
    bring_up(AlState::Op);
    segment_.slave(1).faults().silent = true;
    auto w = master_.exchange_process_data();
    ASSERT_FALSE(w);
    EXPECT_EQ(w.error(), EcatErrc::WorkingCounter);
    EXPECT_EQ(master_.stats().wkc_errors, 1U);
    EXPECT_EQ(master_.diagnose_wkc(6),
              "cyclic LRW working counter 6, expected 9: slave 1 (AKD2G) does not answer");
}

TEST_F(EcatMasterSegment, CoeEmergencyIsDecodedByTheEmcyModule) {
    scan();
    ASSERT_TRUE(master_.set_state_all(AlState::PreOp));
    std::vector<std::string> seen;
    master_.on_emergency([&](std::size_t slave, const emcy::EmcyMessage& m) {
        seen.push_back(master_.describe_emergency(slave, m));
    });
    segment_.slave(0).app().inject_fault(0x2310);
    // The emergency waits in SM1; an SDO transfer in between must not lose it.
    auto v = master_.sdo_read<std::uint16_t>(0, 0x603F, 0);
    ASSERT_TRUE(v) << master_.last_error();
    EXPECT_EQ(*v, 0x2310);
    master_.poll_mailboxes();
    ASSERT_EQ(seen.size(), 1U);
    EXPECT_EQ(seen[0].rfind("slave 0 (FIO Drive Control): EMCY 0x2310 ", 0), 0U) << seen[0];
}

TEST_F(EcatMasterSegment, PollingMailboxesReadsABoundedNumberPerCallAndLosesNoEmergency) {
    scan();
    ASSERT_TRUE(master_.set_state_all(AlState::PreOp));
    std::vector<std::uint16_t> codes;
    master_.on_emergency([&](std::size_t slave, const emcy::EmcyMessage& m) {
        EXPECT_EQ(slave, 0U);
        codes.push_back(m.error_code);
    });
    // More emergencies than one call reads: the caller gets control back after each batch.
    constexpr std::size_t kLimit = Master::kPolledMessagesPerSlave;
    constexpr std::size_t kFaults = 2 * kLimit + 3;
    for (std::size_t i = 0; i < kFaults; ++i) {
        segment_.slave(0).app().inject_fault(static_cast<std::uint16_t>(0x2310 + i));
    }
    ASSERT_TRUE(master_.read_al_status(0)); // a frame passes: the slave queues them for SM1
    EXPECT_EQ(master_.poll_mailboxes(), kLimit);
    EXPECT_EQ(master_.poll_mailboxes(), kLimit);
    EXPECT_EQ(master_.poll_mailboxes(), 3U);
    EXPECT_EQ(master_.poll_mailboxes(), 0U);
    ASSERT_EQ(codes.size(), kFaults);
    for (std::size_t i = 0; i < kFaults; ++i) {
        EXPECT_EQ(codes[i], 0x2310 + i) << "emergency " << i;
    }
}

// ETG.1000.4 §6.7.2: a repeat toggles the request bit of SM1's activate byte. Only that bit comes
// from the read: a corrupted read (0x44, 0x88 in fuzz_slave_replies' reproducers) must not
// switch the sync manager off or set latch bits.
TEST(SyncManagerRepeat, TheRequestTogglesAndTheSmStaysEnabledWhateverWasRead) {
    EXPECT_EQ(SyncManager::repeat_request_after(0x01), 0x03);
    EXPECT_EQ(SyncManager::repeat_request_after(0x03), 0x01);
    EXPECT_EQ(SyncManager::repeat_request_after(0x44), 0x03);
    EXPECT_EQ(SyncManager::repeat_request_after(0x88), 0x03);
    EXPECT_EQ(SyncManager::repeat_request_after(0xC2), 0x01);
}

TEST_F(EcatMasterSegment, DistributedClocksAlignSystemTimes) {
    scan();
    ASSERT_TRUE(master_.configure_dc()) << master_.last_error();
    auto st = master_.dc_status();
    ASSERT_TRUE(st) << master_.last_error();
    ASSERT_EQ(st->size(), 3U);
    for (const auto& s : *st) {
        EXPECT_LT(std::llabs(s.offset_to_reference), 2000) << "slave " << s.position;
    }
    EXPECT_EQ((*st)[2].delay, 1000U); // two hops of 500 ns in the model
    ASSERT_TRUE(master_.configure_sync0(1, microseconds(1000)));
    EXPECT_TRUE(segment_.slave(1).sync0_active());
}

} // namespace
} // namespace codrive::ethercat
