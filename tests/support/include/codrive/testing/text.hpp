// SPDX-License-Identifier: Apache-2.0
// Small text helpers the tests share: does an output hold a phrase, a list joined into lines.
#pragma once

#include <string>
#include <string_view>
#include <vector>

namespace codrive::testing {

/// Whether `text` (a tool's output, an error sentence) contains `part`.
inline bool has(std::string_view text, std::string_view part) {
    return text.find(part) != std::string_view::npos;
}

/// Every entry followed by a newline: a list of errors or lines as one text to search or print.
inline std::string joined(const std::vector<std::string>& lines) {
    std::string out;
    for (const auto& line : lines) {
        out += line;
        out += '\n';
    }
    return out;
}

} // namespace codrive::testing
