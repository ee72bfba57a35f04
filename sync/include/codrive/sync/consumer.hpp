// SPDX-License-Identifier: Apache-2.0
// SYNC consumer for simulated nodes: counter tracking and period monitoring (CiA 301 §7.2.5).
#pragma once

#include <codrive/core/cob_id.hpp>
#include <codrive/core/event_loop.hpp>
#include <codrive/core/frame.hpp>

#include <cstdint>
#include <functional>
#include <string>
#include <string_view>

namespace codrive::sync {

struct SyncConsumerConfig {
    NodeId node = 0;                   ///< for messages only; 0 = no "node n:" prefix
    std::uint32_t cob_id = cob::kSync; ///< 1005h bits 10..0
    /// Communication cycle period (1006h); 0 disables monitoring.
    Duration cycle_period{0};
    /// A SYNC is missing when none arrived within cycle_period × this factor (CiA 301 leaves
    /// the tolerance to the device; 1.5 accepts normal jitter but catches one lost SYNC).
    double timeout_factor = 1.5;
    /// Expected counter overflow (1019h): 0 = SYNC without counter (DLC 0), else DLC 1.
    std::uint8_t counter_overflow = 0;
};

enum class SyncEventKind : std::uint8_t {
    Missing,     ///< no SYNC within the timeout
    Recovered,   ///< SYNC received after Missing
    CounterJump, ///< counter did not follow last + 1 (wrapping at the overflow value)
    LengthError, ///< DLC does not match 1019h (CiA 301 EMCY 8240h)
};
[[nodiscard]] std::string_view to_string(SyncEventKind k);

struct SyncEvent {
    SyncEventKind kind = SyncEventKind::Missing;
    TimePoint time{};
    std::uint8_t counter = 0;  ///< received counter (CounterJump)
    std::uint8_t expected = 0; ///< expected counter (CounterJump)
    std::string text;          ///< "node 5: SYNC missing: none for 1.5 ms (cycle period 1 ms)"
};

/// Per received SYNC: counter (0 without), receive time, count since configure().
struct SyncReception {
    std::uint8_t counter = 0;
    TimePoint time{};
    std::uint64_t count = 0;
};

class SyncConsumer final : public ITimed {
public:
    using EventHandler = std::function<void(const SyncEvent&)>;
    using Hook = std::function<void(const SyncReception&)>;

    /// Errors: InvalidArgument for a COB-ID outside 11 bits, a negative period, an overflow
    /// value of 1 or above 240, or a timeout factor below 1.
    VoidResult configure(const SyncConsumerConfig& config);
    void set_handler(EventHandler handler) { handler_ = std::move(handler); }
    void set_hook(Hook hook) { hook_ = std::move(hook); }

    void on_frame(const Frame& frame, TimePoint now);
    [[nodiscard]] TimePoint next_deadline() const override { return deadline_; }
    void on_tick(TimePoint now) override;

    [[nodiscard]] std::uint64_t received() const { return received_; }
    [[nodiscard]] std::uint8_t last_counter() const { return last_counter_; }
    [[nodiscard]] bool missing() const { return missing_; }
    /// Interval between the last two SYNCs (0 before the second).
    [[nodiscard]] Duration last_interval() const { return last_interval_; }
    [[nodiscard]] std::uint64_t counter_jumps() const { return counter_jumps_; }
    [[nodiscard]] std::uint64_t length_errors() const { return length_errors_; }

private:
    void emit(SyncEventKind kind, TimePoint now, std::string text, std::uint8_t counter = 0,
              std::uint8_t expected = 0);
    [[nodiscard]] std::string prefix() const;

    SyncConsumerConfig config_;
    Duration timeout_{0};
    TimePoint deadline_ = kNever;
    TimePoint last_{};
    bool have_last_ = false;
    bool missing_ = false;
    std::uint8_t last_counter_ = 0;
    Duration last_interval_{0};
    std::uint64_t received_ = 0;
    std::uint64_t counter_jumps_ = 0;
    std::uint64_t length_errors_ = 0;
    EventHandler handler_;
    Hook hook_;
};

} // namespace codrive::sync
