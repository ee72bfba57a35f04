// SPDX-License-Identifier: Apache-2.0
// Heartbeat consumer: consumer-time monitoring per node (CiA 301 §7.2.8.3.2, 1016h).
#include "format.hpp"

#include <codrive/nmt/heartbeat_consumer.hpp>

namespace codrive::nmt {

VoidResult HeartbeatConsumer::configure(NodeId node, milliseconds consumer_time) {
    if (!valid_node_id(node) || consumer_time.count() < 0) {
        return fail(CoreErrc::InvalidArgument);
    }
    auto& e = nodes_[node];
    e.configured = true;
    e.consumer_time = consumer_time;
    // CiA 301: a changed consumer time applies from the next heartbeat; a running timer keeps
    // its origin so reconfiguring does not hide a loss already in progress.
    if (e.running && consumer_time.count() > 0) {
        e.deadline = e.last + consumer_time;
    } else {
        e.deadline = kNever;
        e.running = e.running && consumer_time.count() > 0;
    }
    recompute_deadline();
    return {};
}

VoidResult HeartbeatConsumer::configure_from_1016(std::uint32_t value) {
    // 1016h sub-entry: bits 31..24 reserved, 23..16 node id, 15..0 consumer time in ms.
    const auto node = static_cast<NodeId>((value >> 16) & 0xFFU);
    const milliseconds time{value & 0xFFFFU};
    if (node == 0) {
        return {}; // CiA 301: node id 0 means "entry not used"
    }
    return configure(node, time);
}

void HeartbeatConsumer::remove(NodeId node) {
    if (valid_node_id(node)) {
        nodes_[node] = Entry{};
        recompute_deadline();
    }
}

void HeartbeatConsumer::expect_boot_up(NodeId node) {
    if (valid_node_id(node)) {
        nodes_[node].expect_boot = true;
    }
}

void HeartbeatConsumer::on_frame(const Frame& frame, TimePoint now) {
    if (frame.extended() || frame.rtr() || frame.error() || frame.id <= cob::kHeartbeat ||
        frame.id > cob::kHeartbeat + kMaxNodeId) {
        return;
    }
    const auto node = static_cast<NodeId>(frame.id - cob::kHeartbeat);
    auto& e = nodes_[node];
    if (!e.configured) {
        return;
    }
    if (frame.len < 1) {
        ++malformed_;
        return;
    }
    const auto state = state_from_byte(frame.data[0]);
    if (!state || (frame.data[0] & 0x80U) != 0) {
        // Bit 7 is the guarding toggle; a heartbeat never sets it (CiA 301 §7.2.8.3.2).
        ++malformed_;
        return;
    }
    const NmtState prev = e.state;
    if (*state == NmtState::BootUp) {
        const bool was_running =
            e.running || (prev != NmtState::Unknown && prev != NmtState::BootUp);
        const bool unexpected = was_running && !e.expect_boot;
        e.state = NmtState::BootUp;
        e.last = now;
        e.running = false;
        e.lost = false;
        e.deadline = kNever;
        e.expect_boot = false;
        recompute_deadline();
        if (unexpected) {
            emit(node, ErrorControlEventKind::UnexpectedBootUp, now,
                 fmt::format("node {}: unexpected boot-up (the node was reset; it was {})", node,
                             to_string(prev)));
        } else {
            emit(node, ErrorControlEventKind::BootUp, now, fmt::format("node {}: boot-up", node));
        }
        return;
    }
    const TimePoint prev_last = e.last;
    const bool was_lost = e.lost;
    e.state = *state;
    e.last = now;
    e.lost = false;
    e.running = e.consumer_time.count() > 0;
    e.deadline = e.running ? now + e.consumer_time : kNever;
    recompute_deadline();
    if (was_lost) {
        emit(node, ErrorControlEventKind::HeartbeatRecovered, now,
             fmt::format("node {}: heartbeat recovered after {} ms (state {})", node,
                         detail::ms_text(now - prev_last), to_string(*state)));
    }
    if (prev != *state) {
        emit(node, ErrorControlEventKind::StateChanged, now,
             fmt::format("node {}: state changed from {} to {}", node, to_string(prev),
                         to_string(*state)));
    }
}

void HeartbeatConsumer::on_tick(TimePoint now) {
    if (now < next_) {
        return;
    }
    for (unsigned n = 1; n <= kMaxNodeId; ++n) {
        auto& e = nodes_[n];
        if (!e.running || e.lost || e.deadline > now) {
            continue;
        }
        e.lost = true;
        e.deadline = kNever;
        emit(static_cast<NodeId>(n), ErrorControlEventKind::HeartbeatLost, now,
             fmt::format("node {}: heartbeat lost after {} ms (consumer time {} ms)", n,
                         detail::ms_text(now - e.last), e.consumer_time.count()));
    }
    recompute_deadline();
}

TimePoint HeartbeatConsumer::next_deadline() const {
    return next_;
}

bool HeartbeatConsumer::lost(NodeId node) const {
    return valid_node_id(node) && nodes_[node].lost;
}

NmtState HeartbeatConsumer::state(NodeId node) const {
    return valid_node_id(node) ? nodes_[node].state : NmtState::Unknown;
}

void HeartbeatConsumer::emit(NodeId node, ErrorControlEventKind kind, TimePoint now,
                             std::string text) {
    if (handler_) {
        handler_(ErrorControlEvent{node, kind, nodes_[node].state, now, std::move(text)});
    }
}

void HeartbeatConsumer::recompute_deadline() {
    TimePoint next = kNever;
    for (const auto& e : nodes_) {
        if (e.running && !e.lost && e.deadline < next) {
            next = e.deadline;
        }
    }
    next_ = next;
}

} // namespace codrive::nmt
