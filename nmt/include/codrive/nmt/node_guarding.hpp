// SPDX-License-Identifier: Apache-2.0
// Node guarding, master side (CiA 301 §7.2.8.3.1: guard time 100Ch, life time factor 100Dh).
#pragma once

#include <codrive/core/can_bus.hpp>
#include <codrive/core/cob_id.hpp>
#include <codrive/core/event_loop.hpp>
#include <codrive/core/frame.hpp>
#include <codrive/nmt/error_control_event.hpp>

#include <array>
#include <cstdint>

namespace codrive::nmt {

/// Per-node guarding counters.
struct GuardStats {
    std::uint64_t requests = 0;      ///< RTRs sent
    std::uint64_t replies = 0;       ///< valid replies
    std::uint64_t missed = 0;        ///< RTRs that got no reply before the next one
    std::uint64_t toggle_errors = 0; ///< replies with the wrong toggle bit
};

/// Polls guarded nodes with an RTR on 700h + node every guard time; each node answers with its
/// state and a toggle bit (bit 7) that starts at 0 and alternates. If no valid reply arrives
/// within the node life time (guard time × life time factor) a GuardTimeout is reported.
/// A reply with the wrong toggle bit is reported and treated as not received (CiA 301
/// §7.2.8.3.1); the expected toggle then follows the node so one glitch gives one event.
class NodeGuardingMaster final : public ITimed {
public:
    explicit NodeGuardingMaster(ICanBus& bus) : bus_(bus) {}

    void set_handler(ErrorControlHandler handler) { handler_ = std::move(handler); }

    /// Starts guarding `node`: the first RTR goes out at `now`. Errors: InvalidArgument for a
    /// node id outside 1..127, a zero guard time or a zero life time factor (both disable
    /// guarding per CiA 301; use remove()).
    VoidResult add(NodeId node, milliseconds guard_time, std::uint8_t life_time_factor,
                   TimePoint now);
    void remove(NodeId node);

    /// Handles replies (data frames on 701h..77Fh); a boot-up (00h) restarts the toggle at 0.
    void on_frame(const Frame& frame, TimePoint now);

    [[nodiscard]] TimePoint next_deadline() const override { return next_; }
    void on_tick(TimePoint now) override;

    [[nodiscard]] bool timed_out(NodeId node) const;
    [[nodiscard]] NmtState state(NodeId node) const;
    [[nodiscard]] GuardStats stats(NodeId node) const;

private:
    struct Entry {
        milliseconds guard_time{0};
        std::uint8_t factor = 0;
        bool active = false;
        bool awaiting = false; ///< an RTR is outstanding
        bool timed_out = false;
        std::uint8_t expected_toggle = 0;
        TimePoint start{};   ///< RTR grid origin
        std::uint64_t k = 0; ///< RTRs sent on this grid
        TimePoint next_rtr = kNever;
        TimePoint last_valid{}; ///< last valid reply (or add() time)
        TimePoint life_deadline = kNever;
        NmtState state = NmtState::Unknown;
        GuardStats stats;
    };
    void emit(NodeId node, ErrorControlEventKind kind, TimePoint now, std::string text);
    void recompute();

    ICanBus& bus_;
    std::array<Entry, kMaxNodeId + 1> nodes_{};
    TimePoint next_ = kNever;
    ErrorControlHandler handler_;
    std::uint64_t send_errors_ = 0;
};

/// Slave side (for simulators): answers guard RTRs with state | toggle and, once the first
/// RTR has arrived, watches that the master keeps guarding (life guarding, CiA 301
/// §7.2.8.3.1): no RTR within guard time × life time factor → LifeGuardLost.
class NodeGuardingResponder final : public ITimed {
public:
    NodeGuardingResponder(ICanBus& bus, NodeId node) : bus_(bus), node_(node) {}

    void set_handler(ErrorControlHandler handler) { handler_ = std::move(handler); }
    void set_state(NmtState state) { state_ = state; }
    [[nodiscard]] NmtState state() const { return state_; }

    /// Sets 100Ch (ms) and 100Dh; life guarding is off when either is 0.
    void set_life_guarding(milliseconds guard_time, std::uint8_t life_time_factor);
    /// Restarts the toggle at 0 (after reset communication or boot-up, CiA 301 §7.2.8.3.1).
    void reset_toggle() { toggle_ = 0; }

    /// Answers an RTR on 700h + node; ignores everything else.
    void on_frame(const Frame& frame, TimePoint now);

    [[nodiscard]] TimePoint next_deadline() const override { return deadline_; }
    void on_tick(TimePoint now) override;

    [[nodiscard]] bool life_guard_lost() const { return lost_; }
    [[nodiscard]] std::uint64_t replies() const { return replies_; }
    /// Test hook for fault injection: the next reply carries the wrong toggle bit.
    void corrupt_next_toggle() { corrupt_next_ = true; }

private:
    ICanBus& bus_;
    NodeId node_;
    NmtState state_ = NmtState::PreOperational;
    std::uint8_t toggle_ = 0;
    milliseconds guard_time_{0};
    std::uint8_t factor_ = 0;
    TimePoint last_rtr_{};
    TimePoint deadline_ = kNever;
    bool lost_ = false;
    bool corrupt_next_ = false;
    std::uint64_t replies_ = 0;
    ErrorControlHandler handler_;
};

} // namespace codrive::nmt
