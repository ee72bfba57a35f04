// SPDX-License-Identifier: Apache-2.0
// Heartbeat producer (CiA 301 §7.2.8.3.2, object 1017h) for the master and for simulators.
#pragma once

#include <codrive/core/can_bus.hpp>
#include <codrive/core/cob_id.hpp>
#include <codrive/core/event_loop.hpp>
#include <codrive/nmt/state.hpp>

namespace codrive::nmt {

/// Sends `700h + node` with the current state every producer time. Deadlines are absolute
/// (start + k·period) so the period does not drift with tick latency.
class HeartbeatProducer final : public ITimed {
public:
    /// Errors are reported by the calls; the constructor only stores its arguments.
    HeartbeatProducer(ICanBus& bus, NodeId node) : bus_(bus), node_(node) {}

    /// Sets the producer time (1017h, ms; 0 stops producing) and restarts the cycle at `now`:
    /// the first heartbeat goes out at now + period.
    void set_period(milliseconds period, TimePoint now);
    [[nodiscard]] milliseconds period() const { return period_; }

    void set_state(NmtState state) { state_ = state; }
    [[nodiscard]] NmtState state() const { return state_; }

    /// Sends the boot-up message (state 00h) and moves to pre-operational (CiA 301 §7.3.2.1:
    /// after initialisation the node enters pre-operational autonomously).
    /// Errors: InvalidArgument for a node id outside 1..127; the bus's send errors.
    VoidResult send_boot_up();

    [[nodiscard]] TimePoint next_deadline() const override { return next_; }
    void on_tick(TimePoint now) override;

    [[nodiscard]] std::uint64_t sent() const { return sent_; }
    [[nodiscard]] std::uint64_t send_errors() const { return send_errors_; }

private:
    ICanBus& bus_;
    NodeId node_;
    NmtState state_ = NmtState::PreOperational;
    milliseconds period_{0};
    TimePoint start_{};
    std::uint64_t k_ = 0;
    TimePoint next_ = kNever;
    std::uint64_t sent_ = 0;
    std::uint64_t send_errors_ = 0;
};

} // namespace codrive::nmt
