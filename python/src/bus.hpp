// SPDX-License-Identifier: Apache-2.0
// The buses Python talks through (SocketCAN, in-process virtual network) and how a call waits.
#pragma once

#include <codrive/core/can_bus.hpp>
#include <codrive/core/virtual_bus.hpp>
#include <codrive/nmt/master.hpp>
#include <codrive/sdo/blocking.hpp>
#include <codrive/sdo/client_manager.hpp>

#include <atomic>
#include <cstdint>
#include <functional>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

namespace codrive::python {

/// A bus with the master's SDO clients and NMT master on it. Calls from Python release the GIL,
/// take mutex() and run the bus with run_until() until their transfer ends: one Python thread
/// drives a bus at a time, and the C++ services never see two threads (wait.hpp says how the
/// bus passes between threads).
class Bus {
public:
    virtual ~Bus() = default;
    Bus(const Bus&) = delete;
    Bus& operator=(const Bus&) = delete;

    /// Runs the bus (dispatching frames and timers) until `done()` holds or `limit` has passed
    /// (on the bus's clock). True if done() held. Call without the GIL, holding mutex().
    virtual bool run_until(const std::function<bool()>& done, Duration limit) = 0;
    /// True on a VirtualNetwork (simulated time), false on a real interface.
    [[nodiscard]] virtual bool simulated() const { return false; }
    /// The bus's time (simulated on a VirtualNetwork).
    [[nodiscard]] virtual TimePoint now() const = 0;
    /// "vcan0", "virtual".
    [[nodiscard]] virtual std::string name() const = 0;

    [[nodiscard]] sdo::SdoClientManager& sdo_clients() { return *clients_; }
    [[nodiscard]] nmt::NmtMaster& nmt() { return *nmt_; }
    [[nodiscard]] std::mutex& mutex() { return mutex_; }
    /// Threads waiting to take the bus (to start a request or make a short call); the thread
    /// running the bus lets go of it as soon as this is non-zero (see BusTurn in wait.hpp).
    [[nodiscard]] std::atomic<int>& submitters() { return submitters_; }
    /// Results delivered so far (every request's callback counts one): the thread running the
    /// bus lets go of it when another thread's result came, so that thread returns at once.
    [[nodiscard]] std::atomic<std::uint64_t>& delivered() { return delivered_; }
    /// True while a thread runs the bus (inside run_until() for a request).
    [[nodiscard]] std::atomic<bool>& running() { return running_; }
    /// Set by a thread that let go of the bus for another one, cleared by the next to take it.
    [[nodiscard]] std::atomic<bool>& handoff() { return handoff_; }
    /// Ends the current wait of the thread running the bus at once (thread-safe); without it a
    /// running bus notices submitters() at its next wake-up.
    virtual void interrupt() {}
    /// The SDO timeout used when a call gives none.
    [[nodiscard]] Duration default_timeout() const { return default_timeout_; }

protected:
    explicit Bus(Duration default_timeout) : default_timeout_(default_timeout) {}
    /// Puts the NMT master on `can` and feeds it and `clients` every frame `can` receives.
    void attach(ICanBus& can, sdo::SdoClientManager& clients);

private:
    sdo::SdoClientManager* clients_ = nullptr;
    std::unique_ptr<nmt::NmtMaster> nmt_;
    std::mutex mutex_;
    std::atomic<int> submitters_{0};
    std::atomic<std::uint64_t> delivered_{0};
    std::atomic<bool> handoff_{false};
    std::atomic<bool> running_{false};
    Duration default_timeout_;
};

/// A SocketCAN interface, driven by the blocking SDO client's own event loop.
class SocketBus final : public Bus {
public:
    /// Errors: the one sentence of describe_can_open_error() (no SocketCAN, no such interface).
    static tl::expected<std::shared_ptr<SocketBus>, std::string> open(const std::string& ifname,
                                                                      Duration default_timeout);
    bool run_until(const std::function<bool()>& done, Duration limit) override;
    void interrupt() override { blocking_->loop().stop(); }
    [[nodiscard]] TimePoint now() const override { return SteadyClock::now(); }
    [[nodiscard]] std::string name() const override { return ifname_; }

private:
    SocketBus(std::unique_ptr<sdo::BlockingSdo> blocking, std::string ifname,
              Duration default_timeout);
    std::unique_ptr<sdo::BlockingSdo> blocking_;
    std::string ifname_;
};

/// An in-process CAN network on simulated time: waiting advances the clock straight to the next
/// deadline, so a test runs as fast as the CPU allows and repeats exactly. Simulated devices
/// join with add_device().
class VirtualNet final : public Bus {
public:
    explicit VirtualNet(Duration default_timeout);
    ~VirtualNet() override;
    bool run_until(const std::function<bool()>& done, Duration limit) override;
    [[nodiscard]] TimePoint now() const override { return clock_.now(); }
    [[nodiscard]] bool simulated() const override { return true; }
    [[nodiscard]] std::string name() const override { return "virtual"; }

    /// A new endpoint for a device; it lives as long as the network.
    VirtualBus& endpoint(const std::string& name) { return net_.endpoint(name); }
    /// A device's timed work, run while the network runs. Hold mutex().
    void add_service(ITimed* service) { services_.push_back(service); }
    void remove_service(ITimed* service);
    /// Simulated seconds since the network was made.
    [[nodiscard]] double seconds() const;

private:
    FakeClock clock_;
    TimePoint start_;
    VirtualNetwork net_;
    VirtualBus& master_;
    std::unique_ptr<sdo::SdoClientManager> clients_;
    std::vector<ITimed*> services_;
};

} // namespace codrive::python
