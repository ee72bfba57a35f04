// SPDX-License-Identifier: Apache-2.0
// SYNC producer (CiA 301 §7.2.5, objects 1005h/1006h/1019h) on absolute deadlines.
#pragma once

#include <codrive/core/can_bus.hpp>
#include <codrive/core/cob_id.hpp>
#include <codrive/core/event_loop.hpp>
#include <codrive/sync/period_stats.hpp>

#include <cstdint>
#include <functional>

namespace codrive::sync {

/// SYNC producer configuration.
struct SyncConfig {
    Duration period = milliseconds(1); ///< communication cycle period (1006h, µs on the wire)
    /// Synchronous counter overflow value (1019h): 0 = no counter (DLC 0), else 2..240 and the
    /// SYNC carries a counter 1..overflow (DLC 1).
    std::uint8_t counter_overflow = 0;
    std::uint32_t cob_id = cob::kSync; ///< 1005h bits 10..0
};

/// Passed to the hook on every SYNC.
struct SyncInfo {
    std::uint64_t cycle = 0;  ///< 0 for the first SYNC after start()
    std::uint8_t counter = 0; ///< the counter sent, 0 when the SYNC has none
    TimePoint ideal{};        ///< start + cycle·period
    TimePoint actual{};       ///< when it was sent (the `now` of on_tick)
};

/// Called after each SYNC was handed to the bus. Runs on the cyclic path: it must not block.
using SyncHook = std::function<void(const SyncInfo&)>;
/// Sends the SYNC frame itself, together with what goes out with it (the controller: the
/// cycle's RPDOs behind it in one ICanBus::send_many(), PdoMaster::on_sync(cycle, now, sync)).
/// Returns whether the bus took the SYNC. Runs on the cyclic path: it must not block.
using SyncSender = std::function<bool(const Frame& sync, const SyncInfo&)>;

/// Sends SYNC every period at start + k·period (never "now + period", so late ticks do not
/// accumulate into drift). A tick later than a whole period sends one SYNC and skips the
/// missed slots (counted in skipped()). The error actual − ideal of every SYNC goes into
/// period_error(). No allocation after configure().
class SyncProducer final : public ITimed {
public:
    explicit SyncProducer(ICanBus& bus) : bus_(bus) {}

    /// Errors: InvalidArgument for a non-positive period, an overflow value of 1 or above 240,
    /// or a COB-ID outside 11 bits. Stops a running producer.
    VoidResult configure(const SyncConfig& config);
    [[nodiscard]] const SyncConfig& config() const { return config_; }

    /// Starts the cycle: the first SYNC is due at `start`. Resets the counter to 1 and the
    /// statistics.
    void start(TimePoint start);
    void stop();
    [[nodiscard]] bool running() const { return running_; }

    void set_hook(SyncHook hook) { hook_ = std::move(hook); }
    /// Hands every SYNC frame to `sender` instead of ICanBus::send() (empty: send it alone).
    /// The hook, if any, still runs after it.
    void set_sender(SyncSender sender) { sender_ = std::move(sender); }

    [[nodiscard]] TimePoint next_deadline() const override { return running_ ? next_ : kNever; }
    void on_tick(TimePoint now) override;

    /// Ideal time of cycle k: start + k·period.
    [[nodiscard]] TimePoint ideal_time(std::uint64_t k) const;
    [[nodiscard]] std::uint64_t sent() const { return sent_; }
    [[nodiscard]] std::uint64_t skipped() const { return skipped_; }
    [[nodiscard]] std::uint64_t send_errors() const { return send_errors_; }
    [[nodiscard]] std::uint8_t last_counter() const { return last_counter_; }
    /// Actual send time minus ideal time, per SYNC.
    [[nodiscard]] const PeriodStats& period_error() const { return stats_; }

private:
    ICanBus& bus_;
    SyncConfig config_;
    bool running_ = false;
    TimePoint start_{};
    std::uint64_t k_ = 0; ///< index of the next slot
    TimePoint next_ = kNever;
    std::uint8_t counter_ = 1;
    std::uint8_t last_counter_ = 0;
    SyncHook hook_;
    SyncSender sender_;
    PeriodStats stats_;
    std::uint64_t sent_ = 0;
    std::uint64_t skipped_ = 0;
    std::uint64_t send_errors_ = 0;
};

} // namespace codrive::sync
