// SPDX-License-Identifier: Apache-2.0
// The controller's private parts, shared by its composition (controller.cpp), its runtime
// (controller_runtime.cpp) and its shutdown (controller_shutdown.cpp): per-bus and per-node
// state, the published statistics cell and the acyclic pump of the dedicated-cyclic mode.
#pragma once

#include <codrive/controller/controller.hpp>

#include "ecat_segment.hpp"
#include "handoff_transport.hpp"
#include "seqlock.hpp"
#include "spsc_ring.hpp"

#include <codrive/core/socket_can_bus.hpp>
#include <codrive/drives/canopen_transport.hpp>
#include <codrive/master/master.hpp>
#include <codrive/pdo/configure.hpp>
#include <codrive/pdo/master.hpp>
#include <codrive/sync/producer.hpp>

#include <atomic>
#include <map>
#include <memory>
#include <vector>

namespace codrive::controller {

struct Controller::Node {
    master::NodeEntry entry;
    const drives::Profile* profile = nullptr;
    std::shared_ptr<ObjectDictionary> od; ///< the profile's dictionary, for PDO validation
    std::vector<pdo::PdoConfig> pdos;
    std::unique_ptr<pdo::PdoConfigurator> configurator;
    std::unique_ptr<drives::CanopenTransport> transport;
    /// Dedicated-cyclic mode: the axes' transport (object accesses handed to the acyclic side).
    std::unique_ptr<HandoffTransport> handoff;
    std::vector<std::unique_ptr<drives::Axis>> axes;
    bool image_bound = false;
    std::atomic<std::uint16_t> emcy_code{0}; ///< dedicated mode: last EMCY, for the axes
};

struct Controller::Bus {
    master::BusConfig config;
    std::unique_ptr<SocketCanBus> socket;
    ICanBus* bus = nullptr;
    std::unique_ptr<master::Master> master;
    std::unique_ptr<pdo::PdoMaster> pdo;
    std::unique_ptr<sync::SyncProducer> sync;
    std::map<NodeId, std::unique_ptr<Node>> nodes;
    std::uint64_t bus_errors = 0;
    /// Dedicated-cyclic mode: the cyclic thread's own socket (SYNC and RPDOs out, TPDOs in,
    /// filtered by the kernel) and the PDO events it hands to the acyclic thread.
    std::unique_ptr<SocketCanBus> cyclic_socket;
    SpscRing<pdo::PdoEvent, 64> pdo_events;
};

/// The cyclic figures of stats(), published by whichever thread owns the cycles (the loop
/// thread in Threading::Single, the cyclic thread in Threading::DedicatedCyclic, the loop thread
/// again after the cyclic thread was joined): one writer at a time, lock-free readers.
struct Controller::StatsCell {
    Seqlock<ControllerStats> snapshot;
    // Writer side only: percentiles scan the histogram (a few thousand buckets), so they are
    // recomputed every kPercentileEvery publications, not every cycle.
    static constexpr std::uint64_t kPercentileEvery = 256;
    std::uint64_t publications = 0;
    Duration p50{0};
    Duration p99{0};
};

/// Dedicated-cyclic mode, acyclic side: starts the object accesses the cyclic thread queued
/// and reports its PDO events, once per millisecond.
class Controller::Pump final : public ITimed {
public:
    explicit Pump(Controller& c) : c_(c) {}
    [[nodiscard]] TimePoint next_deadline() const override { return next_; }
    void on_tick(TimePoint now) override {
        if (now < next_) {
            return;
        }
        next_ = now + milliseconds(1);
        c_.pump_acyclic();
    }

private:
    Controller& c_;
    TimePoint next_{};
};

} // namespace codrive::controller
