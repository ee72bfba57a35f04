// SPDX-License-Identifier: Apache-2.0
// Texts of the standard EMCY error codes (CiA 301 Table 21, CiA 402 / IEC 61800-7-201 Annex).
#pragma once

#include <cstdint>
#include <string>
#include <string_view>

namespace codrive::emcy {

/// A lookup result: the text of the code itself, or of the nearest code class above it.
struct ErrorCodeInfo {
    std::string_view text;     ///< "continuous over-current"; "" if nothing matched
    std::uint16_t matched = 0; ///< the table code that matched (== code when exact)
    bool exact = false;
};

/// Finds `code` in the CiA 301/402 table; if absent, the nearest class (xxx0h, xx00h, x000h).
[[nodiscard]] ErrorCodeInfo lookup_error_code(std::uint16_t code);

/// The text for messages: "continuous over-current", "continuous over-current (class 0x2310)"
/// for a code only its class knows, "unknown error code" otherwise.
[[nodiscard]] std::string error_code_text(std::uint16_t code);

} // namespace codrive::emcy
