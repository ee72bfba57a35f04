// SPDX-License-Identifier: Apache-2.0
// The boot report: every boot-up step of one node with its result and duration.
#pragma once

#include <codrive/core/cob_id.hpp>
#include <codrive/core/time.hpp>

#include <string>
#include <vector>

namespace codrive::master {

struct BootStep {
    std::string name; ///< "device type 1000h", "identity 1018h", "write 0x6060:00", ...
    bool ok = false;
    std::string detail; ///< the value seen, or the sentence explaining the failure
    Duration duration{0};
};

struct BootReport {
    NodeId node = 0;
    std::string name;
    bool ok = false;
    bool recovery = false; ///< re-run after the node rebooted on its own
    TimePoint started{};
    Duration duration{0};
    std::vector<BootStep> steps;

    /// The first failed step's sentence, or "" when ok.
    [[nodiscard]] std::string error() const;
    /// A multi-line report:
    ///   node 3 (drive-x): boot-up OK in 41.3 ms
    ///     ok    2.1 ms  device type 1000h  0x00020192
    ///     FAIL  ...
    [[nodiscard]] std::string to_string() const;
};

} // namespace codrive::master
