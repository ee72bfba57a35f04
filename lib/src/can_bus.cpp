// SPDX-License-Identifier: Apache-2.0
// Text for bus states and bus events.
#include <codrive/core/can_bus.hpp>

#include <fmt/format.h>

namespace codrive {

std::string_view to_string(BusState s) {
    switch (s) {
    case BusState::ErrorActive:
        return "error-active";
    case BusState::ErrorWarning:
        return "error-warning";
    case BusState::ErrorPassive:
        return "error-passive";
    case BusState::BusOff:
        return "bus-off";
    }
    return "?";
}

std::string to_string(const BusEvent& e) {
    const std::string counters =
        (e.tx_errors != 0 || e.rx_errors != 0)
            ? fmt::format(" (tx errors {}, rx errors {})", e.tx_errors, e.rx_errors)
            : std::string();
    const std::string detail = e.detail.empty() ? std::string() : ": " + e.detail;
    switch (e.kind) {
    case BusEvent::Kind::StateChanged:
        return fmt::format("bus state {}{}", to_string(e.state), counters);
    case BusEvent::Kind::Restarted:
        return "controller restarted after bus-off";
    case BusEvent::Kind::ControllerProblem:
        return fmt::format("controller problem{}{}", detail, counters);
    case BusEvent::Kind::ProtocolError:
        return fmt::format("protocol error{}{}", detail, counters);
    case BusEvent::Kind::NoAck:
        return "transmission not acknowledged (no other node on the bus?)";
    case BusEvent::Kind::LostArbitration:
        return fmt::format("lost arbitration{}", detail);
    case BusEvent::Kind::TransceiverError:
        return fmt::format("transceiver error{}", detail);
    case BusEvent::Kind::RxOverflow:
        return fmt::format("{} received frames dropped by the kernel (socket receive queue full)",
                           e.count);
    }
    return "bus event";
}

} // namespace codrive
