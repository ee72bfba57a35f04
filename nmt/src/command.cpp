// SPDX-License-Identifier: Apache-2.0
// NMT module-control command frames (CiA 301 §7.2.8.3.1).
#include <codrive/nmt/command.hpp>

#include <array>

namespace codrive::nmt {

namespace {
bool known_command(std::uint8_t cs) {
    return cs == 0x01 || cs == 0x02 || cs == 0x80 || cs == 0x81 || cs == 0x82;
}
} // namespace

std::string_view to_string(NmtCommand c) {
    switch (c) {
    case NmtCommand::Start:
        return "start";
    case NmtCommand::Stop:
        return "stop";
    case NmtCommand::EnterPreOperational:
        return "pre-operational";
    case NmtCommand::ResetNode:
        return "reset node";
    case NmtCommand::ResetCommunication:
        return "reset communication";
    }
    return "unknown";
}

std::optional<NmtCommand> command_from_name(std::string_view name) {
    struct Alias {
        std::string_view name;
        NmtCommand command;
    };
    static constexpr std::array<Alias, 10> kAliases{{
        {"start", NmtCommand::Start},
        {"stop", NmtCommand::Stop},
        {"preop", NmtCommand::EnterPreOperational},
        {"pre-operational", NmtCommand::EnterPreOperational},
        {"reset", NmtCommand::ResetNode},
        {"reset-node", NmtCommand::ResetNode},
        {"reset-comm", NmtCommand::ResetCommunication},
        {"reset-communication", NmtCommand::ResetCommunication},
        {"operational", NmtCommand::Start},
        {"stopped", NmtCommand::Stop},
    }};
    for (const auto& a : kAliases) {
        if (a.name == name) {
            return a.command;
        }
    }
    return std::nullopt;
}

Result<Frame> make_command_frame(NmtCommand command, NodeId node) {
    if (node != kAllNodes && !valid_node_id(node)) {
        return fail(CoreErrc::InvalidArgument);
    }
    return Frame::make(cob::kNmt, {static_cast<std::uint8_t>(command), node});
}

Result<CommandFrame> parse_command_frame(const Frame& frame) {
    if (frame.id != cob::kNmt || frame.extended() || frame.rtr() || frame.len < 2) {
        return fail(CoreErrc::InvalidFrame);
    }
    const std::uint8_t cs = frame.data[0];
    const std::uint8_t node = frame.data[1];
    if (!known_command(cs) || node > kMaxNodeId) {
        return fail(CoreErrc::InvalidFrame);
    }
    return CommandFrame{static_cast<NmtCommand>(cs), node};
}

std::string_view expected_state_name(NmtCommand command) {
    switch (command) {
    case NmtCommand::Start:
        return "operational";
    case NmtCommand::Stop:
        return "stopped";
    case NmtCommand::EnterPreOperational:
        return "pre-operational";
    case NmtCommand::ResetNode:
    case NmtCommand::ResetCommunication:
        return "boot-up";
    }
    return "unknown";
}

} // namespace codrive::nmt
