// SPDX-License-Identifier: Apache-2.0
// The simulated ESC's distributed clock: a free-running local clock with a rate error and the
// drift control loop that steers its system time towards the distributed reference time.
#pragma once

#include <codrive/core/time.hpp>

#include <cstddef>
#include <cstdint>

namespace codrive::sim::ecat {

/// One slave's DC clock (model of ETG.1000.4 §9.1 "distributed clocks", register view in the
/// ET1100 datasheet 0x0900..0x0935).
///
/// - The local clock (0x0918 and the receive time latches) runs at (1 + drift) times the host
///   clock: `local = base + host + host * drift_ppm / 1e6`. Real oscillators are off by tens of
///   ppm; every simulated slave can be given its own error.
/// - The system time is local + system time offset (0x0920, written by the master) + the drift
///   control correction below.
/// - Drift control: each time the master distributes the reference clock's system time (an
///   ARMW/FRMW writing 0x0910), the slave measures `error = own system time - (received +
///   delay 0x0928)`, reports its mean in 0x092C and steers. The ESC datasheets describe the
///   loop only as registers (0x0930 speed counter start, 0x0932 speed counter diff, 0x0934/0x0935
///   filter depths); the standard extracts in this project are silent on its law, so the model
///   is a documented model (docs/conformance.md): a phase slew removes kPhaseGain of the error
///   over about the next interval (never a step: the system time stays monotonic, at most
///   kMaxSlew faster or slower), and a frequency correction moves by kFrequencyGain of the rate
///   error measured between two samples (the change of the error less the slew applied, over
///   the time between them; clamped to ±kMaxFrequency, as a speed counter has a range). With
///   samples every cycle the error stays bounded; without them it grows at the rate error the
///   loop has not learned.
class DcClock {
public:
    static constexpr double kPhaseGain = 0.25;
    static constexpr double kFrequencyGain = 0.1;
    static constexpr double kMaxSlew = 1e-3;      ///< slew rate limit (1000 ppm)
    static constexpr double kMaxFrequency = 5e-4; ///< frequency correction limit (500 ppm)

    DcClock() = default;
    DcClock(std::int64_t base_ns, double drift_ppm) : base_ns_(base_ns), drift_ppm_(drift_ppm) {}

    void set_drift_ppm(double ppm) { drift_ppm_ = ppm; }
    [[nodiscard]] double drift_ppm() const { return drift_ppm_; }

    /// The free-running local time (ns) at host time `now`.
    [[nodiscard]] std::uint64_t local_time(TimePoint now) const;
    /// What the drift control adds to local time + offset at `now` (ns).
    [[nodiscard]] std::int64_t correction(TimePoint now) const;
    /// The reference time arrived: `error_ns` = own system time minus the received one (after
    /// the delay). Steers the loop; returns the mean error for 0x092C, filtered with depth
    /// `filter_depth` (0x0934 bits 3:0: mean over 2^depth samples, 0 = the last sample).
    std::int64_t on_difference(TimePoint now, std::int64_t error_ns, unsigned filter_depth);
    /// Forgets the loop state (a new system time offset was written: a new start).
    void reset(TimePoint now);
    /// The frequency correction the loop applies now (ppm; the 0x0932 speed counter diff's role).
    [[nodiscard]] double frequency_ppm() const { return frequency_ * 1e6; }

private:
    [[nodiscard]] double correction_at(double local) const;

    std::int64_t base_ns_ = 0;
    double drift_ppm_ = 0;
    bool have_sample_ = false;
    double last_sample_ = 0; ///< local time of the last sample
    double interval_ = 0;    ///< local time between the last two samples
    double frequency_ = 0;   ///< ratio added to the clock's rate
    double anchor_ = 0;      ///< local time the correction below was folded at
    double at_anchor_ = 0;   ///< correction (ns) at anchor_
    double slew_ = 0;        ///< phase correction (ns) spread over slew_span_ after anchor_
    double slew_span_ = 0;
    double last_error_ = 0; ///< error at the last sample
    double mean_error_ = 0;
};

/// codrive-ecat-sim's clock error for the slave at `position` when --clock-drift-ppm does not set
/// one: +20, -20, +30, -30, +40, -40, +20, ... ppm (crystal oscillators are off by tens of ppm,
/// each its own way).
[[nodiscard]] double default_clock_drift_ppm(std::size_t position);

} // namespace codrive::sim::ecat
