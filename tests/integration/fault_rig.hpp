// SPDX-License-Identifier: Apache-2.0
// Test rig for fault-injection runs: a master and N mini devices on one virtual network with a
// counting, seeded fault injector, driven by a fake clock in 1 ms cycles.
#pragma once

#include "mini_device.hpp"

#include <codrive/core/cob_id.hpp>
#include <codrive/master/master.hpp>

#include <cstdint>
#include <cstdio>
#include <functional>
#include <map>
#include <memory>
#include <random>
#include <string>
#include <vector>

namespace codrive::integration {

/// Random frame faults at fixed rates from a seeded generator (runs repeat exactly), counting
/// what it did. `applies` restricts the faults to some frames (all by default).
class FaultInjector {
public:
    struct Rates {
        double drop = 0;
        double duplicate = 0;
        double reorder = 0;
        double corrupt = 0;
    };
    struct Counts {
        std::uint64_t frames = 0; ///< frames the injector saw
        std::uint64_t dropped = 0;
        std::uint64_t duplicated = 0;
        std::uint64_t reordered = 0;
        std::uint64_t corrupted = 0;
        [[nodiscard]] std::uint64_t injected() const {
            return dropped + duplicated + reordered + corrupted;
        }
    };

    FaultInjector(Rates rates, std::uint64_t seed) : rates_(rates), rng_(seed) {}

    void set_scope(std::function<bool(const Frame&)> applies) { applies_ = std::move(applies); }
    void set_enabled(bool on) { enabled_ = on; }

    FaultAction decide(const Frame& frame) {
        ++counts_.frames;
        FaultAction a;
        if (!enabled_ || (applies_ && !applies_(frame))) {
            return a;
        }
        std::uniform_real_distribution<double> u(0.0, 1.0);
        if (u(rng_) < rates_.drop) {
            a.drop = true;
            ++counts_.dropped;
            return a;
        }
        if (u(rng_) < rates_.duplicate) {
            a.duplicates = 1;
            ++counts_.duplicated;
        }
        if (u(rng_) < rates_.reorder) {
            // Later frames (sent within 0.5 ms) overtake this one.
            a.delay = microseconds(500);
            ++counts_.reordered;
        }
        if (u(rng_) < rates_.corrupt && frame.len > 0) {
            a.corrupt = true;
            ++counts_.corrupted;
        }
        return a;
    }
    [[nodiscard]] const Counts& counts() const { return counts_; }

private:
    Rates rates_;
    std::mt19937_64 rng_;
    std::function<bool(const Frame&)> applies_;
    bool enabled_ = true;
    Counts counts_;
};

/// True for frames of the default SDO channels (581h..5FFh, 601h..67Fh).
inline bool is_sdo_frame(const Frame& f) {
    return !f.extended() && ((f.id > cob::kSdoTx && f.id <= cob::kSdoTx + kMaxNodeId) ||
                             (f.id > cob::kSdoRx && f.id <= cob::kSdoRx + kMaxNodeId));
}

/// Master plus devices 1..n on a network with 100 µs latency.
class Rig {
public:
    explicit Rig(int nodes, master::MasterConfig config = {})
        : master_bus_(net.endpoint("master")), master(master_bus_, clock, std::move(config)) {
        for (int i = 1; i <= nodes; ++i) {
            VirtualBus& bus = net.endpoint("node" + std::to_string(i));
            devices.push_back(std::make_unique<MiniDevice>(bus, static_cast<NodeId>(i)));
        }
        master.set_event_handler([this](const master::MasterEvent& e) {
            ++event_counts[e.kind];
            events.push_back(e);
        });
    }

    /// Routes every frame through `injector` (nullptr: no faults).
    void set_injector(FaultInjector* injector) {
        if (injector == nullptr) {
            net.set_fault_filter(nullptr);
            return;
        }
        net.set_fault_filter(
            [injector](const std::string&, const Frame& f) { return injector->decide(f); });
    }

    /// The node configuration the master boots: identity check, heartbeat 100 ms consumed with
    /// 250 ms (two heartbeats must go missing before a loss is reported).
    static master::NodeConfig node_config(NodeId id) {
        master::NodeConfig c;
        c.id = id;
        c.name = "mini" + std::to_string(id);
        c.identity.device_type = kDeviceType;
        c.identity.vendor_id = kVendorId;
        c.identity.product_code = kProductCode;
        c.heartbeat_producer = milliseconds(100);
        c.heartbeat_consumer = milliseconds(250);
        c.sdo_timeout = milliseconds(100);
        c.probe_retries = 5;
        return c;
    }

    void power_on_all() {
        for (auto& d : devices) {
            d->power_on(clock.now());
        }
        run_for(milliseconds(1));
    }

    /// Adds every node and boots them all; nodes whose boot failed are booted again, at most
    /// `attempts` times in total. Returns the number of boot attempts that failed.
    int boot_all(int attempts = 10) {
        for (auto& d : devices) {
            master.add_node(node_config(d->node()));
        }
        int failures = 0;
        std::vector<NodeId> todo;
        for (auto& d : devices) {
            todo.push_back(d->node());
        }
        for (int round = 0; round < attempts && !todo.empty(); ++round) {
            // Shared with the callbacks, which must not outlive what they write to.
            struct Round {
                std::size_t left = 0;
                int failures = 0;
                std::vector<NodeId> failed;
            };
            auto r = std::make_shared<Round>();
            r->left = todo.size();
            for (NodeId id : todo) {
                master.boot(id, [r](const master::BootReport& report) {
                    --r->left;
                    if (!report.ok) {
                        ++r->failures;
                        r->failed.push_back(report.node);
                    }
                });
            }
            for (int i = 0; i < 100'000 && r->left > 0; ++i) {
                run_for(milliseconds(1));
            }
            failures += r->failures;
            todo = r->left == 0 ? r->failed : todo;
        }
        return todo.empty() ? failures : -1;
    }

    void run_for(Duration d) { run_until(clock.now() + d); }
    void run_until(TimePoint t) {
        std::vector<ITimed*> timed{&master};
        for (auto& d : devices) {
            timed.push_back(d.get());
        }
        for (ITimed* extra : extra_timed) {
            timed.push_back(extra);
        }
        net.run_until(clock, t, timed);
    }
    /// Runs up to `cycles` cycles of 1 ms; `each` (optional) runs after every cycle and may
    /// stop the run early by returning false. Returns the cycles run.
    std::uint64_t run_cycles(std::uint64_t cycles,
                             const std::function<bool(std::uint64_t)>& each = {}) {
        const TimePoint start = clock.now();
        for (std::uint64_t c = 1; c <= cycles; ++c) {
            run_until(start + milliseconds(c));
            if (each && !each(c)) {
                return c;
            }
        }
        return cycles;
    }

    [[nodiscard]] MiniDevice& device(NodeId id) { return *devices.at(id - 1U); }
    [[nodiscard]] std::uint64_t count(master::MasterEventKind k) const {
        const auto it = event_counts.find(k);
        return it == event_counts.end() ? 0 : it->second;
    }

    FakeClock clock;
    VirtualNetwork net{clock, microseconds(100)};

private:
    VirtualBus& master_bus_;

public:
    master::Master master;
    std::vector<std::unique_ptr<MiniDevice>> devices;
    std::vector<ITimed*> extra_timed;
    std::vector<master::MasterEvent> events;
    std::map<master::MasterEventKind, std::uint64_t> event_counts;
};

} // namespace codrive::integration
