// SPDX-License-Identifier: Apache-2.0
// The master's FoE client against a scripted slave (fake clock, in-process link): a slave that
// breaks the protocol — wrong packet number, an opcode out of turn, a malformed message — ends
// the transfer with a sentence, and the master tells the slave so with an FoE ERR (ETG.1000.6
// §5.7), as a real slave's own state machine expects.
#include <codrive/ethercat/datagram.hpp>
#include <codrive/ethercat/error.hpp>
#include <codrive/ethercat/foe.hpp>
#include <codrive/ethercat/mailbox.hpp>
#include <codrive/ethercat/master.hpp>

#include <gtest/gtest.h>

#include <deque>

namespace codrive::ethercat {
namespace {

constexpr std::uint16_t kSm0 = 0x1000;
constexpr std::uint16_t kSm1 = 0x1080;
constexpr std::uint16_t kMailbox = 128;

/// One slave whose answers come from a script: every request the master writes to SM0 is
/// recorded, and the next scripted FoE message is put in SM1 for the read that follows it.
class ScriptedSlave final : public IEcatLink {
public:
    explicit ScriptedSlave(FakeClock& clock) : clock_(clock) {}
    void answer(FoeOpcode op, std::uint32_t value, std::vector<std::uint8_t> body = {}) {
        std::vector<std::uint8_t> p;
        encode_foe(p, op, value, body);
        script_.push_back(std::move(p));
    }
    void answer_raw(std::vector<std::uint8_t> payload) { script_.push_back(std::move(payload)); }
    VoidResult send(std::span<const std::uint8_t> frame) override {
        clock_.advance(milliseconds(1));
        auto datagrams = decode_frame(frame);
        if (!datagrams) {
            return {};
        }
        for (auto& d : *datagrams) {
            const auto ado = static_cast<std::uint16_t>(d.address >> 16);
            d.wkc = 1;
            if (d.command == Command::Fpwr && ado == kSm0) {
                auto m = MailboxMessage::decode(d.data);
                if (m && m->header.type == MailboxType::Foe) {
                    requests_.push_back(m->payload);
                    ready_ = !script_.empty();
                }
            } else if (d.command == Command::Fprd && ado == kSm1) {
                if (!ready_) {
                    d.wkc = 0;
                    continue;
                }
                ready_ = false;
                MailboxMessage m;
                m.header.type = MailboxType::Foe;
                m.payload = std::move(script_.front());
                script_.pop_front();
                auto bytes = m.encode(kMailbox);
                std::copy(bytes.begin(), bytes.end(), d.data.begin());
            }
        }
        if (auto out = encode_frame(*datagrams)) {
            pending_.push_back(std::move(*out));
        }
        return {};
    }
    Result<std::size_t> receive(std::span<std::uint8_t> buffer, TimePoint deadline) override {
        if (pending_.empty()) {
            clock_.set(deadline);
            return fail(CoreErrc::Timeout);
        }
        const auto f = std::move(pending_.front());
        pending_.pop_front();
        std::copy(f.begin(), f.end(), buffer.begin());
        return f.size();
    }
    void idle(Duration d) override { clock_.advance(d); }
    [[nodiscard]] std::string name() const override { return "scripted slave"; }
    /// What the master wrote, decoded.
    [[nodiscard]] std::vector<FoeMessage> requests() const {
        std::vector<FoeMessage> out;
        for (const auto& r : requests_) {
            auto m = decode_foe(r);
            EXPECT_TRUE(m) << "the master wrote a malformed FoE message";
            if (m) {
                out.push_back(*m);
            }
        }
        return out;
    }

private:
    FakeClock& clock_;
    std::deque<std::vector<std::uint8_t>> script_;
    std::deque<std::vector<std::uint8_t>> pending_;
    std::vector<std::vector<std::uint8_t>> requests_;
    bool ready_ = false;
};

class FoeProtocol : public ::testing::Test {
protected:
    FoeProtocol() {
        SlaveInfo s;
        s.station_address = 0x1001;
        s.state = AlState::PreOp;
        s.sii.name = "DRIVE";
        s.sii.rx_mailbox_offset = kSm0;
        s.sii.rx_mailbox_size = kMailbox;
        s.sii.tx_mailbox_offset = kSm1;
        s.sii.tx_mailbox_size = kMailbox;
        s.sii.mailbox_protocols = mbx_proto::kFoe;
        master_.slaves().push_back(s);
    }
    FakeClock clock_;
    ScriptedSlave slave_{clock_};
    Master master_{slave_, clock_};
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
