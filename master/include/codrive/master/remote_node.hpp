// SPDX-License-Identifier: Apache-2.0
// The master's view of one remote node: NMT state, error control, last EMCY, boot-up.
#pragma once

#include <codrive/master/boot_report.hpp>
#include <codrive/master/boot_sequence.hpp>
#include <codrive/master/node_config.hpp>

#include <codrive/emcy/consumer.hpp>
#include <codrive/nmt/state.hpp>

#include <memory>
#include <optional>

namespace codrive::master {

class Master;

class RemoteNode {
public:
    [[nodiscard]] NodeId id() const { return config_.id; }
    [[nodiscard]] const NodeConfig& config() const { return config_; }
    /// Last NMT state the node reported (heartbeat, guarding reply or boot-up).
    [[nodiscard]] nmt::NmtState state() const { return state_; }
    [[nodiscard]] bool heartbeat_lost() const { return heartbeat_lost_; }
    [[nodiscard]] bool booted() const { return booted_; }
    [[nodiscard]] bool booting() const { return boot_ && boot_->running(); }
    [[nodiscard]] const std::optional<BootReport>& last_boot() const { return last_boot_; }
    [[nodiscard]] const std::optional<emcy::EmcyEvent>& last_emcy() const { return last_emcy_; }
    [[nodiscard]] unsigned reboots() const { return reboots_; }
    [[nodiscard]] sdo::SdoClient& sdo() { return *sdo_; }

private:
    friend class Master;
    RemoteNode(NodeConfig config, sdo::SdoClient& sdo) : config_(std::move(config)), sdo_(&sdo) {}

    NodeConfig config_;
    sdo::SdoClient* sdo_;
    nmt::NmtState state_ = nmt::NmtState::Unknown;
    nmt::NmtState wanted_ = nmt::NmtState::Unknown; ///< state to restore after a reboot
    bool heartbeat_lost_ = false;
    bool booted_ = false;
    unsigned reboots_ = 0;
    std::optional<BootReport> last_boot_;
    std::optional<emcy::EmcyEvent> last_emcy_;
    std::unique_ptr<BootSequence> boot_;
    /// After boot-up with a heartbeat configured: the first heartbeat must come by then
    /// (CiA 301 monitoring only starts with it, so a node that dies right after its boot-up
    /// would otherwise never be reported).
    TimePoint first_heartbeat_due_ = kNever;
    bool lost_before_first_heartbeat_ = false;
};

} // namespace codrive::master
