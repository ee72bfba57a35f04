// SPDX-License-Identifier: Apache-2.0
// Node state table fed by error-control messages (CiA 301 §7.2.8.3).
#include <codrive/nmt/node_state_table.hpp>

namespace codrive::nmt {

namespace {
const NodeStateEntry kNoEntry{};
}

bool NodeStateTable::on_frame(const Frame& frame, TimePoint now) {
    if (frame.extended() || frame.rtr() || frame.error()) {
        return false;
    }
    if (frame.id <= cob::kHeartbeat || frame.id > cob::kHeartbeat + kMaxNodeId) {
        return false;
    }
    const auto node = static_cast<NodeId>(frame.id - cob::kHeartbeat);
    if (frame.len < 1) {
        ++malformed_;
        return false;
    }
    const auto state = state_from_byte(frame.data[0]);
    if (!state) {
        ++malformed_;
        return false;
    }
    auto& e = entries_[node];
    e.state = *state;
    e.last_seen = now;
    ++e.messages;
    if (*state == NmtState::BootUp) {
        ++e.boot_ups;
    }
    return true;
}

NmtState NodeStateTable::state(NodeId node) const {
    return entry(node).state;
}

const NodeStateEntry& NodeStateTable::entry(NodeId node) const {
    return valid_node_id(node) ? entries_[node] : kNoEntry;
}

void NodeStateTable::set_state(NodeId node, NmtState state) {
    if (valid_node_id(node)) {
        entries_[node].state = state;
    }
}

void NodeStateTable::clear() {
    entries_.fill(NodeStateEntry{});
}

} // namespace codrive::nmt
