// SPDX-License-Identifier: Apache-2.0
// `codrive save` / `codrive restore`: store parameters in a drive's non-volatile memory (1010h)
// or bring back its factory defaults (1011h), per category where the drive has categories.
#include "cli_common.hpp"
#include "command_registry.hpp"
#include "ecat_session.hpp"

#include <codrive/drives/canopen_transport.hpp>
#include <codrive/drives/persistence.hpp>
#include <codrive/ethercat/coe_transport.hpp>
#include <codrive/master/master.hpp>

#include <fmt/format.h>

#include <functional>
#include <memory>
#include <optional>
#include <thread>

namespace codrive::cli {
namespace {

struct PersistArgs {
    std::string iface;
    std::string ethercat;
    unsigned node = 0;
    std::string what = "all";
    int timeout_ms = 5000;
};

using RunUntil = std::function<bool(const std::function<bool()>&, Duration)>;

/// Identifies the drive, then stores or restores one category; prints one line.
int persist(const PersistArgs& a, bool save, drives::DriveTransport& t, const RunUntil& run) {
    // Any CANopen device stores and restores through 1010h/1011h (CiA 301 §7.5.2.13/14), a
    // drive or not: identify_device() labels it by what its 1000h says.
    std::optional<drives::DriveResult<drives::DeviceIdentity>> id;
    drives::identify_device(
        t, [&id](drives::DriveResult<drives::DeviceIdentity> r) { id = std::move(r); });
    run([&id] { return id.has_value(); }, milliseconds(a.timeout_ms));
    if (!id) {
        fmt::print(stderr, "codrive: {}: no answer to 1000h within {} ms\n", t.name(),
                   a.timeout_ms);
        return kExitFailure;
    }
    if (!*id) {
        fmt::print(stderr, "codrive: {}\n", id->error().message);
        return kExitFailure;
    }
    const drives::Profile& p = *(*id)->profile;
    const std::string label = (*id)->label();
    std::optional<drives::DriveVoid> done;
    auto on_done = [&done](drives::DriveVoid r) { done = std::move(r); };
    if (save) {
        drives::store_parameters(t, p, a.what, on_done);
    } else {
        drives::restore_default_parameters(t, p, a.what, on_done);
    }
    // Saving may take a while on a real drive (FIO §7.12.4.15: up to 20 s).
    run([&done] { return done.has_value(); }, milliseconds(a.timeout_ms));
    if (!done) {
        fmt::print(stderr, "codrive: {}: no answer to {:04X}h within {} ms\n", t.name(),
                   save ? 0x1010 : 0x1011, a.timeout_ms);
        return kExitFailure;
    }
    if (!*done) {
        fmt::print(stderr, "codrive: {}\n", done->error().message);
        return done->error().code == drives::DriveErrc::InvalidArgument ? kExitUsage : kExitFailure;
    }
    const drives::StoreCategory* c = p.store_category(a.what);
    if (save) {
        fmt::print("{} ({}): saved {} ({:04X}h:{:02X}h)\n", t.name(), label, c->title, 0x1010,
                   c->subindex);
    } else {
        fmt::print("{} ({}): factory defaults of {} restored ({:04X}h:{:02X}h); they take effect "
                   "{}\n",
                   t.name(), label, c->title, 0x1011, c->subindex,
                   p.persistence.restore_restarts ? "now: the drive restarts"
                                                  : "at the next reset node or power-on");
    }
    return kExitOk;
}

int run_can(const PersistArgs& a, bool save) {
    if (!valid_node_id(a.node)) {
        fmt::print(stderr, "codrive: node id must be 1..127\n");
        return kExitUsage;
    }
    auto s = open_master(a.iface);
    if (!s) {
        return kExitNoBus;
    }
    master::Master& m = *s->master;
    drives::CanopenTransport t(m.sdo().client(static_cast<NodeId>(a.node)));
    const int rc = persist(a, save, t, [&s](const std::function<bool()>& pred, Duration limit) {
        return s->loop->run_until(pred, limit);
    });
    s->loop->remove_timed(&m);
    return rc;
}

int run_ecat(const PersistArgs& a, bool save) {
    auto s = open_segment(a.ethercat, 1);
    if (!s) {
        return kExitNoBus;
    }
    ethercat::Master& m = *s->master;
    const auto slave = slave_for_coe(m, a.node, 1);
    if (!slave) {
        return kExitFailure;
    }
    ethercat::CoeTransport t(m, *slave);
    return persist(a, save, t, [&](const std::function<bool()>& pred, Duration limit) {
        const TimePoint deadline = RealClock::instance().now() + limit;
        while (!pred() && RealClock::instance().now() < deadline) {
            t.poll();
            m.poll_mailboxes();
            if (t.pending() == 0) {
                std::this_thread::sleep_for(milliseconds(1));
            }
        }
        return pred();
    });
}

void install_one(CLI::App& app, int& exit_code, bool save) {
    auto a = std::make_shared<PersistArgs>();
    auto* cmd = app.add_subcommand(
        save ? "save" : "restore",
        save ? "Store a drive's parameters in its non-volatile memory (1010h \"save\")"
             : "Restore a drive's factory defaults (1011h \"load\"), effective after reset");
    auto* can = cmd->add_option("-i,--iface", a->iface, "CAN interface");
    cmd->add_option("--ethercat", a->ethercat, "EtherCAT: network interface of the segment")
        ->excludes(can);
    cmd->add_option("-n,--node", a->node, "Node id (EtherCAT: slave position from 1)")->required();
    cmd->add_option("--what", a->what,
                    "Category: all, or the drive's own (FIO: comm, app, customer, drive, "
                    "tuning, ethernet)")
        ->capture_default_str();
    cmd->add_option("--timeout", a->timeout_ms, "Time for each answer in ms")
        ->capture_default_str();
    cmd->footer("Exit status: 0 done, 1 refused or no answer, 2 bad arguments (also a category "
                "the drive does not have), 3 no interface.");
    cmd->callback([a, save, &exit_code] {
        if (a->iface.empty() == a->ethercat.empty()) {
            fmt::print(stderr, "codrive: {} needs -i IFACE (CAN) or --ethercat IFACE\n",
                       save ? "save" : "restore");
            exit_code = kExitUsage;
            return;
        }
        exit_code = a->ethercat.empty() ? run_can(*a, save) : run_ecat(*a, save);
    });
}

void install_persist(CLI::App& app, int& exit_code) {
    install_one(app, exit_code, true);
    install_one(app, exit_code, false);
}

} // namespace
} // namespace codrive::cli

using codrive::cli::install_persist;
CODRIVE_REGISTER_COMMAND(install_persist);
