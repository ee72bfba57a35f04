// SPDX-License-Identifier: Apache-2.0
// Events of the error-control protocols (heartbeat, node guarding, life guarding).
#pragma once

#include <codrive/core/cob_id.hpp>
#include <codrive/core/time.hpp>
#include <codrive/nmt/state.hpp>

#include <cstdint>
#include <functional>
#include <string>
#include <string_view>

namespace codrive::nmt {

/// What happened. Each event carries a ready-made sentence in `text`.
enum class ErrorControlEventKind : std::uint8_t {
    BootUp,             ///< first boot-up of a node not yet monitored (or one that was expected)
    UnexpectedBootUp,   ///< boot-up from a node that was already running: it was reset
    StateChanged,       ///< reported NMT state differs from the previous one
    HeartbeatLost,      ///< no heartbeat within the consumer time (1016h)
    HeartbeatRecovered, ///< heartbeat received again after a loss
    GuardTimeout,       ///< node guarding: no valid reply within the life time (100Ch × 100Dh)
    GuardToggleError,   ///< node guarding: reply with the wrong toggle bit
    GuardRecovered,     ///< node guarding: valid reply after a timeout
    LifeGuardLost,      ///< slave side: no guard request within the life time
    LifeGuardRecovered, ///< slave side: guard requests arrive again
};

/// "boot-up", "unexpected boot-up", "state changed", "heartbeat lost", ...
[[nodiscard]] std::string_view to_string(ErrorControlEventKind k);

/// One error-control event.
struct ErrorControlEvent {
    NodeId node = 0;
    ErrorControlEventKind kind = ErrorControlEventKind::StateChanged;
    NmtState state = NmtState::Unknown; ///< the node's last reported state
    TimePoint time{};                   ///< when the event was detected
    std::string text; ///< "node 2: heartbeat lost after 300 ms (consumer time 250 ms)"
};

using ErrorControlHandler = std::function<void(const ErrorControlEvent&)>;

} // namespace codrive::nmt
