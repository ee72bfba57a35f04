// SPDX-License-Identifier: Apache-2.0
// `codrive scan`: finds every node on a CAN bus, or every slave of an EtherCAT segment
// (`--ethercat IFACE`), and prints its identity.
#include "cli_common.hpp"
#include "command_registry.hpp"
#include "ecat_session.hpp"

#include <codrive/master/master.hpp>
#include <codrive/master/network_scan.hpp>

#include <fmt/format.h>

namespace codrive::cli {
namespace {

struct ScanArgs {
    std::string iface;
    std::string ethercat;
    int timeout_ms = 300;
};

/// EtherCAT: the slaves with position (from 1, as `-n` counts them), station address, identity
/// from the SII, name and AL state.
int run_ecat_scan(const ScanArgs& a) {
    const auto t0 = SteadyClock::now();
    auto s = open_segment(a.ethercat, 1);
    if (!s) {
        return kExitNoBus;
    }
    fmt::print("{}", format_slave_table(*s->master, 1));
    fmt::print("scanned {} slave(s) on {} in {:.0f} ms\n", s->master->slaves().size(), a.ethercat,
               to_ms(SteadyClock::now() - t0));
    return kExitOk;
}

int run_scan(const ScanArgs& a) {
    if (a.iface.empty() == a.ethercat.empty()) {
        fmt::print(stderr, "codrive: scan needs -i IFACE (CAN) or --ethercat IFACE\n");
        return kExitUsage;
    }
    if (!a.ethercat.empty()) {
        return run_ecat_scan(a);
    }
    auto s = open_master(a.iface);
    if (!s) {
        return kExitNoBus;
    }
    master::Master& m = *s->master;
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
    auto* cmd = app.add_subcommand(
        "scan", "Find the nodes on a CAN bus (1000h, 1018h, 1008h) or the slaves of an EtherCAT "
                "segment");
    auto* can = cmd->add_option("-i,--iface", args->iface, "CAN interface");
    cmd->add_option("--ethercat", args->ethercat, "EtherCAT: network interface of the segment")
        ->excludes(can);
    cmd->add_option("--timeout", args->timeout_ms, "SDO timeout per request in ms")
        ->capture_default_str();
    cmd->callback([args, &exit_code] { exit_code = run_scan(*args); });
}

} // namespace
} // namespace codrive::cli

using codrive::cli::install_scan;
CODRIVE_REGISTER_COMMAND(install_scan);
