// SPDX-License-Identifier: Apache-2.0
// Names of error-control events.
#include <codrive/nmt/error_control_event.hpp>

namespace codrive::nmt {

std::string_view to_string(ErrorControlEventKind k) {
    switch (k) {
    case ErrorControlEventKind::BootUp:
        return "boot-up";
    case ErrorControlEventKind::UnexpectedBootUp:
        return "unexpected boot-up";
    case ErrorControlEventKind::StateChanged:
        return "state changed";
    case ErrorControlEventKind::HeartbeatLost:
        return "heartbeat lost";
    case ErrorControlEventKind::HeartbeatRecovered:
        return "heartbeat recovered";
    case ErrorControlEventKind::GuardTimeout:
        return "guard timeout";
    case ErrorControlEventKind::GuardToggleError:
        return "guard toggle error";
    case ErrorControlEventKind::GuardRecovered:
        return "guard recovered";
    case ErrorControlEventKind::LifeGuardLost:
        return "life guard lost";
    case ErrorControlEventKind::LifeGuardRecovered:
        return "life guard recovered";
    }
    return "unknown";
}

} // namespace codrive::nmt
