// SPDX-License-Identifier: Apache-2.0
// The simulated ESC's mailbox queue: SM1 loading, the repeat protocol (ETG.1000.4 §6.7.2) and
// sending a message with the next mailbox counter (1..7).
#include <codrive/sim/ecat/esc_slave.hpp>

#include <codrive/ethercat/mailbox.hpp>

#include <algorithm>

namespace codrive::sim::ecat {

using namespace codrive::ethercat;

void EscSlave::clear_mailboxes() {
    mailbox_in_full_ = false;
    mailbox_out_full_ = false;
    outbox_.clear();
    sm1_message_.clear();
    last_read_.clear();
    last_request_counter_ = 0; // a new master session starts counting again
    if (foe_) {
        foe_->reset();
    }
    set_sm_status(0, 0);
    set_sm_status(1, 0);
}

void EscSlave::load_mailbox_out() {
    if (mailbox_out_full_ || outbox_.empty()) {
        return;
    }
    const SyncManager s1 = sm(1);
    if (!s1.enabled() || s1.length == 0) {
        return;
    }
    std::vector<std::uint8_t> msg = std::move(outbox_.front());
    outbox_.pop_front();
    msg.resize(s1.length, 0);
    const auto area = sm_area(s1); // a master may place SM1 so that it runs past the memory
    std::copy_n(msg.begin(), area.size(), area.begin());
    sm1_message_ = std::move(msg);
    mailbox_out_full_ = true;
    set_sm_status(1, SyncManager::kStatusMailboxFull);
}

void EscSlave::serve_mailbox_repeat() {
    // The application's side of the repeat protocol (ETG.1000.4 §6.7.2): on a toggled repeat
    // request write the last message the master read into SM1 again; a newer one waiting there
    // goes back to the head of the queue. Then acknowledge with the same toggle.
    const auto act = static_cast<std::uint16_t>(reg::sm(1) + SyncManager::kActivateOffset);
    const auto pdi = static_cast<std::uint16_t>(reg::sm(1) + SyncManager::kPdiControlOffset);
    const bool request = (mem_[act] & SyncManager::kActivateRepeatRequest) != 0;
    const bool ack = (mem_[pdi] & SyncManager::kPdiRepeatAck) != 0;
    if (request == ack) {
        return;
    }
    const SyncManager s1 = sm(1);
    if (s1.enabled() && s1.length != 0 && !last_read_.empty()) {
        if (mailbox_out_full_) {
            outbox_.push_front(std::move(sm1_message_));
        }
        sm1_message_ = last_read_;
        sm1_message_.resize(s1.length, 0);
        const auto area = sm_area(s1);
        std::copy_n(sm1_message_.begin(), area.size(), area.begin());
        mailbox_out_full_ = true;
        set_sm_status(1, SyncManager::kStatusMailboxFull);
        ++mailbox_repeats_;
    }
    mem_[pdi] = static_cast<std::uint8_t>(request ? mem_[pdi] | SyncManager::kPdiRepeatAck
                                                  : mem_[pdi] & ~SyncManager::kPdiRepeatAck);
}

void EscSlave::send_mailbox(std::vector<std::uint8_t> payload, MailboxType type) {
    MailboxMessage m;
    m.header.type = type;
    mailbox_counter_ = static_cast<std::uint8_t>(mailbox_counter_ % 7 + 1);
    m.header.counter = mailbox_counter_;
    m.payload = std::move(payload);
    auto bytes = m.encode();
    if (bytes.size() > sii_.tx_mailbox_size) {
        return; // the CoE server never builds more than the mailbox holds
    }
    outbox_.push_back(std::move(bytes));
    load_mailbox_out();
}

} // namespace codrive::sim::ecat
