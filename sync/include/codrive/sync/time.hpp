// SPDX-License-Identifier: Apache-2.0
// TIME producer and consumer (CiA 301 §7.2.6): TIME_OF_DAY, a broadcast like SYNC.
#pragma once

#include <codrive/core/can_bus.hpp>
#include <codrive/core/cob_id.hpp>
#include <codrive/core/error.hpp>
#include <codrive/core/frame.hpp>

#include <array>
#include <chrono>
#include <cstdint>
#include <functional>
#include <span>
#include <string>

namespace codrive::sync {

/// CiA 301 TIME_OF_DAY: milliseconds after midnight (28 bits, 4 reserved bits 0) and days since
/// 1984-01-01 (16 bits). 6 bytes little-endian on the wire.
struct TimeOfDay {
    std::uint32_t ms_after_midnight = 0; ///< 0..86'399'999
    std::uint16_t days_since_1984 = 0;
    friend bool operator==(const TimeOfDay&, const TimeOfDay&) = default;
};

inline constexpr std::size_t kTimeOfDayLen = 6;
inline constexpr std::uint32_t kMsPerDay = 86'400'000;

/// The 6 wire bytes. Bits 28..31 of the first word are reserved and sent as 0.
[[nodiscard]] std::array<std::uint8_t, kTimeOfDayLen> encode(const TimeOfDay& t);
/// Decodes 6 bytes. Errors: InvalidFrame if shorter than 6 bytes or the millisecond field is
/// not below 86'400'000 (reserved bits are ignored).
[[nodiscard]] Result<TimeOfDay> decode_time_of_day(std::span<const std::uint8_t> bytes);

/// Wall-clock conversion (UTC; leap seconds are not represented, as in CiA 301).
/// Errors: OutOfRange before 1984-01-01 or after day 65535 (year 2163).
[[nodiscard]] Result<TimeOfDay> to_time_of_day(std::chrono::system_clock::time_point t);
[[nodiscard]] std::chrono::system_clock::time_point to_system_time(const TimeOfDay& t);
/// "2026-11-21 05:39:00.123 UTC".
[[nodiscard]] std::string to_string(const TimeOfDay& t);

/// Broadcasts TIME on 100h (1012h bit 30 "produce").
class TimeProducer {
public:
    explicit TimeProducer(ICanBus& bus, std::uint32_t cob_id = cob::kTime)
        : bus_(bus), cob_id_(cob_id) {}
    /// Errors: the bus's send errors.
    VoidResult publish(const TimeOfDay& t);
    /// Converts then publishes. Errors: OutOfRange (see to_time_of_day), send errors.
    VoidResult publish(std::chrono::system_clock::time_point t);
    [[nodiscard]] std::uint64_t sent() const { return sent_; }

private:
    ICanBus& bus_;
    std::uint32_t cob_id_;
    std::uint64_t sent_ = 0;
};

/// Receives TIME (1012h bit 31 "consume"); keeps the last value and when it arrived.
class TimeConsumer {
public:
    using Handler = std::function<void(const TimeOfDay&, TimePoint rx_time)>;

    explicit TimeConsumer(std::uint32_t cob_id = cob::kTime) : cob_id_(cob_id) {}
    void set_handler(Handler handler) { handler_ = std::move(handler); }

    /// Handles TIME frames; malformed ones are counted, not applied.
    void on_frame(const Frame& frame, TimePoint now);

    [[nodiscard]] bool has_time() const { return received_ != 0; }
    [[nodiscard]] const TimeOfDay& last() const { return last_; }
    [[nodiscard]] TimePoint last_rx() const { return last_rx_; }
    /// Network time at monotonic `now`: last TIME plus the time elapsed since it arrived.
    /// Errors: NotPermitted before the first TIME.
    [[nodiscard]] Result<std::chrono::system_clock::time_point> network_time(TimePoint now) const;
    [[nodiscard]] std::uint64_t received() const { return received_; }
    [[nodiscard]] std::uint64_t malformed() const { return malformed_; }

private:
    std::uint32_t cob_id_;
    TimeOfDay last_{};
    TimePoint last_rx_{};
    Handler handler_;
    std::uint64_t received_ = 0;
    std::uint64_t malformed_ = 0;
};

} // namespace codrive::sync
