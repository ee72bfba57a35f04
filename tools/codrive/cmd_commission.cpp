// SPDX-License-Identifier: Apache-2.0
// `codrive commission`: gives a drive a new node-ID (and CAN bit rate) the way its manual says —
// write the objects, save, reset node — and waits for the boot-up at the new node-ID.
#include "cli_common.hpp"
#include "command_registry.hpp"

#include <codrive/drives/canopen_transport.hpp>
#include <codrive/drives/commissioning.hpp>
#include <codrive/drives/persistence.hpp>
#include <codrive/master/master.hpp>

#include <fmt/format.h>

#include <memory>
#include <optional>

namespace codrive::cli {
namespace {

struct CommissionArgs {
    std::string iface;
    unsigned node = 0;
    unsigned new_node = 0;
    std::optional<unsigned> bitrate;
    int timeout_ms = 5000;
};

int run_commission(const CommissionArgs& a) {
    if (!valid_node_id(a.node) || !valid_node_id(a.new_node)) {
        fmt::print(stderr, "codrive: node ids must be 1..127\n");
        return kExitUsage;
    }
    auto s = open_master(a.iface);
    if (!s) {
        return kExitNoBus;
    }
    master::Master& m = *s->master;
    // The boot-up message (CiA 301 §7.2.8.3.3: 700h + node-ID, one byte 00h) at the new id.
    bool booted = false;
    const std::uint32_t boot_id = 0x700U + a.new_node;
    s->bus->set_frame_handler([&m, &booted, boot_id](const Frame& f, TimePoint t) {
        if (f.id == boot_id && f.len == 1 && f.data[0] == 0x00) {
            booted = true;
        }
        m.on_frame(f, t);
    });
    const auto wait = [&](const std::function<bool()>& pred) {
        return s->loop->run_until(pred, milliseconds(a.timeout_ms));
    };
    const auto old_id = static_cast<NodeId>(a.node);
    drives::CanopenTransport t(m.sdo().client(old_id));
    auto id = std::make_shared<std::optional<drives::DriveResult<const drives::Profile*>>>();
    drives::identify_profile(t, [id](auto r) { *id = std::move(r); });
    wait([&] { return id->has_value(); });
    if (!id->has_value() || !**id) {
        fmt::print(stderr, "codrive: {}\n",
                   id->has_value() ? (**id).error().message : t.name() + ": no answer");
        return kExitFailure;
    }
    const drives::Profile& p = ****id;
    auto done = std::make_shared<std::optional<drives::DriveVoid>>();
    drives::commission_node(t, p, a.new_node, a.bitrate, [done](auto r) { *done = std::move(r); });
    wait([&] { return done->has_value(); });
    if (!done->has_value() || !**done) {
        const bool usage =
            done->has_value() && (**done).error().code != drives::DriveErrc::Transport;
        fmt::print(stderr, "codrive: {}\n",
                   done->has_value() ? (**done).error().message : t.name() + ": no answer");
        return usage ? kExitUsage : kExitFailure;
    }
    // §6.2.74/§6.2.76: effective after a restart.
    if (auto r = m.nmt().reset_node(old_id); !r) {
        fmt::print(stderr, "codrive: NMT reset node {} failed: {}\n", a.node, r.error().message());
        return kExitFailure;
    }
    if (!wait([&] { return booted; })) {
        fmt::print(stderr,
                   "codrive: node {} saved node-ID {}{} but sent no boot-up at node {} within {} "
                   "ms{}\n",
                   a.node, a.new_node,
                   a.bitrate ? fmt::format(" and {} kbit/s", *a.bitrate) : std::string(),
                   a.new_node, a.timeout_ms,
                   a.bitrate ? fmt::format(": it now talks at {} kbit/s; set {} to that rate "
                                           "and look with `codrive scan -i {}`",
                                           *a.bitrate, a.iface, a.iface)
                             : std::string());
        return kExitFailure;
    }
    // Read back at the new node-ID what the drive now runs with.
    drives::CanopenTransport fresh(m.sdo().client(static_cast<NodeId>(a.new_node)));
    std::optional<std::uint8_t> rate_code;
    bool read = p.commissioning.bit_rate_object == 0;
    if (!read) {
        fresh.read_as<std::uint8_t>(p.commissioning.bit_rate_object, 0,
                                    [&](drives::DriveResult<std::uint8_t> r) {
                                        read = true;
                                        if (r) {
                                            rate_code = *r;
                                        }
                                    });
        wait([&] { return read; });
    }
    unsigned kbit = 0;
    for (const drives::BitRateCode& b : p.commissioning.bit_rates) {
        kbit = rate_code && b.code == *rate_code ? b.kbit : kbit;
    }
    fmt::print("node {} ({}) is now node {}: boot-up seen at node {}{}\n", a.node, p.title,
               a.new_node, a.new_node,
               kbit != 0 ? fmt::format(", CAN bit rate {} kbit/s ({:04X}h = {})", kbit,
                                       p.commissioning.bit_rate_object, *rate_code)
                         : std::string());
    s->loop->remove_timed(&m);
    return kExitOk;
}

void install_commission(CLI::App& app, int& exit_code) {
    auto a = std::make_shared<CommissionArgs>();
    auto* cmd = app.add_subcommand(
        "commission", "Give a drive a new node-ID (and bit rate): write, save, reset node, wait "
                      "for the boot-up at the new node-ID");
    cmd->add_option("-i,--iface", a->iface, "CAN interface")->required();
    cmd->add_option("-n,--node", a->node, "The drive's node-ID now (DS-BVS: 1 as shipped)")
        ->required();
    cmd->add_option("--node-id", a->new_node, "The new node-ID, 1..127")->required();
    cmd->add_option("--bitrate", a->bitrate,
                    "New CAN bit rate in kbit/s (DS-BVS: 20, 50, 125, "
                    "250, 500, 1000)");
    cmd->add_option("--timeout", a->timeout_ms, "Time for each answer and the boot-up in ms")
        ->capture_default_str();
    cmd->footer("Exit status: 0 the drive booted at the new node-ID, 1 refused or no boot-up, "
                "2 bad arguments (also a drive without a node-ID object or an unsupported bit "
                "rate), 3 no interface.");
    cmd->callback([a, &exit_code] { exit_code = run_commission(*a); });
}

} // namespace
} // namespace codrive::cli

using codrive::cli::install_commission;
CODRIVE_REGISTER_COMMAND(install_commission);
