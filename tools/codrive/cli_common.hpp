// SPDX-License-Identifier: Apache-2.0
// Helpers shared by `codrive` subcommands: open a bus with a readable error, parse ids.
#pragma once

#include <codrive/core/event_loop.hpp>
#include <codrive/core/socket_can_bus.hpp>
#include <codrive/master/master.hpp>

#include <memory>
#include <optional>
#include <string>

namespace codrive::cli {

/// An opened CAN interface attached to its own event loop.
struct BusSession {
    std::unique_ptr<EventLoop> loop;
    std::unique_ptr<SocketCanBus> bus;
};

/// Opens `ifname` and attaches it to a new loop. On failure prints one sentence to stderr
/// (describe_can_open_error()) and
/// returns nullopt.
std::optional<BusSession> open_bus(const std::string& ifname, SocketCanOptions options = {});

/// An opened CAN interface with a master (default configuration) ticking on its loop: the
/// preamble of the commands that talk to nodes (SDO, NMT, scan, drives).
struct MasterSession : BusSession {
    std::unique_ptr<master::Master> master;
};

/// open_bus() plus the master; nullopt (the sentence printed) when the bus cannot be opened.
std::optional<MasterSession> open_master(const std::string& ifname);

/// Parses a node id "1".."127" (decimal or 0x hex); prints an error and returns nullopt.
std::optional<unsigned> parse_node(const std::string& text, bool allow_all = false);

/// True if stderr is a terminal (progress bars, colours).
bool stderr_is_tty();

/// Catches SIGINT and SIGTERM for a command that ends its work safely on them (an axis stopped,
/// an SDO transfer aborted): the handler only records the first signal, the command's waits
/// poll stop_signal() and end.
void catch_stop_signals();
/// The first SIGINT/SIGTERM caught since catch_stop_signals() (0: none).
int stop_signal();
/// stop_signal() != 0.
bool stop_requested();
/// "SIGINT" or "SIGTERM".
const char* signal_name(int sig);

} // namespace codrive::cli
