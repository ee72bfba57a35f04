// SPDX-License-Identifier: Apache-2.0
// The one hexadecimal digit decoder of the core's text parsers (frames, values, EDS files).
#pragma once

namespace codrive::detail {

/// Value 0..15 of a hexadecimal digit (either case), or -1 for any other character.
constexpr int hex_digit(char c) noexcept {
    if (c >= '0' && c <= '9') {
        return c - '0';
    }
    if (c >= 'a' && c <= 'f') {
        return c - 'a' + 10;
    }
    if (c >= 'A' && c <= 'F') {
        return c - 'A' + 10;
    }
    return -1;
}

} // namespace codrive::detail
