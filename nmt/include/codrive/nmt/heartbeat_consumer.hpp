// SPDX-License-Identifier: Apache-2.0
// Heartbeat consumer (CiA 301 §7.2.8.3.2, object 1016h): per-node consumer time monitoring.
#pragma once

#include <codrive/core/event_loop.hpp>
#include <codrive/core/frame.hpp>
#include <codrive/nmt/error_control_event.hpp>

#include <array>
#include <cstdint>

namespace codrive::nmt {

/// Watches heartbeats of up to 127 nodes. Monitoring of a node starts with its first heartbeat
/// after configure() (CiA 301 §7.2.8.3.2: "the consumer time starts with the first heartbeat");
/// a boot-up message does not start it, because a freshly booted node produces no heartbeat
/// until its 1017h is configured.
///
/// A loss is reported when `now >= last heartbeat + consumer time`, exactly once per loss.
class HeartbeatConsumer final : public ITimed {
public:
    HeartbeatConsumer() = default;

    void set_handler(ErrorControlHandler handler) { handler_ = std::move(handler); }

    /// Sets the consumer time of `node` (1016h sub-entry: node in bits 23..16, time in ms).
    /// A time of 0 disables monitoring of that node (events for boot-up and state changes are
    /// still reported). Errors: InvalidArgument for a node id outside 1..127.
    VoidResult configure(NodeId node, milliseconds consumer_time);
    /// Parses and applies a 1016h sub-entry value. Errors: InvalidArgument as above.
    VoidResult configure_from_1016(std::uint32_t value);
    /// Stops watching the node and forgets its state.
    void remove(NodeId node);
    /// The next boot-up of `node` is expected (the master reset it): reported as BootUp.
    void expect_boot_up(NodeId node);

    /// Handles 701h..77Fh data frames; ignores everything else.
    void on_frame(const Frame& frame, TimePoint now);

    [[nodiscard]] TimePoint next_deadline() const override;
    void on_tick(TimePoint now) override;

    /// True while a node is monitored and its heartbeat is overdue.
    [[nodiscard]] bool lost(NodeId node) const;
    [[nodiscard]] NmtState state(NodeId node) const;
    [[nodiscard]] std::uint64_t malformed() const { return malformed_; }

private:
    struct Entry {
        milliseconds consumer_time{0};
        TimePoint last{};
        TimePoint deadline = kNever;
        NmtState state = NmtState::Unknown;
        bool configured = false;
        bool running = false; ///< heard a heartbeat since boot-up / configure
        bool lost = false;
        bool expect_boot = false;
    };
    void emit(NodeId node, ErrorControlEventKind kind, TimePoint now, std::string text);
    void recompute_deadline();

    std::array<Entry, kMaxNodeId + 1> nodes_{};
    TimePoint next_ = kNever;
    ErrorControlHandler handler_;
    std::uint64_t malformed_ = 0;
};

} // namespace codrive::nmt
