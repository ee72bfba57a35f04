// SPDX-License-Identifier: Apache-2.0
// Progress bar drawing for `codrive sdo`.
#include "sdo_progress.hpp"

#include "cli_common.hpp"

#include <fmt/format.h>

#include <string>

namespace codrive::cli {

SdoProgressBar::SdoProgressBar() : enabled_(stderr_is_tty()), start_(SteadyClock::now()) {}

SdoProgressBar::~SdoProgressBar() {
    finish();
}

void SdoProgressBar::update(std::size_t done, std::optional<std::size_t> total) {
    if (!enabled_) {
        return;
    }
    const TimePoint now = SteadyClock::now();
    // Short transfers draw nothing; long ones redraw at most 10 times a second.
    if (now - start_ < std::chrono::seconds(1) ||
        now - last_draw_ < std::chrono::milliseconds(100)) {
        return;
    }
    last_draw_ = now;
    const double secs = std::chrono::duration<double>(now - start_).count();
    const double kib_s = static_cast<double>(done) / 1024.0 / secs;
    constexpr int kWidth = 30;
    std::string line;
    if (total && *total > 0) {
        const double frac = static_cast<double>(done) / static_cast<double>(*total);
        const int fill = static_cast<int>(frac * kWidth);
        line = fmt::format("\r[{:<{}}] {:3.0f}% {}/{} bytes {:.1f} KiB/s",
                           std::string(static_cast<std::size_t>(fill), '#'), kWidth, frac * 100.0,
                           done, *total, kib_s);
    } else {
        line = fmt::format("\r{} bytes {:.1f} KiB/s", done, kib_s);
    }
    fmt::print(stderr, "{}", line);
    std::fflush(stderr);
    drawn_ = true;
}

void SdoProgressBar::finish() {
    if (drawn_) {
        fmt::print(stderr, "\r\033[K");
        std::fflush(stderr);
        drawn_ = false;
    }
}

} // namespace codrive::cli
