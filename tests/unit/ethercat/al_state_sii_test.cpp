// SPDX-License-Identifier: Apache-2.0
// ESM transition rules, AL status code texts (ETG.1000.6) and SII EEPROM parsing (ETG.2010).
#include <codrive/core/endian.hpp>
#include <codrive/ethercat/al_state.hpp>
#include <codrive/ethercat/mailbox.hpp>
#include <codrive/ethercat/registers.hpp>
#include <codrive/ethercat/sii.hpp>

#include <gtest/gtest.h>

namespace codrive::ethercat {
namespace {

TEST(EcatEsm, UpOneStepAtATimeDownAnyStep) {
    EXPECT_TRUE(transition_allowed(AlState::Init, AlState::PreOp));
    EXPECT_TRUE(transition_allowed(AlState::PreOp, AlState::SafeOp));
    EXPECT_TRUE(transition_allowed(AlState::SafeOp, AlState::Op));
    EXPECT_FALSE(transition_allowed(AlState::Init, AlState::SafeOp));
    EXPECT_FALSE(transition_allowed(AlState::Init, AlState::Op));
    EXPECT_FALSE(transition_allowed(AlState::PreOp, AlState::Op));
    EXPECT_TRUE(transition_allowed(AlState::Op, AlState::Init));
    EXPECT_TRUE(transition_allowed(AlState::Op, AlState::PreOp));
    EXPECT_TRUE(transition_allowed(AlState::Init, AlState::Boot));
    EXPECT_FALSE(transition_allowed(AlState::Boot, AlState::PreOp));
    EXPECT_TRUE(transition_allowed(AlState::Boot, AlState::Init));
}

TEST(EcatEsm, StateNamesAndParsing) {
    EXPECT_EQ(to_string(AlState::SafeOp), "SAFE-OP");
    EXPECT_EQ(al_state_from_string("pre-op"), AlState::PreOp);
    EXPECT_EQ(al_state_from_string("SAFEOP"), AlState::SafeOp);
    EXPECT_EQ(al_state_from_bits(0x0018), AlState::Op);
    EXPECT_FALSE(al_state_from_bits(0x0005));
}

TEST(EcatEsm, AlStatusCodesHaveTheirStandardText) {
    EXPECT_EQ(al_status_code_describe(0x001D), "invalid output configuration");
    EXPECT_EQ(al_status_code_describe(0x0011), "invalid requested state change");
    EXPECT_EQ(al_status_code_describe(0x001B), "sync manager watchdog");
    EXPECT_EQ(al_status_code_describe(0x8001), "vendor-specific AL status code");
    EXPECT_EQ(al_status_code_describe(0x00EE), "unknown AL status code");
}

TEST(EcatSii, BuiltImageParsesBackWithIdentityMailboxAndSyncManagers) {
    SiiInfo in;
    in.vendor_id = 0x0048554B;
    in.product_code = 0x0002BA67;
    in.revision = 3;
    in.serial = 42;
    in.name = "FIO Drive Control";
    in.rx_mailbox_offset = 0x1000;
    in.rx_mailbox_size = 128;
    in.tx_mailbox_offset = 0x1080;
    in.tx_mailbox_size = 128;
    in.mailbox_protocols = mbx_proto::kCoe;
    in.sync_managers = {{0x1000, 128, 0x26, 1, SmType::MailboxOut},
                        {0x1080, 128, 0x22, 1, SmType::MailboxIn},
                        {0x1100, 0, 0x64, 1, SmType::Outputs},
                        {0x1180, 0, 0x20, 1, SmType::Inputs}};
    const auto image = build_sii(in);
    ASSERT_TRUE(sii_categories_end(image));
    auto out = parse_sii(image);
    ASSERT_TRUE(out);
    EXPECT_TRUE(out->checksum_ok);
    EXPECT_EQ(out->vendor_id, in.vendor_id);
    EXPECT_EQ(out->product_code, in.product_code);
    EXPECT_EQ(out->revision, 3U);
    EXPECT_EQ(out->serial, 42U);
    EXPECT_EQ(out->name, "FIO Drive Control");
    EXPECT_EQ(out->tx_mailbox_offset, 0x1080);
    EXPECT_TRUE(out->has_coe());
    ASSERT_EQ(out->sync_managers.size(), 4U);
    EXPECT_EQ(out->sync_managers[2].type, SmType::Outputs);
    EXPECT_EQ(out->sync_managers[3].start, 0x1180);
}

TEST(EcatSii, GeneralCategoryStatesTheCoeServicesAndPortsTheSlaveHas) {
    // ETG.2010 Table 6, as a master such as SOEM reads it ("CoE details"): SDO, SDO information,
    // PDO assignment, PDO configuration, complete access; FoE; ports 0 and 1 MII.
    SiiInfo in;
    in.name = "AKD2G";
    in.mailbox_protocols = mbx_proto::kCoe | mbx_proto::kFoe;
    const auto image = build_sii(in);
    std::size_t at = 0x80; // categories start at word 40h
    while (at + 4 <= image.size() &&
           get_le<std::uint16_t>(image.data() + at) != sii_cat::kGeneral) {
        at += 4 + 2U * get_le<std::uint16_t>(image.data() + at + 2);
    }
    ASSERT_LT(at + 4 + 18, image.size());
    const std::uint8_t* general = image.data() + at + 4;
    EXPECT_EQ(general[3], 1) << "name: first string";
    EXPECT_EQ(general[5], 0x2F) << "CoE details";
    EXPECT_EQ(general[6], 0x01) << "FoE details";
    EXPECT_EQ(get_le<std::uint16_t>(general + 16), 0x0011) << "physical ports";
}

TEST(EcatSii, TruncatedCategoryIsAnErrorAndBadChecksumIsFlagged) {
    SiiInfo in;
    in.name = "x";
    auto image = build_sii(in);
    image.resize(image.size() - 4); // cut into the last category
    image[0] ^= 0xFF;               // corrupt the checksummed area
    auto out = parse_sii(image);
    if (out) {
        EXPECT_FALSE(out->checksum_ok);
    }
    EXPECT_FALSE(sii_categories_end(image));
    EXPECT_FALSE(parse_sii(std::vector<std::uint8_t>(20, 0)));
}

TEST(EcatRegisters, SyncManagerAndFmmuRecordsRoundTrip) {
    Fmmu f;
    f.logical_start = 0x00010010;
    f.length = 11;
    f.physical_start = 0x1100;
    f.type = Fmmu::kWrite;
    f.activate = 1;
    const auto b = f.encode();
    const Fmmu g = Fmmu::decode(b);
    EXPECT_EQ(g.logical_start, f.logical_start);
    EXPECT_EQ(g.length, 11);
    EXPECT_EQ(g.physical_start, 0x1100);
    SyncManager s;
    s.start = 0x1000;
    s.length = 128;
    s.control = 0x26;
    s.activate = 1;
    const SyncManager t = SyncManager::decode(s.encode());
    EXPECT_TRUE(t.is_mailbox());
    EXPECT_TRUE(t.master_writes());
    EXPECT_TRUE(t.enabled());
}

TEST(EcatMailbox, HeaderRoundTripsTypeCounterAndLength) {
    MailboxMessage m;
    m.header.type = MailboxType::Coe;
    m.header.counter = 5;
    m.payload = {1, 2, 3};
    auto bytes = m.encode(32);
    EXPECT_EQ(bytes.size(), 32U);
    auto back = MailboxMessage::decode(bytes);
    ASSERT_TRUE(back);
    EXPECT_EQ(back->header.length, 3);
    EXPECT_EQ(back->header.counter, 5);
    EXPECT_EQ(back->header.type, MailboxType::Coe);
    EXPECT_EQ(back->payload, m.payload);
    bytes[0] = 200; // length beyond the buffer
    EXPECT_FALSE(MailboxMessage::decode(bytes));
}

} // namespace
} // namespace codrive::ethercat
