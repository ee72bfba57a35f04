// SPDX-License-Identifier: Apache-2.0
// Events the master reports to the application, each with a ready sentence.
#pragma once

#include <codrive/core/cob_id.hpp>
#include <codrive/core/time.hpp>

#include <functional>
#include <string>
#include <string_view>

namespace codrive::master {

enum class MasterEventKind : std::uint8_t {
    BootCompleted,
    BootFailed,
    NodeRebooted, ///< unexpected boot-up: the master re-runs its boot-up
    Recovered,    ///< a rebooted node is back in the state it had
    RecoveryFailed,
    HeartbeatLost,
    HeartbeatRecovered,
    GuardingError, ///< node guarding timeout or toggle error
    StateChanged,
    Emcy,
    EmcyReset,
    BusEvent, ///< error-passive, bus-off, rx overflow ...
};
[[nodiscard]] std::string_view to_string(MasterEventKind k);

struct MasterEvent {
    NodeId node = 0; ///< 0 for bus-wide events
    MasterEventKind kind = MasterEventKind::StateChanged;
    TimePoint time{};
    std::string text;
};

using MasterEventHandler = std::function<void(const MasterEvent&)>;

} // namespace codrive::master
