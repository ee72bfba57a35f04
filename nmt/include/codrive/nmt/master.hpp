// SPDX-License-Identifier: Apache-2.0
// The NMT master: sends module-control commands and keeps the node state table.
#pragma once

#include <codrive/core/can_bus.hpp>
#include <codrive/nmt/command.hpp>
#include <codrive/nmt/node_state_table.hpp>

namespace codrive::nmt {

/// Sends NMT commands through an injected bus and tracks node states from error-control
/// messages passed to on_frame(). Sans-I/O: never blocks.
class NmtMaster {
public:
    explicit NmtMaster(ICanBus& bus) : bus_(bus) {}

    /// Sends `command` to `node` (kAllNodes = every node). Stop and start are reflected in the
    /// state table at once only for nodes that report no error control (CiA 301 gives no
    /// acknowledgement); resets mark the node(s) Unknown until their boot-up arrives.
    /// Errors: InvalidArgument for a bad node id; the bus's send errors (TxQueueFull, BusOff...).
    VoidResult send(NmtCommand command, NodeId node);

    VoidResult start(NodeId node) { return send(NmtCommand::Start, node); }
    VoidResult stop(NodeId node) { return send(NmtCommand::Stop, node); }
    VoidResult enter_pre_operational(NodeId node) {
        return send(NmtCommand::EnterPreOperational, node);
    }
    VoidResult reset_node(NodeId node) { return send(NmtCommand::ResetNode, node); }
    VoidResult reset_communication(NodeId node) {
        return send(NmtCommand::ResetCommunication, node);
    }

    /// Feeds boot-up / heartbeat / guarding replies to the state table.
    void on_frame(const Frame& frame, TimePoint now) { table_.on_frame(frame, now); }

    [[nodiscard]] const NodeStateTable& states() const { return table_; }
    [[nodiscard]] NodeStateTable& states() { return table_; }
    [[nodiscard]] std::uint64_t commands_sent() const { return sent_; }

private:
    ICanBus& bus_;
    NodeStateTable table_;
    std::uint64_t sent_ = 0;
};

} // namespace codrive::nmt
