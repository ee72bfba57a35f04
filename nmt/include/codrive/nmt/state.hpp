// SPDX-License-Identifier: Apache-2.0
// NMT states as carried in boot-up, heartbeat and node-guarding messages (CiA 301 §7.2.8.3).
#pragma once

#include <cstdint>
#include <optional>
#include <string_view>

namespace codrive::nmt {

/// The state byte of an error-control message (bit 7, the guarding toggle bit, removed).
/// CiA 301 §7.2.8.3: 00h boot-up, 04h stopped, 05h operational, 7Fh pre-operational.
enum class NmtState : std::uint8_t {
    BootUp = 0x00, ///< also "Initializing": the boot-up message carries 00h
    Stopped = 0x04,
    Operational = 0x05,
    PreOperational = 0x7F,
    Unknown = 0xFF, ///< nothing heard yet, or an undefined state value
};

/// "boot-up", "stopped", "operational", "pre-operational", "unknown".
[[nodiscard]] std::string_view to_string(NmtState s);

/// Decodes a state byte (toggle bit 7 ignored). nullopt for values CiA 301 does not define.
[[nodiscard]] std::optional<NmtState> state_from_byte(std::uint8_t b);

} // namespace codrive::nmt
