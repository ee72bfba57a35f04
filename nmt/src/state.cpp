// SPDX-License-Identifier: Apache-2.0
// NMT state names and decoding.
#include <codrive/nmt/state.hpp>

namespace codrive::nmt {

std::string_view to_string(NmtState s) {
    switch (s) {
    case NmtState::BootUp:
        return "boot-up";
    case NmtState::Stopped:
        return "stopped";
    case NmtState::Operational:
        return "operational";
    case NmtState::PreOperational:
        return "pre-operational";
    case NmtState::Unknown:
        break;
    }
    return "unknown";
}

std::optional<NmtState> state_from_byte(std::uint8_t b) {
    switch (b & 0x7FU) {
    case 0x00:
        return NmtState::BootUp;
    case 0x04:
        return NmtState::Stopped;
    case 0x05:
        return NmtState::Operational;
    case 0x7F:
        return NmtState::PreOperational;
    default:
        return std::nullopt;
    }
}

} // namespace codrive::nmt
