// SPDX-License-Identifier: Apache-2.0
// Node guarding, master side (CiA 301 §7.2.8.3.1).
#include "format.hpp"

#include <codrive/nmt/node_guarding.hpp>

namespace codrive::nmt {

VoidResult NodeGuardingMaster::add(NodeId node, milliseconds guard_time,
                                   std::uint8_t life_time_factor, TimePoint now) {
    if (!valid_node_id(node) || guard_time.count() <= 0 || life_time_factor == 0) {
        return fail(CoreErrc::InvalidArgument);
    }
    Entry e;
    e.guard_time = guard_time;
    e.factor = life_time_factor;
    e.active = true;
    e.start = now;
    e.next_rtr = now;
    e.last_valid = now;
    e.life_deadline = now + guard_time * life_time_factor;
    e.state = nodes_[node].state;
    nodes_[node] = e;
    recompute();
    return {};
}

void NodeGuardingMaster::remove(NodeId node) {
    if (valid_node_id(node)) {
        nodes_[node] = Entry{};
        recompute();
    }
}

void NodeGuardingMaster::on_frame(const Frame& frame, TimePoint now) {
    if (frame.extended() || frame.rtr() || frame.error() || frame.id <= cob::kHeartbeat ||
        frame.id > cob::kHeartbeat + kMaxNodeId) {
        return;
    }
    const auto node = static_cast<NodeId>(frame.id - cob::kHeartbeat);
    auto& e = nodes_[node];
    if (!e.active) {
        return;
    }
    if (frame.len < 1) {
        ++e.stats.toggle_errors; // counted as an invalid reply
        return;
    }
    const std::uint8_t byte = frame.data[0];
    if (byte == 0x00) {
        // Boot-up: the node was reset, its toggle restarts at 0 (CiA 301 §7.2.8.3.1).
        const NmtState prev = e.state;
        e.state = NmtState::BootUp;
        e.expected_toggle = 0;
        const bool unexpected = prev != NmtState::Unknown && prev != NmtState::BootUp;
        emit(node,
             unexpected ? ErrorControlEventKind::UnexpectedBootUp : ErrorControlEventKind::BootUp,
             now,
             unexpected ? fmt::format("node {}: unexpected boot-up (the node was reset; it was {})",
                                      node, to_string(prev))
                        : fmt::format("node {}: boot-up", node));
        return;
    }
    const auto state = state_from_byte(byte);
    if (!state) {
        ++e.stats.toggle_errors;
        return;
    }
    const auto toggle = static_cast<std::uint8_t>(byte >> 7);
    e.awaiting = false;
    if (toggle != e.expected_toggle) {
        // Treated as not received: the life time keeps running. Follow the node's toggle so a
        // single glitch yields a single event.
        ++e.stats.toggle_errors;
        const std::uint8_t expected = e.expected_toggle;
        e.expected_toggle = static_cast<std::uint8_t>(toggle ^ 1U);
        emit(node, ErrorControlEventKind::GuardToggleError, now,
             fmt::format("node {}: node guarding toggle error (expected toggle bit {}, got {})",
                         node, expected, toggle));
        return;
    }
    e.expected_toggle = static_cast<std::uint8_t>(toggle ^ 1U);
    ++e.stats.replies;
    const TimePoint prev_valid = e.last_valid;
    e.last_valid = now;
    e.life_deadline = now + e.guard_time * e.factor;
    const NmtState prev = e.state;
    e.state = *state;
    if (e.timed_out) {
        e.timed_out = false;
        emit(node, ErrorControlEventKind::GuardRecovered, now,
             fmt::format("node {}: node guarding recovered after {} ms (state {})", node,
                         detail::ms_text(now - prev_valid), to_string(*state)));
    }
    if (prev != *state) {
        emit(node, ErrorControlEventKind::StateChanged, now,
             fmt::format("node {}: state changed from {} to {}", node, to_string(prev),
                         to_string(*state)));
    }
    recompute();
}

void NodeGuardingMaster::on_tick(TimePoint now) {
    if (now < next_) {
        return;
    }
    for (unsigned n = 1; n <= kMaxNodeId; ++n) {
        auto& e = nodes_[n];
        if (!e.active) {
            continue;
        }
        const auto node = static_cast<NodeId>(n);
        if (!e.timed_out && e.life_deadline <= now) {
            e.timed_out = true;
            emit(node, ErrorControlEventKind::GuardTimeout, now,
                 fmt::format("node {}: node guarding timeout: no valid reply for {} ms (guard time "
                             "{} ms x life time factor {})",
                             node, detail::ms_text(now - e.last_valid), e.guard_time.count(),
                             e.factor));
        }
        if (e.next_rtr <= now) {
            if (e.awaiting) {
                ++e.stats.missed;
            }
            if (bus_.send(Frame::make_rtr(cob::heartbeat(node), 1))) {
                ++e.stats.requests;
                e.awaiting = true;
            } else {
                ++send_errors_;
            }
            while (e.next_rtr <= now) {
                ++e.k;
                e.next_rtr = e.start + e.guard_time * static_cast<std::int64_t>(e.k);
            }
        }
    }
    recompute();
}

bool NodeGuardingMaster::timed_out(NodeId node) const {
    return valid_node_id(node) && nodes_[node].timed_out;
}

NmtState NodeGuardingMaster::state(NodeId node) const {
    return valid_node_id(node) ? nodes_[node].state : NmtState::Unknown;
}

GuardStats NodeGuardingMaster::stats(NodeId node) const {
    return valid_node_id(node) ? nodes_[node].stats : GuardStats{};
}

void NodeGuardingMaster::emit(NodeId node, ErrorControlEventKind kind, TimePoint now,
                              std::string text) {
    if (handler_) {
        handler_(ErrorControlEvent{node, kind, nodes_[node].state, now, std::move(text)});
    }
}

void NodeGuardingMaster::recompute() {
    TimePoint next = kNever;
    for (const auto& e : nodes_) {
        if (!e.active) {
            continue;
        }
        if (e.next_rtr < next) {
            next = e.next_rtr;
        }
        if (!e.timed_out && e.life_deadline < next) {
            next = e.life_deadline;
        }
    }
    next_ = next;
}

} // namespace codrive::nmt
