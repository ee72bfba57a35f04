// SPDX-License-Identifier: Apache-2.0
// The simulated ESC's drifting local clock and its drift control loop (model documented in
// dc_clock.hpp and docs/conformance.md).
#include <codrive/sim/ecat/dc_clock.hpp>

#include <algorithm>
#include <cmath>

namespace codrive::sim::ecat {

std::uint64_t DcClock::local_time(TimePoint now) const {
    const auto host = std::chrono::duration_cast<nanoseconds>(now.time_since_epoch()).count();
    const auto drift = std::llround(static_cast<double>(host) * drift_ppm_ * 1e-6);
    return static_cast<std::uint64_t>(host + base_ns_ + drift);
}

double DcClock::correction_at(double local) const {
    const double since = local - anchor_;
    const double slewed =
        slew_span_ <= 0 ? slew_ : slew_ * std::clamp(since / slew_span_, 0.0, 1.0);
    return at_anchor_ + frequency_ * since + slewed;
}

std::int64_t DcClock::correction(TimePoint now) const {
    return std::llround(correction_at(static_cast<double>(local_time(now))));
}

void DcClock::reset(TimePoint now) {
    have_sample_ = false;
    frequency_ = 0;
    at_anchor_ = 0;
    slew_ = 0;
    slew_span_ = 0;
    interval_ = 0;
    anchor_ = static_cast<double>(local_time(now));
    mean_error_ = 0;
    last_error_ = 0;
}

std::int64_t DcClock::on_difference(TimePoint now, std::int64_t error_ns, unsigned filter_depth) {
    const auto local = static_cast<double>(local_time(now));
    const auto e = static_cast<double>(error_ns);
    // What the phase slew set at the last sample has applied since (anchor_ is that sample).
    const double since = local - anchor_;
    const double applied =
        slew_span_ <= 0 ? slew_ : slew_ * std::clamp(since / slew_span_, 0.0, 1.0);
    // Fold what the correction reached so far, then steer from here.
    at_anchor_ = correction_at(local);
    anchor_ = local;
    if (have_sample_ && local > last_sample_) {
        interval_ = local - last_sample_;
        // The error changed by (rate error left) * interval + the slew applied: take out the
        // slew and correct the frequency by a part of the rate error measured.
        const double rate = (e - last_error_ - applied) / interval_;
        frequency_ = std::clamp(frequency_ - kFrequencyGain * rate, -kMaxFrequency, kMaxFrequency);
    }
    const bool first = !have_sample_;
    have_sample_ = true;
    last_sample_ = local;
    last_error_ = e;
    // Slew a part of the phase error away over about one interval, never faster than kMaxSlew.
    slew_span_ = interval_ > 0 ? interval_ : 1'000'000.0;
    const double limit = kMaxSlew * slew_span_;
    slew_ = std::clamp(-kPhaseGain * e, -limit, limit);
    const double weight = std::ldexp(1.0, -static_cast<int>(std::min(filter_depth, 15U)));
    mean_error_ = first ? e : mean_error_ + (e - mean_error_) * weight;
    return std::llround(mean_error_);
}

double default_clock_drift_ppm(std::size_t position) {
    const double magnitude = 20.0 + 10.0 * static_cast<double>((position / 2) % 3);
    return position % 2 == 0 ? magnitude : -magnitude;
}

} // namespace codrive::sim::ecat
