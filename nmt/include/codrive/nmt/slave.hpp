// SPDX-License-Identifier: Apache-2.0
// The NMT slave state machine (CiA 301 §7.3.2) for simulated nodes.
#pragma once

#include <codrive/core/cob_id.hpp>
#include <codrive/core/frame.hpp>
#include <codrive/core/time.hpp>
#include <codrive/nmt/command.hpp>
#include <codrive/nmt/state.hpp>

#include <cstdint>
#include <functional>

namespace codrive::nmt {

/// Follows the NMT commands addressed to one node (or to all) and reports transitions. A reset
/// command is reported through the reset handler; the owner re-initialises its application
/// (ResetNode) or communication (ResetCommunication) parameters and then calls boot_up(), which
/// moves to pre-operational (CiA 301 Figure 48: initialisation ends autonomously in
/// pre-operational after the boot-up message).
class NmtSlave {
public:
    using StateHandler = std::function<void(NmtState from, NmtState to)>;
    using ResetHandler = std::function<void(NmtCommand reset)>;

    explicit NmtSlave(NodeId node) : node_(node) {}

    void set_state_handler(StateHandler h) { on_state_ = std::move(h); }
    void set_reset_handler(ResetHandler h) { on_reset_ = std::move(h); }

    /// Handles NMT frames (000h) for this node or for all nodes; ignores other frames.
    /// Returns true if a command for this node was applied.
    bool on_frame(const Frame& frame, TimePoint now);

    /// Ends initialisation: Initializing → PreOperational. The caller sends the boot-up message
    /// (HeartbeatProducer::send_boot_up()).
    void boot_up();

    /// A state change the node makes on its own, e.g. the error behaviour of 1029h (CiA 301
    /// §7.5.2.32: on a communication error go to pre-operational or stopped). Reports it through
    /// the state handler like a command would. Ignored while initialising (use boot_up()).
    void enter(NmtState to);

    [[nodiscard]] NmtState state() const { return state_; }
    [[nodiscard]] NodeId node() const { return node_; }
    /// NMT frames that were not valid commands.
    [[nodiscard]] std::uint64_t malformed() const { return malformed_; }

    /// CiA 301 Table 50: which services a state allows.
    [[nodiscard]] bool sdo_allowed() const { return state_ != NmtState::Stopped; }
    [[nodiscard]] bool pdo_allowed() const { return state_ == NmtState::Operational; }
    [[nodiscard]] bool sync_emcy_allowed() const {
        return state_ == NmtState::Operational || state_ == NmtState::PreOperational;
    }

private:
    void set(NmtState to);

    NodeId node_;
    NmtState state_ = NmtState::BootUp; ///< Initializing until boot_up()
    StateHandler on_state_;
    ResetHandler on_reset_;
    std::uint64_t malformed_ = 0;
};

} // namespace codrive::nmt
