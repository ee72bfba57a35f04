// SPDX-License-Identifier: Apache-2.0
// Live capture from SocketCAN interfaces with candump-style filters.
#pragma once

#include <codrive/core/error.hpp>
#include <codrive/core/socket_can_bus.hpp>
#include <codrive/dump/dumper.hpp>

#include <atomic>
#include <chrono>
#include <cstdint>
#include <functional>
#include <string>
#include <string_view>
#include <vector>

namespace codrive::dump {

/// One interface argument: `vcan0`, `vcan0,0x580:0x780`, `can1,0x181~0x7FF` (candump syntax:
/// id:mask passes matching frames, id~mask passes the others; ids of more than 3 hex digits or
/// above 7FFh are 29-bit filters).
struct LiveSpec {
    std::string iface;
    std::vector<CanFilter> filters;
};

/// Parses an interface argument. Errors: InvalidArgument (the message is in `error`).
[[nodiscard]] Result<LiveSpec> parse_live_spec(std::string_view text, std::string& error);

/// Names of the CAN interfaces of this host (for `any`), from /sys/class/net.
[[nodiscard]] std::vector<std::string> list_can_interfaces();

struct LiveOptions {
    bool top = false;                             ///< redraw the statistics table
    std::chrono::milliseconds refresh{1000};      ///< table refresh period
    std::uint64_t count = 0;                      ///< stop after this many frames (0: never)
    const std::atomic<bool>* stop = nullptr;      ///< set by a signal handler
    std::function<void(std::string_view)> screen; ///< where `--top` draws
    /// Clear the screen before each `--top` table (a terminal); else tables follow each other
    /// separated by a blank line, with no escape codes (a pipe or a file).
    bool clear_screen = true;
    std::function<void()> ready; ///< called once every interface is open
};

/// Captures until `stop` or `count`. Kernel receive timestamps are monotonic; they are turned
/// into wall-clock time with the offset between the clocks sampled at start. Errors: the first
/// interface that cannot be opened (NoSuchInterface, NoSocketCan, ...), named in `error`.
VoidResult run_live(const std::vector<LiveSpec>& specs, Dumper& dumper, const LiveOptions& options,
                    std::string& error);

} // namespace codrive::dump
