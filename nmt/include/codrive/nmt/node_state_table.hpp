// SPDX-License-Identifier: Apache-2.0
// The NMT master's view of every node's state, fed by boot-up, heartbeat and guarding replies.
#pragma once

#include <codrive/core/cob_id.hpp>
#include <codrive/core/frame.hpp>
#include <codrive/core/time.hpp>
#include <codrive/nmt/state.hpp>

#include <array>
#include <cstdint>

namespace codrive::nmt {

/// What is known about one node.
struct NodeStateEntry {
    NmtState state = NmtState::Unknown;
    TimePoint last_seen = TimePoint{}; ///< valid once `messages` > 0
    std::uint32_t messages = 0;        ///< error-control messages received
    std::uint32_t boot_ups = 0;        ///< boot-up messages received
};

/// Node state table for nodes 1..127. Fixed size, no allocation.
class NodeStateTable {
public:
    /// Takes any frame; only data frames on 701h..77Fh with at least one byte change the table
    /// (heartbeat, boot-up and node-guarding replies all carry the state in byte 0, bits 0..6).
    /// Returns true if the frame was an error-control message that updated the table.
    bool on_frame(const Frame& frame, TimePoint now);

    /// State of a node; Unknown for invalid ids and nodes never heard.
    [[nodiscard]] NmtState state(NodeId node) const;
    /// The entry of a node (a default entry for invalid ids).
    [[nodiscard]] const NodeStateEntry& entry(NodeId node) const;
    /// Sets a node's state, e.g. after a command whose effect cannot be observed otherwise.
    void set_state(NodeId node, NmtState state);
    /// Forgets every node.
    void clear();
    /// Undefined state values and malformed error-control frames seen.
    [[nodiscard]] std::uint64_t malformed() const { return malformed_; }

private:
    std::array<NodeStateEntry, kMaxNodeId + 1> entries_{};
    std::uint64_t malformed_ = 0;
};

} // namespace codrive::nmt
