// SPDX-License-Identifier: Apache-2.0
// NMT slave state machine (CiA 301 §7.3.2).
#include <codrive/nmt/slave.hpp>

namespace codrive::nmt {

bool NmtSlave::on_frame(const Frame& frame, TimePoint /*now*/) {
    if (frame.id != cob::kNmt || frame.extended() || frame.error()) {
        return false;
    }
    auto cmd = parse_command_frame(frame);
    if (!cmd) {
        ++malformed_;
        return false;
    }
    if (cmd->node != kAllNodes && cmd->node != node_) {
        return false;
    }
    if (state_ == NmtState::BootUp) {
        // Still initialising: commands other than resets have no transition from here.
        if (cmd->command != NmtCommand::ResetNode &&
            cmd->command != NmtCommand::ResetCommunication) {
            return false;
        }
    }
    switch (cmd->command) {
    case NmtCommand::Start:
        set(NmtState::Operational);
        break;
    case NmtCommand::Stop:
        set(NmtState::Stopped);
        break;
    case NmtCommand::EnterPreOperational:
        set(NmtState::PreOperational);
        break;
    case NmtCommand::ResetNode:
    case NmtCommand::ResetCommunication:
        set(NmtState::BootUp);
        if (on_reset_) {
            on_reset_(cmd->command);
        }
        break;
    }
    return true;
}

void NmtSlave::boot_up() {
    if (state_ == NmtState::BootUp) {
        set(NmtState::PreOperational);
    }
}

void NmtSlave::enter(NmtState to) {
    if (state_ == NmtState::BootUp || to == NmtState::BootUp || to == NmtState::Unknown) {
        return;
    }
    set(to);
}

void NmtSlave::set(NmtState to) {
    const NmtState from = state_;
    state_ = to;
    if (from != to && on_state_) {
        on_state_(from, to);
    }
}

} // namespace codrive::nmt
