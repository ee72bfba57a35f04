// SPDX-License-Identifier: Apache-2.0
// The CANopen master of one bus: node supervision, boot-up and automatic recovery.
#pragma once

#include <codrive/master/events.hpp>
#include <codrive/master/remote_node.hpp>

#include <codrive/core/can_bus.hpp>
#include <codrive/core/event_loop.hpp>
#include <codrive/emcy/consumer.hpp>
#include <codrive/nmt/heartbeat_consumer.hpp>
#include <codrive/nmt/heartbeat_producer.hpp>
#include <codrive/nmt/master.hpp>
#include <codrive/nmt/node_guarding.hpp>
#include <codrive/sdo/client_manager.hpp>

#include <array>
#include <functional>
#include <memory>
#include <vector>

namespace codrive::master {

struct MasterConfig {
    /// The master's own node id (for its heartbeat); 0 = the master produces no heartbeat.
    NodeId node_id = 0;
    milliseconds heartbeat_period{0};
    /// Re-run boot-up of a node that reboots on its own and return it to its previous state.
    bool auto_recover = true;
    sdo::ClientConfig sdo;
};

/// Owns the SDO clients, NMT master, heartbeat consumer, node guarding and EMCY consumer of one
/// bus and keeps a RemoteNode per configured node. It installs itself as the bus's frame and
/// event handler; other services (PDO engine, drives) receive frames through add_listener().
/// Sans-I/O: register it with an EventLoop (add_timed) or tick it from a VirtualNetwork.
class Master final : public ITimed {
public:
    Master(ICanBus& bus, const IClock& clock, MasterConfig config = {});
    ~Master() override;
    Master(const Master&) = delete;
    Master& operator=(const Master&) = delete;

    /// Adds (or replaces) a node. Heartbeat consumption / guarding start after its boot-up.
    RemoteNode& add_node(NodeConfig config);
    [[nodiscard]] RemoteNode* node(NodeId id);
    [[nodiscard]] std::vector<RemoteNode*> nodes();

    /// Boots one node (see BootSequence); the callback and a BootCompleted/BootFailed event
    /// report the result.
    void boot(NodeId id, std::function<void(const BootReport&)> done = {});
    /// Boots every node in parallel; the callback gets all reports when the last one ends.
    void boot_all(std::function<void(const std::vector<BootReport>&)> done = {});

    void set_event_handler(MasterEventHandler handler) { handler_ = std::move(handler); }
    /// Frames the master does not consume are offered to listeners in order (PDO engine...).
    void add_listener(std::function<void(const Frame&, TimePoint)> listener) {
        listeners_.push_back(std::move(listener));
    }

    void on_frame(const Frame& frame, TimePoint now);
    void on_bus_event(const BusEvent& event);
    [[nodiscard]] TimePoint next_deadline() const override;
    void on_tick(TimePoint now) override;

    [[nodiscard]] sdo::SdoClientManager& sdo() { return sdo_; }
    [[nodiscard]] nmt::NmtMaster& nmt() { return nmt_; }
    [[nodiscard]] emcy::EmcyConsumer& emcy() { return emcy_; }
    [[nodiscard]] nmt::HeartbeatConsumer& heartbeats() { return heartbeats_; }
    [[nodiscard]] ICanBus& bus() { return bus_; }
    [[nodiscard]] const IClock& clock() const { return clock_; }

private:
    void emit(NodeId node, MasterEventKind kind, std::string text);
    void on_error_control(const nmt::ErrorControlEvent& e);
    void on_emcy(const emcy::EmcyEvent& e);
    void start_monitoring(RemoteNode& n);
    void recover(RemoteNode& n);

    ICanBus& bus_;
    const IClock& clock_;
    MasterConfig config_;
    sdo::SdoClientManager sdo_;
    nmt::NmtMaster nmt_;
    nmt::HeartbeatConsumer heartbeats_;
    nmt::NodeGuardingMaster guarding_;
    std::unique_ptr<nmt::HeartbeatProducer> producer_;
    emcy::EmcyConsumer emcy_;
    std::array<std::unique_ptr<RemoteNode>, kMaxNodeId + 1> nodes_{};
    std::vector<std::function<void(const Frame&, TimePoint)>> listeners_;
    MasterEventHandler handler_;
    std::vector<std::unique_ptr<BootSequence>> retired_; ///< finished sequences, freed on tick
};

} // namespace codrive::master
