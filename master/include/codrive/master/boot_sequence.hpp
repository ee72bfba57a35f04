// SPDX-License-Identifier: Apache-2.0
// CiA 302-2-style boot-up of one node over SDO: bring it to pre-operational (or reset its
// communication), probe 1000h, check 1018h, download the configuration, set error control,
// start the node. Asynchronous and sans-I/O.
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
    /// for this node while the sequence runs. Pre-operational / operational confirm NMT enter
    /// pre-operational / start; a boot-up message ends the wait after NMT reset communication,
    /// and otherwise restarts the sequence (bounded by NodeConfig::reboot_restarts).
    void on_node_state(nmt::NmtState state, TimePoint now);
    /// Waiting for the node to confirm an NMT command: when to repeat it or give up.
    [[nodiscard]] TimePoint next_deadline() const { return wait_deadline_; }
    void on_tick(TimePoint now);

private:
    /// What the sequence waits for between SDO steps (an NMT command has no confirmation of its
    /// own: CiA 301 §7.2.8.3.1).
    /// Probe: the device type probe is due (after the boot-up message that ends BootUp).
    enum class Wait { None, BootUp, Probe, PreOperational, Operational };

    void step_ok(std::string name, std::string detail);
    void step_failed(std::string name, std::string detail);
    void enter_state();
    void probe(int attempt);
    void confirm_pre_operational();
    void check_identity(std::size_t sub);
    void write(std::size_t i);
    void extra(std::size_t i);
    void error_control();
    void guard();
    void finish();
    bool send_start(TimePoint now);
    bool send_pre_operational(TimePoint now);
    void wait_done();
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
    Wait wait_ = Wait::None;
    TimePoint wait_deadline_ = kNever; ///< kNever: not waiting
    milliseconds wait_period_{0};      ///< between repeats of the awaited NMT command
    int start_sends_ = 0;
    int pre_op_sends_ = 0;
    int restarts_ = 0;
    bool reboot_seen_ = false; ///< a boot-up message arrived: the failing step restarts
    std::optional<nmt::NmtState> reported_; ///< last state the heartbeat reported
    std::shared_ptr<bool> alive_; ///< callbacks check it: the sequence may be destroyed first
};

} // namespace codrive::master
