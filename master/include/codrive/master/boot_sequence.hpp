// SPDX-License-Identifier: Apache-2.0
// CiA 302-2-style boot-up of one node over SDO: probe 1000h, check 1018h, download the
// configuration, set error control, start the node. Asynchronous and sans-I/O.
#pragma once

#include <codrive/master/boot_report.hpp>
#include <codrive/master/node_config.hpp>

#include <codrive/core/time.hpp>
#include <codrive/nmt/state.hpp>

#include <functional>
#include <memory>
#include <optional>
#include <string>

namespace codrive::sdo {
class SdoClient;
}
namespace codrive::nmt {
class NmtMaster;
}

namespace codrive::master {

/// Runs the boot-up steps of one node. Steps run one after another through the node's SDO
/// client; the first failure ends the sequence. The callback gets the complete report.
/// Destroying the sequence cancels it (the callback is not called).
class BootSequence {
public:
    using Done = std::function<void(const BootReport&)>;

    BootSequence(const NodeConfig& config, sdo::SdoClient& sdo, nmt::NmtMaster& nmt,
                 const IClock& clock);
    ~BootSequence();
    BootSequence(const BootSequence&) = delete;
    BootSequence& operator=(const BootSequence&) = delete;

    /// Starts the sequence. `start_node` overrides the configuration's start flag (recovery
    /// returns a node to the state it had before it rebooted).
    void run(Done done, bool start_node, bool recovery = false);
    [[nodiscard]] bool running() const { return running_; }

    /// The node's NMT state from its heartbeat (BootUp for a boot-up message), fed by the master
    /// for this node while the sequence runs. Operational confirms NMT start; a boot-up message
    /// restarts the sequence (bounded by NodeConfig::reboot_restarts).
    void on_node_state(nmt::NmtState state, TimePoint now);
    /// Waiting for the node to confirm NMT start: when to repeat it.
    [[nodiscard]] TimePoint next_deadline() const { return start_deadline_; }
    void on_tick(TimePoint now);

private:
    struct State;
    void next();
    void step_ok(std::string name, std::string detail);
    void step_failed(std::string name, std::string detail);
    void probe(int attempt);
    void check_identity(std::size_t sub);
    void write(std::size_t i);
    void extra(std::size_t i);
    void error_control();
    void finish();
    bool send_start(TimePoint now);
    void complete();
    void restart(std::string why);

    const NodeConfig& config_;
    sdo::SdoClient& sdo_;
    nmt::NmtMaster& nmt_;
    const IClock& clock_;
    BootReport report_;
    Done done_;
    TimePoint step_started_{};
    bool start_node_ = true;
    bool running_ = false;
    int phase_ = 0;
    TimePoint start_deadline_ = kNever; ///< kNever: not waiting for operational
    int start_sends_ = 0;
    int restarts_ = 0;
    bool reboot_seen_ = false; ///< a boot-up message arrived: the failing step restarts
    std::optional<nmt::NmtState> reported_; ///< last state the heartbeat reported
    std::shared_ptr<bool> alive_; ///< callbacks check it: the sequence may be destroyed first
};

} // namespace codrive::master
