// SPDX-License-Identifier: Apache-2.0
// The simulated ESC's EtherCAT state machine (ETG.1000.6 §6.4): AL control requests, the checks
// of the mailbox and process data sync managers a transition needs, and leaving OP on a fault.
#include <codrive/sim/ecat/esc_slave.hpp>

namespace codrive::sim::ecat {

using namespace codrive::ethercat;

std::size_t EscSlave::pdo_bytes(std::uint16_t assign_index) {
    return (for_each_mapped(assign_index, [](std::uint32_t, std::size_t) {}) + 7) / 8;
}

std::uint16_t EscSlave::check_transition(AlState to) {
    if (to == AlState::PreOp && state_ == AlState::Init && sii_.has_mailbox()) {
        const SyncManager s0 = sm(0);
        const SyncManager s1 = sm(1);
        if (!s0.enabled() || !s1.enabled() || !s0.is_mailbox() || !s1.is_mailbox() ||
            s0.start != sii_.rx_mailbox_offset || s0.length != sii_.rx_mailbox_size ||
            s1.start != sii_.tx_mailbox_offset || s1.length != sii_.tx_mailbox_size ||
            !s0.master_writes() || s1.master_writes()) {
            return al_code::kInvalidMailboxConfigPreop;
        }
    }
    if (to == AlState::SafeOp && state_ == AlState::PreOp) {
        const std::size_t out = pdo_bytes(0x1C12);
        const std::size_t in = pdo_bytes(0x1C13);
        const SyncManager s2 = sm(2);
        const SyncManager s3 = sm(3);
        if (s2.length != out || (out > 0 && !s2.enabled())) {
            return al_code::kInvalidOutputConfig;
        }
        if (s3.length != in || (in > 0 && !s3.enabled())) {
            return al_code::kInvalidInputConfig;
        }
    }
    return al_code::kNoError;
}

void EscSlave::on_al_control(std::uint16_t value) {
    const bool ack = (value & kAlErrorFlag) != 0;
    const bool error_pending = (reg16(reg::kAlStatus) & kAlErrorFlag) != 0;
    // A pending error must be acknowledged before any other state is requested (ETG.1000.6
    // §6.4.1.3), except INIT: a request for INIT is always carried out, acknowledged or not
    // (masters reset a slave with a plain INIT: SOEM's ecx_reconfig_slave() writes 0x0001).
    const bool to_init = (value & 0x0F) == static_cast<unsigned>(AlState::Init);
    if (error_pending && !ack && !to_init) {
        return;
    }
    if (ack) {
        set_al_status(state_, false, 0);
    }
    const auto to = al_state_from_bits(value);
    if (!to) {
        set_al_status(state_, true, al_code::kUnknownState);
        return;
    }
    if (*to == state_) {
        return;
    }
    if (*to == AlState::Boot) {
        set_al_status(state_, true, al_code::kBootstrapNotSupported);
        return;
    }
    if (!transition_allowed(state_, *to)) {
        set_al_status(state_, true, al_code::kInvalidStateChange);
        return;
    }
    if (auto it = faults_.refuse.find(*to); it != faults_.refuse.end()) {
        set_al_status(state_, true, it->second, true);
        return;
    }
    if (*to == AlState::Op && faults_.refuse_op_requests > 0) {
        --faults_.refuse_op_requests;
        set_al_status(state_, true, faults_.refuse_op_code, true);
        return;
    }
    if (const std::uint16_t code = check_transition(*to); code != al_code::kNoError) {
        set_al_status(state_, true, code);
        return;
    }
    const AlState from = state_;
    state_ = *to;
    set_al_status(state_, false, 0);
    if (state_ == AlState::Init) {
        clear_mailboxes();
    }
    app_->on_state_change(from, state_);
}

bool EscSlave::leave_op(std::uint16_t code) {
    if (state_ != AlState::Op) {
        return false;
    }
    watchdog_armed_ = false;
    state_ = AlState::SafeOp;
    set_al_status(state_, true, code, true);
    app_->on_state_change(AlState::Op, AlState::SafeOp);
    return true;
}

} // namespace codrive::sim::ecat
