// SPDX-License-Identifier: Apache-2.0
// `codrive nmt`: sends one NMT module-control command (CiA 301 §7.2.8.3.1) and exits.
#include "cli_common.hpp"
#include "command_registry.hpp"

#include <codrive/nmt/master.hpp>

#include <fmt/format.h>

#include <memory>

namespace codrive::cli {
namespace {

struct NmtOptions {
    std::string iface;
    std::string command;
    std::string node;
};

int run_nmt(const NmtOptions& o) {
    const auto command = nmt::command_from_name(o.command);
    if (!command) {
        fmt::print(stderr,
                   "codrive: unknown NMT command '{}' (use start, stop, preop, reset, "
                   "reset-comm)\n",
                   o.command);
        return kExitUsage;
    }
    const auto node = parse_node(o.node, /*allow_all=*/true);
    if (!node) {
        return kExitUsage;
    }
    SocketCanOptions so;
    so.filters = {CanFilter{0x7FF, 0x7FF}}; // send only: receive nothing we would not read
    auto s = open_bus(o.iface, so);
    if (!s) {
        return kExitNoBus;
    }
    nmt::NmtMaster master(*s->bus);
    const auto target = static_cast<NodeId>(*node);
    const std::string who =
        target == nmt::kAllNodes ? std::string("all nodes") : fmt::format("node {}", target);
    if (auto r = master.send(*command, target); !r) {
        fmt::print(stderr, "codrive: NMT {} to {} failed on {}: {}\n", nmt::to_string(*command),
                   who, o.iface, r.error().message());
        return kExitFailure;
    }
    if (!s->bus->drain(std::chrono::seconds(2))) {
        fmt::print(stderr, "codrive: NMT {} to {} could not be transmitted on {} within 2 s\n",
                   nmt::to_string(*command), who, o.iface);
        return kExitFailure;
    }
    fmt::print("NMT {} sent to {} on {}\n", nmt::to_string(*command), who, o.iface);
    return kExitOk;
}

void install_nmt(CLI::App& app, int& exit_code) {
    auto opts = std::make_shared<NmtOptions>();
    auto* cmd = app.add_subcommand(
        "nmt", "Send an NMT command: start, stop, preop, reset, reset-comm to NODE or all");
    cmd->add_option("-i,--iface", opts->iface, "CAN interface")->required();
    cmd->add_option("command", opts->command, "start | stop | preop | reset | reset-comm")
        ->required()
        ->check(CLI::IsMember({"start", "stop", "preop", "reset", "reset-comm"}));
    cmd->add_option("node", opts->node, "Node id 1..127, or 'all'")->required();
    cmd->callback([opts, &exit_code] { exit_code = run_nmt(*opts); });
}

} // namespace
} // namespace codrive::cli

using codrive::cli::install_nmt;
CODRIVE_REGISTER_COMMAND(install_nmt);
