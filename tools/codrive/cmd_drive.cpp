// SPDX-License-Identifier: Apache-2.0
// `codrive drive`: one CiA 402 axis over SDO (no bus file needed): status, enable, disable,
// fault reset, homing, profile position / velocity moves and jog.
#include "cli_common.hpp"
#include "command_registry.hpp"

#include <codrive/drives/axis.hpp>
#include <codrive/drives/canopen_transport.hpp>
#include <codrive/drives/profile.hpp>
#include <codrive/master/master.hpp>

#include <fmt/format.h>

namespace codrive::cli {
namespace {

struct DriveArgs {
    std::string iface;
    unsigned node = 0;
    unsigned axis = 1;
    std::string action;
    int method = 35;
    std::optional<std::int32_t> pp;
    std::optional<std::int32_t> pv;
    std::int32_t jog_velocity = 10000;
    double jog_s = 1.0;
    int timeout_ms = 10000;
};

int run_drive(const DriveArgs& a) {
    if (!valid_node_id(a.node)) {
        fmt::print(stderr, "codrive: node id must be 1..127\n");
        return kExitUsage;
    }
    auto s = open_bus(a.iface);
    if (!s) {
        return kExitNoBus;
    }
    master::Master m(*s->bus, RealClock::instance());
    s->loop->add_timed(&m);
    const auto node = static_cast<NodeId>(a.node);
    auto& sdo = m.sdo().client(node);

    // Identify the drive so messages and quirks come from its profile.
    std::optional<std::uint32_t> device_type;
    std::optional<std::uint32_t> vendor;
    std::optional<std::uint32_t> product;
    std::string error;
    std::string device_name;
    int pending = 4;
    sdo.read<std::string>(0x1008, 0, [&](sdo::SdoResult<std::string> r) {
        --pending;
        if (r) {
            device_name = *r;
        }
    });
    sdo.read<std::uint32_t>(0x1000, 0, [&](sdo::SdoResult<std::uint32_t> r) {
        --pending;
        if (r) {
            device_type = *r;
        } else {
            error = r.error().to_string();
        }
    });
    sdo.read<std::uint32_t>(0x1018, 1, [&](sdo::SdoResult<std::uint32_t> r) {
        --pending;
        if (r) {
            vendor = *r;
        }
    });
    sdo.read<std::uint32_t>(0x1018, 2, [&](sdo::SdoResult<std::uint32_t> r) {
        --pending;
        if (r) {
            product = *r;
        }
    });
    s->loop->run_until([&] { return pending == 0; }, seconds(5));
    if (!device_type) {
        fmt::print(stderr, "codrive: {}\n", error.empty() ? "no answer" : error);
        return kExitFailure;
    }
    const drives::Profile* profile =
        drives::match_identity(*device_type, vendor.value_or(0), product.value_or(0), device_name);
    if (profile == nullptr) {
        profile = &drives::generic_profile();
    }
    m.emcy().set_text_provider(node, drives::emcy_text_provider(*profile));
    drives::CanopenTransport transport(sdo);
    drives::AxisConfig ac;
    ac.axis = a.axis;
    ac.profile = profile;
    ac.timeout = milliseconds(a.timeout_ms);
    drives::Axis axis(transport, ac);
    s->loop->add_timed(&axis);
    m.set_event_handler([](const master::MasterEvent& e) {
        if (e.kind == master::MasterEventKind::Emcy) {
            fmt::print("{}\n", e.text);
        }
    });

    auto wait = [&](const std::function<void(drives::Axis::Done)>& op) -> bool {
        bool done = false;
        std::string err;
        op([&](drives::DriveVoid r) {
            done = true;
            err = r ? "" : r.error().message;
        });
        s->loop->run_until([&] { return done; }, milliseconds(a.timeout_ms + 2000));
        if (!done) {
            err = "the operation did not finish";
        }
        if (!err.empty()) {
            fmt::print(stderr, "codrive: {}\n", err);
        }
        return err.empty();
    };

    if (!s->loop->run_until([&] { return axis.has_statusword(); }, seconds(3))) {
        fmt::print(stderr, "codrive: node {} axis {}: no statusword (0x{:04X}) over SDO\n", a.node,
                   a.axis, axis.index(0x6041));
        return kExitFailure;
    }
    bool ok = true;
    const bool motion = a.action == "home" || a.action == "move" || a.action == "jog";
    if (motion) {
        // Each invocation is a new master: enable() makes the axis command what the drive
        // does (or brings it there), so no stale controlword 0 disables it.
        ok = wait([&](auto done) { axis.enable(std::move(done)); });
        if (!ok) {
            return kExitFailure;
        }
    }
    if (a.action == "enable") {
        ok = wait([&](auto done) { axis.enable(std::move(done)); });
    } else if (a.action == "disable") {
        ok = wait([&](auto done) { axis.disable(std::move(done)); });
    } else if (a.action == "reset") {
        ok = wait([&](auto done) { axis.fault_reset(std::move(done)); });
    } else if (a.action == "home") {
        drives::HomingParams hp;
        hp.method = static_cast<std::int8_t>(a.method);
        ok = wait([&](auto done) {
                 axis.set_mode(drives::cia402::Mode::Homing, std::move(done));
             }) &&
             wait([&](auto done) { axis.home(hp, std::move(done)); });
    } else if (a.action == "move" && a.pp) {
        ok = wait([&](auto done) {
                 axis.set_mode(drives::cia402::Mode::ProfilePosition, std::move(done));
             }) &&
             wait([&](auto done) { axis.move_to(*a.pp, {}, std::move(done)); });
    } else if (a.action == "move" && a.pv) {
        ok = wait([&](auto done) {
                 axis.set_mode(drives::cia402::Mode::ProfileVelocity, std::move(done));
             }) &&
             wait([&](auto done) { axis.run_velocity(*a.pv, std::move(done)); });
    } else if (a.action == "jog") {
        ok = wait([&](auto done) {
                 axis.set_mode(drives::cia402::Mode::ProfileVelocity, std::move(done));
             }) &&
             wait([&](auto done) { axis.run_velocity(a.jog_velocity, std::move(done)); });
        s->loop->run_until(s->loop->now() + std::chrono::duration_cast<Duration>(
                                                std::chrono::duration<double>(a.jog_s)));
        ok = ok && wait([&](auto done) { axis.run_velocity(0, std::move(done)); });
    } else if (a.action == "move") {
        fmt::print(stderr, "codrive: move needs --pp TARGET or --pv VELOCITY\n");
        return kExitUsage;
    }
    s->loop->run_until(s->loop->now() + milliseconds(50));
    // Without PDOs the position comes from one SDO read.
    std::optional<std::int32_t> position = axis.position_actual();
    if (!position) {
        bool read_done = false;
        sdo.read<std::int32_t>(axis.index(0x6064), 0, [&](sdo::SdoResult<std::int32_t> r) {
            read_done = true;
            if (r) {
                position = *r;
            }
        });
        s->loop->run_until([&] { return read_done; }, seconds(2));
    }
    fmt::print("node {} axis {} ({}): {}, statusword 0x{:04X}, mode {}, position {}{}\n", a.node,
               a.axis, profile->title, drives::cia402::to_string(axis.state()), axis.statusword(),
               axis.mode_display() ? drives::cia402::mode_name(*axis.mode_display()) : "-",
               position ? std::to_string(*position) : "-",
               axis.state() == drives::cia402::State::OperationEnabled
                   ? std::string()
                   : std::string(" — ") + axis.diagnose());
    s->loop->remove_timed(&axis);
    s->loop->remove_timed(&m);
    return ok ? kExitOk : kExitFailure;
}

void install_drive(CLI::App& app, int& exit_code) {
    auto a = std::make_shared<DriveArgs>();
    auto* cmd = app.add_subcommand("drive", "Operate one CiA 402 axis over SDO");
    cmd->add_option("-i,--iface", a->iface, "CAN interface")->required();
    cmd->add_option("-n,--node", a->node, "Node id")->required();
    cmd->add_option("--axis", a->axis, "Axis of a multi-axis drive (AKD2G: 1 or 2)")
        ->capture_default_str();
    cmd->add_option("action", a->action, "status|enable|disable|reset|home|move|jog")
        ->required()
        ->check(CLI::IsMember({"status", "enable", "disable", "reset", "home", "move", "jog"}));
    cmd->add_option("--method", a->method, "Homing method (6098h)")->capture_default_str();
    cmd->add_option("--pp", a->pp, "move: profile position target");
    cmd->add_option("--pv", a->pv, "move: profile velocity");
    cmd->add_option("--velocity", a->jog_velocity, "jog: velocity")->capture_default_str();
    cmd->add_option("--seconds", a->jog_s, "jog: duration")->capture_default_str();
    cmd->add_option("--timeout", a->timeout_ms, "Operation timeout in ms")->capture_default_str();
    cmd->callback([a, &exit_code] { exit_code = run_drive(*a); });
}

} // namespace
} // namespace codrive::cli

using codrive::cli::install_drive;
CODRIVE_REGISTER_COMMAND(install_drive);
