// SPDX-License-Identifier: Apache-2.0
// In-process CAN network with any number of endpoints, deterministic time and fault injection.
#pragma once

#include <codrive/core/can_bus.hpp>
#include <codrive/core/event_loop.hpp>

#include <cstdint>
#include <deque>
#include <functional>
#include <memory>
#include <random>
#include <string>
#include <vector>

namespace codrive {

class VirtualNetwork;

/// What the fault injector does with one frame.
struct FaultAction {
    bool drop = false;
    Duration delay{0};    ///< extra delivery delay (reorders against later frames)
    int duplicates = 0;   ///< extra copies delivered
    bool corrupt = false; ///< flip one payload bit (the CRC would catch it on a real bus;
                          ///< here it models corruption that slips past, for SDO-CRC tests)
    static FaultAction none() { return {}; }
};

/// Random fault rates (0..1), applied with a seeded generator so runs repeat exactly.
struct FaultRates {
    double drop = 0;
    double duplicate = 0;
    double reorder = 0; ///< delay a frame by `reorder_delay` so later ones overtake it
    double corrupt = 0;
    Duration reorder_delay = std::chrono::microseconds(500);
    std::uint64_t seed = 1;
};

/// An endpoint on a VirtualNetwork. Frames it sends reach every other endpoint (never itself,
/// unless loopback is enabled), in order, after the network latency.
class VirtualBus final : public ICanBus {
public:
    VoidResult send(const Frame& frame) override;
    void set_frame_handler(FrameHandler handler) override { frame_handler_ = std::move(handler); }
    void set_event_handler(EventHandler handler) override { event_handler_ = std::move(handler); }
    [[nodiscard]] std::size_t tx_pending() const override { return 0; }
    [[nodiscard]] const BusStats& stats() const override { return stats_; }
    [[nodiscard]] const std::string& name() const override { return name_; }

    void set_loopback(bool on) { loopback_ = on; }
    /// Detaches: the endpoint neither sends nor receives (a powered-off node).
    void set_connected(bool on) { connected_ = on; }
    [[nodiscard]] bool connected() const { return connected_; }

private:
    friend class VirtualNetwork;
    VirtualBus(VirtualNetwork& net, std::string name) : net_(net), name_(std::move(name)) {}
    VirtualNetwork& net_;
    std::string name_;
    FrameHandler frame_handler_;
    EventHandler event_handler_;
    BusStats stats_;
    bool loopback_ = false;
    bool connected_ = true;
};

/// The network. Time comes from the clock given at construction; `deliver()` hands out every
/// frame that is due at clock.now(), including frames sent by handlers while delivering.
class VirtualNetwork final : public ITimed {
public:
    explicit VirtualNetwork(const IClock& clock, Duration latency = Duration{0});

    /// Creates an endpoint; it lives as long as the network.
    VirtualBus& endpoint(std::string name);

    /// Delivers all frames due now. Returns how many were delivered.
    std::size_t deliver();
    /// Fake-clock helper: advances `clock` step by step to `until`, delivering and ticking the
    /// given services at every deadline on the way.
    void run_until(FakeClock& clock, TimePoint until, std::vector<ITimed*> services = {});

    /// Custom per-frame fault decision (sender name, frame) — overrides the random rates.
    void set_fault_filter(std::function<FaultAction(const std::string&, const Frame&)> filter) {
        fault_filter_ = std::move(filter);
    }
    void set_fault_rates(const FaultRates& rates);
    /// Bus-off: every endpoint gets a StateChanged(BusOff) event and sends fail until
    /// restored (then Restarted + ErrorActive).
    void set_bus_off(bool on);
    [[nodiscard]] bool bus_off() const { return bus_off_; }

    /// Every frame that went over the wire (after faults), for assertions; off by default.
    void set_recording(bool on) { recording_ = on; }
    [[nodiscard]] const std::vector<Frame>& recorded() const { return recorded_; }
    void clear_recorded() { recorded_.clear(); }

    [[nodiscard]] TimePoint next_deadline() const override;
    void on_tick(TimePoint now) override;
    [[nodiscard]] std::uint64_t frames_sent() const { return frames_sent_; }
    [[nodiscard]] std::uint64_t frames_dropped() const { return frames_dropped_; }

private:
    friend class VirtualBus;
    VoidResult transmit(VirtualBus& from, const Frame& frame);
    FaultAction decide(const std::string& sender, const Frame& frame);

    struct InFlight {
        TimePoint due;
        std::uint64_t seq;
        VirtualBus* from;
        Frame frame;
    };
    const IClock& clock_;
    Duration latency_;
    std::vector<std::unique_ptr<VirtualBus>> endpoints_;
    std::deque<InFlight> queue_; ///< kept sorted by (due, seq)
    std::uint64_t seq_ = 0;
    std::function<FaultAction(const std::string&, const Frame&)> fault_filter_;
    FaultRates rates_;
    bool have_rates_ = false;
    std::mt19937_64 rng_{1};
    bool bus_off_ = false;
    bool recording_ = false;
    std::vector<Frame> recorded_;
    std::uint64_t frames_sent_ = 0;
    std::uint64_t frames_dropped_ = 0;
    bool delivering_ = false;
};

} // namespace codrive
