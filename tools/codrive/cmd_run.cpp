// SPDX-License-Identifier: Apache-2.0
// `codrive run bus.yml`: boot the bus from its file and show a live status table per axis.
#include "cli_common.hpp"
#include "command_registry.hpp"

#include <codrive/controller/controller.hpp>
#include <codrive/drives/profile.hpp>
#include <codrive/drives/safe_stop.hpp>
#include <codrive/master/master.hpp>

#include <csignal>
#include <fmt/format.h>
#include <unistd.h>

namespace codrive::cli {
namespace {

struct RunArgs {
    std::string file;
    double duration_s = 0;
    int refresh_ms = 500;
    bool enable = false;
    bool check = false;
};

// `--check`: every finding of the bus file, no bus opened; exit status 2 if there is any.
int check_only(const std::string& file) {
    const auto findings = controller::check_bus_file(file);
    for (const auto& f : findings) {
        fmt::print(stderr, "{}\n", f);
    }
    if (!findings.empty()) {
        fmt::print(stderr, "{}: {} problem{} found\n", file, findings.size(),
                   findings.size() == 1 ? "" : "s");
        return kExitUsage;
    }
    fmt::print("{}: OK\n", file);
    return kExitOk;
}

std::string status_table(controller::Controller& c) {
    std::string out = fmt::format("{:<28} {:<22} {:<5} {:>12} {:>10} {:>7}  {}\n", "axis", "state",
                                  "mode", "position", "velocity", "torque", "last EMCY");
    for (const auto& ref : c.axes()) {
        const drives::Axis& a = *ref.axis;
        std::string emcy = "-";
        // CAN buses come first; an EtherCAT segment's axes (bus index after them) have no
        // CANopen master and report their emergencies as controller events instead.
        if (ref.bus < c.can_bus_count()) {
            if (auto* n = c.master(ref.bus).node(ref.node); n != nullptr && n->last_emcy()) {
                emcy = n->last_emcy()->text;
            }
        }
        out += fmt::format("{:<28} {:<22} {:<5} {:>12} {:>10} {:>7}  {}\n", ref.name,
                           drives::cia402::to_string(a.state()),
                           a.mode_display() ? std::to_string(*a.mode_display()) : "-",
                           a.position_actual() ? std::to_string(*a.position_actual()) : "-",
                           a.velocity_actual() ? std::to_string(*a.velocity_actual()) : "-",
                           a.torque_actual() ? std::to_string(*a.torque_actual()) : "-", emcy);
    }
    return out;
}

int run_bus(const RunArgs& a) {
    if (a.check) {
        return check_only(a.file);
    }
    controller::ControllerOptions options;
    options.event_summary_interval = seconds(1); // a flood of one event must not bury the table
    auto created = controller::Controller::from_file(a.file, options);
    if (!created) {
        fmt::print(stderr, "{}", created.error().detail);
        // A bus file with findings is the user's input; anything else (no event loop) is not.
        return created.error().code == controller::ControllerErrc::BusFileInvalid ? kExitUsage
                                                                                  : kExitFailure;
    }
    auto& c = **created;
    c.stop_on_signals();
    c.set_event_callback([](const std::string& text) {
        if (text.find('\n') == std::string::npos) {
            fmt::print("{}\n", text);
        }
    });
    if (auto r = c.start(); !r) {
        fmt::print(stderr, "codrive: {}\n", r.error().detail);
        // A signal during the boot-up: the nodes were left pre-operational by start().
        return c.stop_signal() != 0 ? 128 + c.stop_signal() : kExitFailure;
    }
    for (const auto& r : c.boot_reports()) {
        fmt::print("{}", r.to_string());
    }
    if (a.enable) {
        for (const auto& ref : c.axes()) {
            drives::Axis* ax = ref.axis;
            ax->enable([ax](drives::DriveVoid r) {
                fmt::print("{}: {}\n", ax->name(), r ? "enabled" : r.error().message);
            });
        }
    }
    const bool tty = ::isatty(1) != 0;
    const TimePoint end =
        a.duration_s > 0
            ? SteadyClock::now() +
                  std::chrono::duration_cast<Duration>(std::chrono::duration<double>(a.duration_s))
            : kNever;
    while (c.running() && SteadyClock::now() < end) {
        c.run_for(milliseconds(a.refresh_ms));
        if (!c.running()) {
            break;
        }
        fmt::print("{}{}{}\n", tty ? "\033[2J\033[H" : "", status_table(c), c.stats().to_string());
        std::fflush(stdout);
        if (SteadyClock::now() >= end) {
            break;
        }
    }
    if (c.stop_requested()) {
        fmt::print("codrive: {} received: safe shutdown (quick stop, disable, NMT "
                   "pre-operational)\n",
                   signal_name(c.stop_signal()));
        std::fflush(stdout);
    }
    c.shutdown();
    fmt::print("{}{}\n", status_table(c), c.stats().to_string());
    // Exit status 0 also on SIGINT/SIGTERM (the documented way to end a run), but not when an
    // axis did not confirm its safe stop.
    for (const auto& ref : c.axes()) {
        if (drives::needs_safe_stop(ref.axis->state())) {
            return kExitFailure;
        }
    }
    return kExitOk;
}

void install_run(CLI::App& app, int& exit_code) {
    auto a = std::make_shared<RunArgs>();
    auto* cmd = app.add_subcommand(
        "run", "Boot a bus from its file and show live axis status until Ctrl-C or SIGTERM");
    cmd->footer("Ctrl-C (SIGINT) or SIGTERM: safe shutdown (quick stop, disable, NMT "
                "pre-operational, EtherCAT PRE-OP; see docs/safe-stop.md). Exit status: 0 after a "
                "clean stop (also on a signal), 1 boot-up failed or an axis did not confirm its "
                "stop, 2 bad bus file, 130/143 SIGINT/SIGTERM during the boot-up.");
    cmd->add_option("file", a->file, "Bus file (YAML, see docs/bus-file.md)")->required();
    cmd->add_option("--duration", a->duration_s,
                    "Stop after this many seconds (default: until "
                    "Ctrl-C)");
    cmd->add_option("--refresh", a->refresh_ms, "Table refresh period in ms")
        ->capture_default_str();
    cmd->add_flag("--enable", a->enable, "Enable every axis after boot-up");
    cmd->add_flag("--check", a->check,
                  "Only validate the bus file: print every finding as FILE:LINE: and exit "
                  "(status 2 if any); opens no bus");
    cmd->callback([a, &exit_code] { exit_code = run_bus(*a); });
}

} // namespace
} // namespace codrive::cli

using codrive::cli::install_run;
CODRIVE_REGISTER_COMMAND(install_run);
