// SPDX-License-Identifier: Apache-2.0
// Monotonic time types and the clock abstraction (real and fake) used by every service.
#pragma once

#include <chrono>
#include <cstdint>

namespace codrive {

/// All protocol time is monotonic (CLOCK_MONOTONIC), never wall-clock.
using SteadyClock = std::chrono::steady_clock;
using TimePoint = SteadyClock::time_point;
using Duration = std::chrono::nanoseconds;
using std::chrono::microseconds;
using std::chrono::milliseconds;
using std::chrono::nanoseconds;
using std::chrono::seconds;

/// "No deadline": a service with nothing scheduled reports this from next_deadline().
inline constexpr TimePoint kNever = TimePoint::max();

/// Source of the current time; injected so tests can run on a fake clock.
class IClock {
public:
    virtual ~IClock() = default;
    [[nodiscard]] virtual TimePoint now() const = 0;
};

/// The real monotonic clock.
class RealClock final : public IClock {
public:
    [[nodiscard]] TimePoint now() const override { return SteadyClock::now(); }
    /// A process-wide instance.
    static RealClock& instance();
};

/// A manually advanced clock for deterministic tests.
class FakeClock final : public IClock {
public:
    explicit FakeClock(TimePoint start = TimePoint{} + std::chrono::hours(1)) : now_(start) {}
    [[nodiscard]] TimePoint now() const override { return now_; }
    void advance(Duration d) { now_ += d; }
    void set(TimePoint t) { now_ = t; }

private:
    TimePoint now_;
};

/// Milliseconds as a double, for messages.
inline double to_ms(Duration d) {
    return std::chrono::duration<double, std::milli>(d).count();
}

} // namespace codrive
