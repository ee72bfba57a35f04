// SPDX-License-Identifier: Apache-2.0
// A one-slave EtherCAT segment whose mailbox answers come from a script (fake clock, in-process
// link), for the master's mailbox protocol clients (FoE, CoE SDO) faced with a misbehaving slave.
#pragma once

#include <codrive/ethercat/datagram.hpp>
#include <codrive/ethercat/error.hpp>
#include <codrive/ethercat/mailbox.hpp>
#include <codrive/ethercat/master.hpp>

#include <algorithm>
#include <deque>
#include <vector>

namespace codrive::ethercat::testing {

inline constexpr std::uint16_t kSm0 = 0x1000;
inline constexpr std::uint16_t kSm1 = 0x1080;
inline constexpr std::uint16_t kMailbox = 128;

/// Every request the master writes to SM0 in messages of `type` is recorded, and the next
/// scripted payload is put in SM1 (as a message of `type`) for the read that follows it.
class ScriptedSlave final : public IEcatLink {
public:
    ScriptedSlave(FakeClock& clock, MailboxType type) : clock_(clock), type_(type) {}
    /// The payload (protocol header first) of the next answer. `another_follows`: once this one
    /// is read, the next scripted answer is in SM1 too (a late answer to a request that timed
    /// out, waiting ahead of the answer to the current one).
    void answer_raw(std::vector<std::uint8_t> payload, bool another_follows = false) {
        script_.push_back({std::move(payload), another_follows});
    }
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
                if (m && m->header.type == type_) {
                    requests_.push_back(m->payload);
                    ready_ = !script_.empty();
                }
            } else if (d.command == Command::Fprd && ado == kSm1) {
                if (!ready_) {
                    d.wkc = 0;
                    continue;
                }
                MailboxMessage m;
                m.header.type = type_;
                m.payload = std::move(script_.front().payload);
                ready_ = script_.front().another_follows && script_.size() > 1;
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
    /// The payloads of the requests the master wrote, in order.
    [[nodiscard]] const std::vector<std::vector<std::uint8_t>>& requests() const {
        return requests_;
    }

private:
    FakeClock& clock_;
    MailboxType type_;
    struct Answer {
        std::vector<std::uint8_t> payload;
        bool another_follows = false;
    };
    std::deque<Answer> script_;
    std::deque<std::vector<std::uint8_t>> pending_;
    std::vector<std::vector<std::uint8_t>> requests_;
    bool ready_ = false;
};

/// The slave as the master's scan would have found it: PRE-OP, "DRIVE", 128-byte mailboxes at
/// kSm0/kSm1 speaking `protocols` (mbx_proto bits).
inline SlaveInfo scripted_slave_info(std::uint16_t protocols) {
    SlaveInfo s;
    s.station_address = 0x1001;
    s.state = AlState::PreOp;
    s.sii.name = "DRIVE";
    s.sii.rx_mailbox_offset = kSm0;
    s.sii.rx_mailbox_size = kMailbox;
    s.sii.tx_mailbox_offset = kSm1;
    s.sii.tx_mailbox_size = kMailbox;
    s.sii.mailbox_protocols = protocols;
    return s;
}

} // namespace codrive::ethercat::testing
