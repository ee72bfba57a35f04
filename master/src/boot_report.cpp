// SPDX-License-Identifier: Apache-2.0
// Text of boot reports.
#include <codrive/master/boot_report.hpp>

#include <fmt/format.h>

namespace codrive::master {

std::string BootReport::error() const {
    for (const auto& s : steps) {
        if (!s.ok) {
            return s.detail;
        }
    }
    return ok ? std::string() : fmt::format("node {}: boot-up did not finish", node);
}

std::string BootReport::to_string() const {
    std::string out = fmt::format(
        "node {}{}: {}{} in {:.1f} ms\n", node, name.empty() ? std::string() : " (" + name + ")",
        recovery ? "recovery boot-up " : "boot-up ", ok ? "OK" : "FAILED", to_ms(duration));
    for (const auto& s : steps) {
        out += fmt::format("  {:<4} {:>7.1f} ms  {:<34} {}\n", s.ok ? "ok" : "FAIL",
                           to_ms(s.duration), s.name, s.detail);
    }
    return out;
}

} // namespace codrive::master
