// SPDX-License-Identifier: Apache-2.0
// `codrive scan`: finds every node on a CAN bus and prints its identity.
#include "cli_common.hpp"
#include "command_registry.hpp"

#include <codrive/master/master.hpp>
#include <codrive/master/network_scan.hpp>

#include <fmt/format.h>

namespace codrive::cli {
namespace {

struct ScanArgs {
    std::string iface;
    int timeout_ms = 300;
};

int run_scan(const ScanArgs& a) {
    auto s = open_bus(a.iface);
    if (!s) {
        return kExitNoBus;
    }
    master::Master m(*s->bus, RealClock::instance());
    s->loop->add_timed(&m);
    master::ScanOptions o;
    o.timeout = milliseconds(a.timeout_ms);
    master::NetworkScan scan(m.sdo(), &m.nmt().states(), o);
    std::optional<std::vector<master::ScanRow>> rows;
    const auto t0 = SteadyClock::now();
    scan.start([&](std::vector<master::ScanRow> r) { rows = std::move(r); });
    s->loop->run_until([&] { return rows.has_value(); }, std::chrono::seconds(30));
    s->loop->remove_timed(&m);
    if (!rows) {
        fmt::print(stderr, "codrive: scan of {} did not finish within 30 s\n", a.iface);
        return kExitFailure;
    }
    fmt::print("{}", master::format_scan_table(*rows));
    fmt::print("scanned nodes 1-127 on {} in {:.0f} ms\n", a.iface, to_ms(SteadyClock::now() - t0));
    return kExitOk;
}

void install_scan(CLI::App& app, int& exit_code) {
    auto args = std::make_shared<ScanArgs>();
    auto* cmd = app.add_subcommand("scan", "Find the nodes on a CAN bus (1000h, 1018h, 1008h)");
    cmd->add_option("-i,--iface", args->iface, "CAN interface")->required();
    cmd->add_option("--timeout", args->timeout_ms, "SDO timeout per request in ms")
        ->capture_default_str();
    cmd->callback([args, &exit_code] { exit_code = run_scan(*args); });
}

} // namespace
} // namespace codrive::cli

using codrive::cli::install_scan;
CODRIVE_REGISTER_COMMAND(install_scan);
