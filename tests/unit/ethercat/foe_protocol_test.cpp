// SPDX-License-Identifier: Apache-2.0
// The master's FoE client against a scripted slave (fake clock, in-process link): a slave that
// breaks the protocol — wrong packet number, an opcode out of turn, a malformed message — ends
// the transfer with a sentence, and the master tells the slave so with an FoE ERR (ETG.1000.6
// §5.7), as a real slave's own state machine expects.
#include "scripted_slave.hpp"

#include <codrive/ethercat/foe.hpp>

#include <gtest/gtest.h>

namespace codrive::ethercat {
namespace {

using testing::ScriptedSlave;

/// The scripted slave seen as FoE messages: answers are built and requests decoded as FoE.
class FoeScript {
public:
    explicit FoeScript(ScriptedSlave& link) : link_(link) {}
    void answer(FoeOpcode op, std::uint32_t value, std::vector<std::uint8_t> body = {}) {
        std::vector<std::uint8_t> p;
        encode_foe(p, op, value, body);
        link_.answer_raw(std::move(p));
    }
    void answer_raw(std::vector<std::uint8_t> payload) { link_.answer_raw(std::move(payload)); }
    /// What the master wrote, decoded.
    [[nodiscard]] std::vector<FoeMessage> requests() const {
        std::vector<FoeMessage> out;
        for (const auto& r : link_.requests()) {
            auto m = decode_foe(r);
            EXPECT_TRUE(m) << "the master wrote a malformed FoE message";
            if (m) {
                out.push_back(*m);
            }
        }
        return out;
    }

private:
    ScriptedSlave& link_;
};

class FoeProtocol : public ::testing::Test {
protected:
    FoeProtocol() { master_.slaves().push_back(testing::scripted_slave_info(mbx_proto::kFoe)); }
    FakeClock clock_;
    ScriptedSlave link_{clock_, MailboxType::Foe};
    FoeScript slave_{link_};
    Master master_{link_, clock_};
};

std::string body_text(const FoeMessage& m) {
    return {m.body.begin(), m.body.end()};
}

TEST_F(FoeProtocol, ReadSendsPasswordAndNameThenAcksEveryDataUntilAShortOne) {
    slave_.answer(FoeOpcode::Data, 1, std::vector<std::uint8_t>(116, 0xAA));
    slave_.answer(FoeOpcode::Data, 2, {1, 2, 3});
    FoeOptions o;
    o.password = 0x12345678;
    auto r = master_.foe_read(0, "drive.akd", o);
    ASSERT_TRUE(r) << master_.last_error();
    EXPECT_EQ(r->size(), 119U);
    const auto req = slave_.requests();
    ASSERT_EQ(req.size(), 3U);
    EXPECT_EQ(req[0].opcode, FoeOpcode::ReadRequest);
    EXPECT_EQ(req[0].value, 0x12345678U);
    EXPECT_EQ(body_text(req[0]), "drive.akd");
    EXPECT_EQ(req[1].opcode, FoeOpcode::Ack);
    EXPECT_EQ(req[1].value, 1U);
    EXPECT_EQ(req[2].opcode, FoeOpcode::Ack);
    EXPECT_EQ(req[2].value, 2U);
}

TEST_F(FoeProtocol, WrongPacketNumberEndsTheReadAndTellsTheSlave) {
    slave_.answer(FoeOpcode::Data, 1, std::vector<std::uint8_t>(116, 0));
    slave_.answer(FoeOpcode::Data, 3, {1}); // packet 2 skipped
    auto r = master_.foe_read(0, "drive.akd");
    ASSERT_FALSE(r);
    EXPECT_EQ(r.error(), EcatErrc::ProtocolError);
    EXPECT_EQ(master_.last_error(),
              "slave 0 (DRIVE): FoE read 'drive.akd': DATA packet 3 where 2 was expected");
    const auto req = slave_.requests();
    ASSERT_EQ(req.size(), 3U);
    EXPECT_EQ(req[2].opcode, FoeOpcode::Error);
    EXPECT_EQ(req[2].value, foe_error::kPacketNumberWrong);
    EXPECT_EQ(body_text(req[2]), "packet number wrong");
}

TEST_F(FoeProtocol, AnAckOfTheWrongPacketEndsTheWriteAndTellsTheSlave) {
    slave_.answer(FoeOpcode::Ack, 0);
    slave_.answer(FoeOpcode::Ack, 7);
    auto w = master_.foe_write(0, "drive.akd", std::vector<std::uint8_t>(200, 1));
    ASSERT_FALSE(w);
    EXPECT_EQ(master_.last_error(), "slave 0 (DRIVE): FoE write 'drive.akd' (200 bytes): ACK of "
                                    "packet 7 where 1 was expected");
    const auto req = slave_.requests();
    ASSERT_EQ(req.size(), 3U);
    EXPECT_EQ(req[0].opcode, FoeOpcode::WriteRequest);
    EXPECT_EQ(req[1].opcode, FoeOpcode::Data);
    EXPECT_EQ(req[1].value, 1U);
    EXPECT_EQ(req[1].body.size(), 116U) << "DATA as large as the slave's 128-byte SM0 allows";
    EXPECT_EQ(req[2].opcode, FoeOpcode::Error);
    EXPECT_EQ(req[2].value, foe_error::kPacketNumberWrong);
}

TEST_F(FoeProtocol, AnOpcodeOutOfTurnOrAMalformedMessageIsNamed) {
    slave_.answer(FoeOpcode::Ack, 1); // a read answered with an ACK
    ASSERT_FALSE(master_.foe_read(0, "a.akd"));
    EXPECT_EQ(master_.last_error(),
              "slave 0 (DRIVE): FoE read 'a.akd': the slave sent FoE ACK where DATA was expected");
    slave_.answer_raw({3, 0, 1}); // shorter than the FoE header
    ASSERT_FALSE(master_.foe_read(0, "b.akd"));
    EXPECT_EQ(master_.last_error(),
              "slave 0 (DRIVE): FoE read 'b.akd': the slave's FoE message is malformed");
    const auto req = slave_.requests();
    ASSERT_EQ(req.size(), 4U);
    EXPECT_EQ(req[1].opcode, FoeOpcode::Error);
    EXPECT_EQ(req[1].value, foe_error::kIllegal);
    EXPECT_EQ(req[3].opcode, FoeOpcode::Error);
}

TEST_F(FoeProtocol, TheSlavesErrorTextIsQuotedPrintableOnly) {
    slave_.answer(FoeOpcode::Error, foe_error::kNoRights, {'l', 'o', 'c', 'k', 0x07, 0, 'x'});
    ASSERT_FALSE(master_.foe_read(0, "fw.bin"));
    EXPECT_EQ(master_.last_error(), "slave 0 (DRIVE): FoE read 'fw.bin': the slave answered error "
                                    "0x800A (no rights): \"lock?\"");
    EXPECT_EQ(slave_.requests().size(), 1U) << "an ERR is not answered";
}

} // namespace
} // namespace codrive::ethercat
