// SPDX-License-Identifier: Apache-2.0
// The EtherCAT state machine (ETG.1000.6 §6.4): AL states, transitions and AL status codes.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <string_view>

namespace codrive::ethercat {

/// AL states as written to AL control (0x0120) and read from AL status (0x0130), bits 3..0.
enum class AlState : std::uint8_t {
    None = 0,
    Init = 0x01,
    PreOp = 0x02,
    Boot = 0x03,
    SafeOp = 0x04,
    Op = 0x08,
};

inline constexpr std::uint16_t kAlErrorFlag = 0x10; ///< AL status bit 4 / AL control ack bit

/// "INIT", "PRE-OP", "BOOT", "SAFE-OP", "OP", or "state 0x5" for other values.
[[nodiscard]] std::string to_string(AlState s);
/// The state in the low 4 bits of an AL status/control value, or nullopt if not a state.
[[nodiscard]] std::optional<AlState> al_state_from_bits(std::uint16_t bits);
/// Parses "init", "preop", "pre-op", "safeop", "op", "boot" (case-insensitive).
[[nodiscard]] std::optional<AlState> al_state_from_string(std::string_view text);

/// Whether an ESC accepts a direct transition (ETG.1000.6 Table 9): up one step at a time
/// (INIT→PRE-OP→SAFE-OP→OP, INIT→BOOT), any step down, BOOT→INIT only.
[[nodiscard]] bool transition_allowed(AlState from, AlState to);

/// AL status codes (ETG.1000.6 Table 11); the values are the 16-bit register 0x0134 values.
namespace al_code {
inline constexpr std::uint16_t kNoError = 0x0000;
inline constexpr std::uint16_t kUnspecified = 0x0001;
inline constexpr std::uint16_t kInvalidStateChange = 0x0011;
inline constexpr std::uint16_t kUnknownState = 0x0012;
inline constexpr std::uint16_t kBootstrapNotSupported = 0x0013;
inline constexpr std::uint16_t kInvalidMailboxConfigPreop = 0x0016;
inline constexpr std::uint16_t kInvalidSmConfig = 0x0017;
inline constexpr std::uint16_t kNoValidInputs = 0x0018;
inline constexpr std::uint16_t kNoValidOutputs = 0x0019;
inline constexpr std::uint16_t kSyncError = 0x001A;
inline constexpr std::uint16_t kSmWatchdog = 0x001B;
inline constexpr std::uint16_t kInvalidOutputConfig = 0x001D;
inline constexpr std::uint16_t kInvalidInputConfig = 0x001E;
inline constexpr std::uint16_t kInvalidDcSyncConfig = 0x0030;
} // namespace al_code

/// The ETG.1000.6 text of an AL status code ("invalid output configuration"), or nullopt for
/// vendor codes.
[[nodiscard]] std::optional<std::string_view> al_status_code_text(std::uint16_t code);
/// Text for any code: standard text, "vendor-specific AL status code" (0x8000 and up), or
/// "unknown AL status code".
[[nodiscard]] std::string_view al_status_code_describe(std::uint16_t code);

} // namespace codrive::ethercat
