// SPDX-License-Identifier: Apache-2.0
// The simulated AKD2G EtherCAT slave against its manual, through the master in-process
// (FakeClock): both axes' objects, the fixed and default PDO maps, flexible mapping with
// padding, the sync managers' addresses and the only AL status codes the drive reports.
#include <codrive/ethercat/registers.hpp>
#include <codrive/sim/sim_device.hpp>
#include <codrive/testing/sim_segment.hpp>

#include <codrive/core/sdo_abort.hpp>

#include <gtest/gtest.h>

namespace codrive::ethercat {
namespace {

using sim::ecat::make_drive_slave;

class Akd2gSlave : public codrive::testing::SimSegmentTest {
protected:
    Akd2gSlave() { segment_.add(make_drive_slave("akd2g", 7)); }
    std::uint32_t u32(std::uint16_t index, std::uint8_t sub) {
        auto r = master_.sdo_read<std::uint32_t>(0, index, sub);
        EXPECT_TRUE(r) << master_.last_error();
        return r.value_or(0);
    }
};

TEST_F(Akd2gSlave, MailboxesSitAtTheManualsAddresses) {
    ASSERT_TRUE(master_.scan()) << master_.last_error();
    const auto& sii = master_.slaves()[0].sii;
    EXPECT_EQ(sii.rx_mailbox_offset, 0x1800); // §3.3 Mail Out buffer
    EXPECT_EQ(sii.tx_mailbox_offset, 0x1C00); // §3.3 Mail In buffer
    EXPECT_EQ(sii.product_code, 0x11210100U); // two axes (1018h:02 bits 23..20)
}

TEST_F(Akd2gSlave, BothAxesObjectsAndMapsFollowTheManual) {
    bring_up(AlState::PreOp);
    // Axis 2's objects at +800h: 6860h exists (the error codrive run used to stop at).
    ASSERT_TRUE(master_.sdo_write<std::int8_t>(0, 0x6860, 0, 8)) << master_.last_error();
    // Defaults (§3.11.2): 1600h/1A00h axis 1, 1601h/1A01h axis 2, both assigned.
    EXPECT_EQ(u32(0x1601, 1), 0x68400010U);
    EXPECT_EQ(u32(0x1601, 2), 0x687A0020U);
    EXPECT_EQ(u32(0x1A01, 3), 0x68F40020U);
    auto assignment = master_.read_pdo_assignment(0);
    ASSERT_TRUE(assignment) << master_.last_error();
    ASSERT_EQ(assignment->first.size(), 2U);
    EXPECT_EQ(assignment->first[1].index, 0x1601);
    ASSERT_EQ(assignment->second.size(), 2U);
    EXPECT_EQ(assignment->second[1].index, 0x1A01);
    // Fixed maps (§5.2.21-§5.2.46): drive maps, per axis, axis 2 at +20h.
    EXPECT_EQ(u32(0x1620, 1), 0x36010120U);
    EXPECT_EQ(u32(0x1A20, 1), 0x35800020U);
    EXPECT_EQ(u32(0x1704, 1), 0x60B80010U);
    EXPECT_EQ(u32(0x1722, 2), 0x68710010U);
    EXPECT_EQ(u32(0x1B06, 1), 0x60FD0020U);
    EXPECT_EQ(u32(0x1B21, 3), 0x686C0020U);
    EXPECT_EQ(u32(0x1B25, 2), 0x68BD0020U);
    // Fixed maps are read-only.
    EXPECT_FALSE(master_.sdo_write<std::uint8_t>(0, 0x1700, 0, 0));
}

TEST_F(Akd2gSlave, FlexibleMappingTakesPaddingAndRefusesWhatCannotBeMapped) {
    bring_up(AlState::PreOp);
    ASSERT_TRUE(master_.sdo_write<std::uint8_t>(0, 0x1602, 0, 0)) << master_.last_error();
    // §3.11.1: index 0000h with a length of whole bytes is padding; 4 bits is not.
    EXPECT_TRUE(master_.sdo_write<std::uint32_t>(0, 0x1602, 1, 0x68400010));
    EXPECT_TRUE(master_.sdo_write<std::uint32_t>(0, 0x1602, 2, 0x00000010));
    auto r = master_.sdo_write<std::uint32_t>(0, 0x1602, 3, 0x00000004);
    ASSERT_FALSE(r);
    EXPECT_EQ(r.error(), SdoAbort::NotMappable);
    // The statusword is an input: it cannot go into an RxPDO.
    r = master_.sdo_write<std::uint32_t>(0, 0x1602, 3, 0x60410010);
    ASSERT_FALSE(r);
    EXPECT_EQ(r.error(), SdoAbort::NotMappable);
    EXPECT_TRUE(master_.sdo_write<std::uint32_t>(0, 0x1602, 3, 0x687A0020));
    ASSERT_TRUE(master_.sdo_write<std::uint8_t>(0, 0x1602, 0, 3)) << master_.last_error();
    // Entries change only while sub 0 is 0.
    r = master_.sdo_write<std::uint32_t>(0, 0x1602, 1, 0x60400010);
    ASSERT_FALSE(r);
    EXPECT_EQ(r.error(), SdoAbort::DataTransferState);
    // The padded map as the only RxPDO: 2 + 2 + 4 bytes, and the slave reaches SAFE-OP.
    std::vector<PdoMapping> rx{{0x1602, {}}};
    std::vector<PdoMapping> tx{{0x1B20, {}}};
    ASSERT_TRUE(master_.configure_pdos(0, rx, tx)) << master_.last_error();
    ASSERT_TRUE(master_.set_state_all(AlState::SafeOp)) << master_.last_error();
    EXPECT_EQ(master_.slaves()[0].output_bytes, 8);
    EXPECT_EQ(master_.slaves()[0].input_bytes, 10);
}

TEST_F(Akd2gSlave, ReportsOnlyTheAlStatusCodesOfItsManual) {
    bring_up(AlState::PreOp);
    // A wrong SM2 length: ETG.1000.6 would say 0x001D; the AKD2G says 0x0017 (§3.1).
    SyncManager sm2;
    sm2.start = 0x1100;
    sm2.length = 3;
    sm2.control = 0x64;
    sm2.activate = 1;
    ASSERT_TRUE(master_.write_registers(0, reg::sm(2), sm2.encode()));
    ASSERT_FALSE(master_.request_state(0, AlState::SafeOp));
    EXPECT_NE(master_.last_error().find("0x0017"), std::string::npos) << master_.last_error();
    // Bootstrap from PRE-OP: 0x0011 (§3.1 lists P -> B), not 0x0013.
    ASSERT_FALSE(master_.request_state(0, AlState::Boot));
    EXPECT_NE(master_.last_error().find("0x0011"), std::string::npos) << master_.last_error();
}

TEST_F(Akd2gSlave, AWarningIsAnEmergencyOverCoeAsOnCan) {
    // STO while disabled: warning W9000 (EMCY FF0Ch, §2.5 table) on axis 2, then the reset
    // message 0000h when it goes; the same emergencies codrive-sim sends on CAN.
    std::vector<std::pair<std::size_t, emcy::EmcyMessage>> seen;
    master_.on_emergency(
        [&](std::size_t slave, const emcy::EmcyMessage& m) { seen.emplace_back(slave, m); });
    bring_up(AlState::PreOp);
    ASSERT_TRUE(master_.sdo_write<std::uint8_t>(0, sim::kControlObject + 1, sim::kControlSto, 1))
        << master_.last_error();
    for (int i = 0; i < 50 && seen.empty(); ++i) {
        clock_.advance(std::chrono::milliseconds(10));
        ASSERT_TRUE(master_.run_mailbox_cycle()) << master_.last_error();
    }
    ASSERT_EQ(seen.size(), 1U);
    EXPECT_EQ(seen[0].first, 0U);
    EXPECT_EQ(seen[0].second.error_code, 0xFF0C);
    EXPECT_EQ(seen[0].second.error_register, 0x01); // AKD2G: only bit 0 (generic)
    EXPECT_EQ(master_.sdo_read<std::uint8_t>(0, 0x1001, 0).value_or(0), 0x01);
    ASSERT_TRUE(master_.sdo_write<std::uint8_t>(0, sim::kControlObject + 1, sim::kControlSto, 0))
        << master_.last_error();
    for (int i = 0; i < 50 && seen.size() < 2; ++i) {
        clock_.advance(std::chrono::milliseconds(10));
        ASSERT_TRUE(master_.run_mailbox_cycle()) << master_.last_error();
    }
    ASSERT_EQ(seen.size(), 2U);
    EXPECT_TRUE(seen[1].second.is_reset());
    EXPECT_EQ(master_.sdo_read<std::uint8_t>(0, 0x1001, 0).value_or(0xFF), 0x00);
}

} // namespace
} // namespace codrive::ethercat
