// SPDX-License-Identifier: Apache-2.0
// NMT module-control commands (CiA 301 §7.2.8.3.1): frame builders and parsers.
#pragma once

#include <codrive/core/cob_id.hpp>
#include <codrive/core/error.hpp>
#include <codrive/core/frame.hpp>

#include <cstdint>
#include <optional>
#include <string_view>

namespace codrive::nmt {

/// Command specifiers of the NMT module-control service (COB-ID 000h, 2 bytes: cs, node).
enum class NmtCommand : std::uint8_t {
    Start = 0x01,
    Stop = 0x02,
    EnterPreOperational = 0x80,
    ResetNode = 0x81,
    ResetCommunication = 0x82,
};

/// Node id 0 addresses every node in NMT commands.
inline constexpr NodeId kAllNodes = 0;

/// "start", "stop", "pre-operational", "reset node", "reset communication".
[[nodiscard]] std::string_view to_string(NmtCommand c);

/// Parses the CLI spelling: "start", "stop", "preop", "reset", "reset-comm" (also the long
/// names of to_string with '-' for ' '). nullopt if unknown.
[[nodiscard]] std::optional<NmtCommand> command_from_name(std::string_view name);

/// The NMT frame for `command` to `node` (0 = all nodes).
/// Errors: InvalidArgument if node is neither 0 nor 1..127.
[[nodiscard]] Result<Frame> make_command_frame(NmtCommand command, NodeId node);

/// A decoded NMT command frame.
struct CommandFrame {
    NmtCommand command = NmtCommand::Start;
    NodeId node = kAllNodes;
};

/// Decodes an NMT command frame. Errors: InvalidFrame if the id is not 000h, the frame is an
/// RTR, shorter than 2 bytes, or has an undefined command specifier or node id.
[[nodiscard]] Result<CommandFrame> parse_command_frame(const Frame& frame);

/// The state a node enters after `command` (reset commands lead to a boot-up).
[[nodiscard]] std::string_view expected_state_name(NmtCommand command);

} // namespace codrive::nmt
