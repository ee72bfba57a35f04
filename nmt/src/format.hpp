// SPDX-License-Identifier: Apache-2.0
// Private helpers for the sentences of NMT events.
#pragma once

#include <codrive/core/time.hpp>

#include <cmath>
#include <fmt/format.h>
#include <string>

namespace codrive::nmt::detail {

/// "300" for whole milliseconds, "12.5" otherwise.
inline std::string ms_text(Duration d) {
    const double ms = to_ms(d);
    if (std::abs(ms - std::round(ms)) < 1e-6) {
        return fmt::format("{}", static_cast<long long>(std::llround(ms)));
    }
    return fmt::format("{:.1f}", ms);
}

} // namespace codrive::nmt::detail
