// SPDX-License-Identifier: Apache-2.0
// A progress bar on stderr for SDO transfers longer than a second (only on a terminal).
#pragma once

#include <codrive/core/time.hpp>

#include <cstddef>
#include <optional>

namespace codrive::cli {

class SdoProgressBar {
public:
    /// Draws nothing unless stderr is a terminal.
    SdoProgressBar();
    ~SdoProgressBar();
    SdoProgressBar(const SdoProgressBar&) = delete;
    SdoProgressBar& operator=(const SdoProgressBar&) = delete;
    void update(std::size_t done, std::optional<std::size_t> total);
    /// Clears the bar line if one was drawn.
    void finish();

private:
    bool enabled_;
    bool drawn_ = false;
    TimePoint start_;
    TimePoint last_draw_{};
};

} // namespace codrive::cli
