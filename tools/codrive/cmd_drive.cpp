// SPDX-License-Identifier: Apache-2.0
// `codrive drive`: one CiA 402 axis (no bus file needed): status, enable, disable, fault reset,
// homing, profile position / velocity moves and jog — over CAN SDO (`-i IFACE`) or EtherCAT
// process data in OP (`--ethercat IFACE`, `-n` = slave position from 1).
#include "cli_common.hpp"
#include "command_registry.hpp"
#include "ecat_session.hpp"

#include <codrive/drives/axis.hpp>
#include <codrive/drives/canopen_transport.hpp>
#include <codrive/drives/persistence.hpp>
#include <codrive/drives/profile.hpp>
#include <codrive/drives/safe_stop.hpp>
#include <codrive/ethercat/coe_transport.hpp>
#include <codrive/ethercat/cyclic_shortfall.hpp>
#include <codrive/ethercat/drive_layout.hpp>
#include <codrive/ethercat/esi.hpp>
#include <codrive/master/master.hpp>

#include <fmt/format.h>

#include <algorithm>
#include <atomic>
#include <csignal>
#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <thread>

namespace codrive::cli {
namespace {

/// Time for the safe stop on a signal (quick stop, then disable), as the controller's default
/// shutdown_timeout.
constexpr Duration kStopBudget = seconds(1);

struct DriveArgs {
    std::string iface;
    std::string ethercat;
    unsigned node = 0;
    unsigned axis = 1;
    std::string action;
    int method = 35;
    std::optional<std::int32_t> pp;
    std::optional<std::int32_t> pv;
    std::int32_t jog_velocity = 10000;
    double jog_s = 1.0;
    int timeout_ms = 10000;
    unsigned cycle_us = 1000; ///< EtherCAT cycle
    bool dc = false;          ///< EtherCAT: DC SYNC0 instead of free run (= --sync dc)
    std::string sync;         ///< EtherCAT: free, sm or dc (ETG.1020 §21.1.3)
    std::string esi;          ///< EtherCAT: the vendor's ESI file of the slave
};

/// What the operations need from a wire: the device's DriveTransport, how messages name the
/// device, and the I/O loop (CAN: the event loop; EtherCAT: mailbox polling).
struct DriveWire {
    drives::DriveTransport* transport = nullptr;
    std::string who; ///< "node 3", "slave 2"
    /// Runs the I/O until pred() holds or `timeout` passes; returns pred().
    std::function<bool(const std::function<bool()>&, Duration)> run_until;
    /// Hands the axis to the loop (on_tick), or takes it back with nullptr.
    std::function<void(drives::Axis*)> attach;
    /// What became of the cyclic frames when no statusword came (EtherCAT:
    /// ethercat::cyclic_shortfall()); nothing to add on CAN.
    std::function<std::string()> why_no_inputs = [] { return std::string(); };
    /// Cyclic frames that brought the inputs in so far (EtherCAT); nullopt on CAN, where the
    /// status comes from SDO reads.
    std::function<std::optional<std::uint64_t>()> inputs_in = [] {
        return std::optional<std::uint64_t>();
    };
};

/// Reads 1008h, 1000h and 1018h:1/:2 and picks the profile; nullptr (printed) without 1000h.
const drives::Profile* identify(DriveWire& w) {
    // Shared: the reads may answer after a signal ended the wait.
    auto id = std::make_shared<std::optional<drives::DriveResult<const drives::Profile*>>>();
    drives::identify_profile(*w.transport, [id](auto r) { *id = std::move(r); });
    w.run_until([&] { return id->has_value(); }, seconds(5));
    if (stop_requested()) {
        return nullptr;
    }
    if (!id->has_value()) {
        fmt::print(stderr, "codrive: {}: no answer\n", w.who);
        return nullptr;
    }
    if (!**id) {
        fmt::print(stderr, "codrive: {}\n", (**id).error().message);
        return nullptr;
    }
    return ***id;
}

/// SIGINT/SIGTERM arrived: once the command has commanded the axis (every action but
/// `status`), it leaves it without torque — quick stop if enabled, then disable voltage — and
/// exits 128 + the signal number.
int stop_on_signal(const DriveArgs& a, DriveWire& w, drives::Axis& axis) {
    const int sig = stop_signal();
    fmt::print(stderr, "codrive: {} received\n", signal_name(sig));
    if (a.action != "status" && axis.has_statusword()) {
        bool over = false;
        std::string err;
        if (drives::safe_stop(axis, RealClock::instance().now() + kStopBudget,
                              RealClock::instance(), [&](drives::DriveVoid r) {
                                  over = true;
                                  err = r ? "" : r.error().message;
                              })) {
            w.run_until([&] { return over; }, kStopBudget + milliseconds(100));
            if (!over || !err.empty()) {
                fmt::print(stderr, "codrive: safe stop failed: {}\n",
                           over ? err : "the drive did not confirm it in time");
                axis.cancel();
            }
        }
        fmt::print(stderr, "codrive: {} axis {}: {}, statusword 0x{:04X}\n", w.who, a.axis,
                   drives::cia402::to_string(axis.state()), axis.statusword());
    }
    return 128 + sig;
}

/// What to type next for a drive at rest or in FAULT ("" when there is nothing to suggest).
std::string next_step(const DriveArgs& a, const drives::Axis& axis) {
    using drives::cia402::State;
    const std::string command =
        fmt::format("codrive drive {} -n {}{}",
                    a.ethercat.empty() ? "-i " + a.iface : "--ethercat " + a.ethercat, a.node,
                    a.axis != 1 ? fmt::format(" --axis {}", a.axis) : std::string());
    switch (axis.state()) {
    case State::SwitchOnDisabled:
    case State::ReadyToSwitchOn:
    case State::SwitchedOn:
        // Only when nothing stands in the way (STO, no remote control, no voltage are named by
        // diagnose() instead of the resting state).
        return axis.diagnose().find("power stage") != std::string::npos
                   ? fmt::format("; `{} enable` enables it", command)
                   : std::string();
    case State::Fault:
        return fmt::format("; remove the cause, then `{} reset` clears the fault", command);
    default:
        return {};
    }
}

/// The action on one axis, then one status line. Transport-neutral: the same on both wires.
int operate(const DriveArgs& a, DriveWire& w, drives::Axis& axis, const drives::Profile& profile) {
    auto wait = [&](const std::function<void(drives::Axis::Done)>& op) -> bool {
        // Shared with the callback: a signal ends the wait before the operation, which the safe
        // stop then cancels (its callback runs after this returns).
        struct Outcome {
            bool done = false;
            std::string err;
        };
        auto out = std::make_shared<Outcome>();
        op([out](drives::DriveVoid r) {
            out->done = true;
            out->err = r ? "" : r.error().message;
        });
        w.run_until([&] { return out->done || stop_requested(); },
                    milliseconds(a.timeout_ms + 2000));
        if (stop_requested()) {
            return false; // the caller stops the axis
        }
        if (!out->done) {
            out->err = "the operation did not finish";
        }
        if (!out->err.empty()) {
            fmt::print(stderr, "codrive: {}{}\n", out->err, w.why_no_inputs());
        }
        return out->err.empty();
    };

    if (!w.run_until([&] { return axis.has_statusword() || stop_requested(); }, seconds(3)) ||
        stop_requested()) {
        if (stop_requested()) {
            return stop_on_signal(a, w, axis);
        }
        fmt::print(stderr, "codrive: {} axis {}: no statusword (0x{:04X}) {}{}\n", w.who, a.axis,
                   axis.index(0x6041),
                   a.ethercat.empty() ? "over SDO" : "in the process data or over CoE",
                   w.why_no_inputs());
        return kExitFailure;
    }
    bool ok = true;
    const bool motion = a.action == "home" || a.action == "move" || a.action == "jog";
    if (motion) {
        // Each invocation is a new master: enable() makes the axis command what the drive
        // does (or brings it there), so no stale controlword 0 disables it.
        ok = wait([&](auto done) { axis.enable(std::move(done)); });
        if (stop_requested()) {
            return stop_on_signal(a, w, axis);
        }
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
        w.run_until([] { return stop_requested(); },
                    std::chrono::duration_cast<Duration>(std::chrono::duration<double>(a.jog_s)));
        ok = ok && !stop_requested() &&
             wait([&](auto done) { axis.run_velocity(0, std::move(done)); });
    } else if (a.action == "move") {
        fmt::print(stderr, "codrive: move needs --pp TARGET or --pv VELOCITY\n");
        return kExitUsage;
    }
    if (stop_requested()) {
        return stop_on_signal(a, w, axis);
    }
    // The status line shows inputs that came in during this wait, or says they are old. Two
    // cycles at least, so that a long EtherCAT cycle gets its frames in.
    const auto inputs_before = w.inputs_in();
    w.run_until([] { return false; },
                std::max<Duration>(milliseconds(50), 2 * microseconds(a.cycle_us)));
    const bool stale = inputs_before && w.inputs_in() == inputs_before;
    // Without process data the position comes from one SDO read.
    std::optional<std::int32_t> position = axis.position_actual();
    if (!position) {
        bool read_done = false;
        w.transport->read_as<std::int32_t>(axis.index(0x6064), 0,
                                           [&](drives::DriveResult<std::int32_t> r) {
                                               read_done = true;
                                               if (r) {
                                                   position = *r;
                                               }
                                           });
        w.run_until([&] { return read_done; }, seconds(2));
    }
    fmt::print("{} axis {} ({}): {}, statusword 0x{:04X}, mode {}, position {}{}{}\n", w.who,
               a.axis, profile.title, drives::cia402::to_string(axis.state()), axis.statusword(),
               axis.mode_display() ? drives::cia402::mode_name(*axis.mode_display()) : "-",
               position ? std::to_string(*position) : "-",
               axis.state() == drives::cia402::State::OperationEnabled
                   ? std::string()
                   : std::string(" — ") + axis.diagnose(),
               next_step(a, axis));
    if (stale) {
        // The line above shows the last inputs that came in (perhaps those of the transition to
        // OP): a status made of them is not the drive's status now. A failed operation has
        // already said what became of the frames.
        fmt::print(stderr,
                   "codrive: {} axis {}: the values above are not current: no cyclic frame "
                   "brought the inputs in while the status was taken{}\n",
                   w.who, a.axis, ok ? w.why_no_inputs() : std::string());
        ok = ok && a.action != "status";
    }
    return ok ? kExitOk : kExitFailure;
}

drives::AxisConfig axis_config(const DriveArgs& a, const drives::Profile& profile) {
    drives::AxisConfig ac;
    ac.axis = a.axis;
    ac.profile = &profile;
    ac.timeout = milliseconds(a.timeout_ms);
    return ac;
}

int run_drive_can(const DriveArgs& a) {
    if (!valid_node_id(a.node)) {
        fmt::print(stderr, "codrive: node id must be 1..127\n");
        return kExitUsage;
    }
    auto s = open_master(a.iface);
    if (!s) {
        return kExitNoBus;
    }
    master::Master& m = *s->master;
    const auto node = static_cast<NodeId>(a.node);
    drives::CanopenTransport transport(m.sdo().client(node));
    DriveWire w;
    w.transport = &transport;
    w.who = fmt::format("node {}", a.node);
    w.run_until = [&s](const std::function<bool()>& pred, Duration timeout) {
        return s->loop->run_until(pred, timeout);
    };
    drives::Axis* attached = nullptr;
    w.attach = [&s, &attached](drives::Axis* axis) {
        if (attached != nullptr) {
            s->loop->remove_timed(attached);
        }
        attached = axis;
        if (axis != nullptr) {
            s->loop->add_timed(axis);
        }
    };
    const drives::Profile* profile = identify(w);
    if (profile == nullptr) {
        return stop_requested() ? 128 + stop_signal() : kExitFailure;
    }
    m.emcy().set_text_provider(node, drives::emcy_text_provider(*profile));
    drives::Axis axis(transport, axis_config(a, *profile));
    w.attach(&axis);
    m.set_event_handler([](const master::MasterEvent& e) {
        if (e.kind == master::MasterEventKind::Emcy) {
            fmt::print("{}\n", e.text);
        }
    });
    const int rc = operate(a, w, axis, *profile);
    w.attach(nullptr);
    s->loop->remove_timed(&m);
    return rc;
}

/// The operating mode whose PDO layout the action needs (its set-points and actuals).
drives::cia402::Mode layout_mode(const DriveArgs& a) {
    using drives::cia402::Mode;
    if (a.action == "home") {
        return Mode::Homing;
    }
    if (a.action == "jog" || (a.action == "move" && a.pv)) {
        return Mode::ProfileVelocity;
    }
    return Mode::ProfilePosition;
}

/// The slave as the command found it, put back on exit: its AL state and, if the command wrote
/// another PDO assignment, the one it had.
struct EcatRestore {
    ethercat::Master& m;
    std::size_t slave;
    std::optional<std::pair<std::vector<ethercat::PdoMapping>, std::vector<ethercat::PdoMapping>>>
        assignment; ///< set when the command changed it
    ~EcatRestore() {
        if (!m.set_state_all(ethercat::AlState::PreOp)) {
            fmt::print(stderr, "codrive: leaving OP: {}\n", m.last_error());
            return;
        }
        if (assignment && !m.configure_pdos(slave, assignment->first, assignment->second)) {
            fmt::print(stderr, "codrive: restoring the PDO assignment: {}\n", m.last_error());
        }
        for (std::size_t i = 0; i < m.slaves().size(); ++i) {
            ethercat::AlState found = m.slaves()[i].found_state;
            if (found == ethercat::AlState::Op) {
                // Without a master cycling, OP would fall to SAFE-OP on the SM watchdog.
                fmt::print(stderr,
                           "codrive: {} was found in OP; left in SAFE-OP (no master "
                           "cycles it now)\n",
                           m.slave_label(i));
                found = ethercat::AlState::SafeOp;
            }
            if (found == ethercat::AlState::None || found == ethercat::AlState::Boot) {
                found = ethercat::AlState::Init;
            }
            if (found != ethercat::AlState::PreOp && !m.request_state(i, found)) {
                fmt::print(stderr, "codrive: {}\n", m.last_error());
            }
        }
    }
};

/// EtherCAT: the slave at position -n (from 1) identified over CoE in PRE-OP, then brought to
/// OP with a PDO layout holding controlword and statusword (the profile's, the slave's own, or
/// the generic CiA 402 one), the sync objects written; the axis runs from the process data,
/// one LRW per cycle; on exit the slave goes back to the state (and assignment) it was found in.
int run_drive_ecat(const DriveArgs& a) {
    auto s = open_segment(a.ethercat, 1);
    if (!s) {
        return kExitNoBus;
    }
    ethercat::Master& m = *s->master;
    const auto slave = slave_for_coe(m, a.node, 1);
    if (!slave) {
        return kExitFailure;
    }
    if (!m.set_state_all(ethercat::AlState::PreOp)) {
        fmt::print(stderr, "codrive: PRE-OP: {}\n", m.last_error());
        return kExitFailure;
    }
    EcatRestore restore{m, *slave, std::nullopt};
    // Identification and setup: blocking CoE in PRE-OP.
    ethercat::CoeTransport setup(m, *slave);
    drives::Axis* attached = nullptr;
    DriveWire w;
    w.transport = &setup;
    w.who = fmt::format("slave {}", a.node);
    w.attach = [&attached](drives::Axis* axis) { attached = axis; };
    w.run_until = [&](const std::function<bool()>& pred, Duration timeout) {
        const TimePoint deadline = RealClock::instance().now() + timeout;
        while (!pred()) {
            if (RealClock::instance().now() >= deadline) {
                return false;
            }
            setup.poll();
            if (setup.pending() == 0) {
                std::this_thread::sleep_for(milliseconds(1));
            }
        }
        return true;
    };
    const drives::Profile* profile = identify(w);
    if (profile == nullptr) {
        return stop_requested() ? 128 + stop_signal() : kExitFailure;
    }
    // --esi: the vendor's file must describe this slave (vendor, product; exact revision
    // first); its default PDO assignment is the layout of a drive codrive has no profile for.
    std::optional<ethercat::EsiDefaultPdos> esi_pdos;
    if (!a.esi.empty()) {
        const auto esi = slave_esi(a.esi, m, *slave);
        if (!esi) {
            return kExitFailure;
        }
        esi_pdos = ethercat::esi_default_pdos(*esi->device);
    }
    auto current = m.read_pdo_assignment(*slave);
    if (!current) {
        fmt::print(stderr, "codrive: reading the PDO assignment (0x1C12/0x1C13): {}\n",
                   m.last_error());
        return kExitFailure;
    }
    auto layout = ethercat::choose_layout(*profile, a.axis, layout_mode(a), current->first,
                                          current->second, esi_pdos ? &*esi_pdos : nullptr);
    if (!layout) {
        fmt::print(stderr, "codrive: {}: {}\n", m.slave_label(*slave), layout.error());
        return kExitFailure;
    }
    if (layout->source != ethercat::LayoutSource::SlaveAssignment) {
        if (!m.configure_pdos(*slave, layout->rx, layout->tx)) {
            fmt::print(stderr, "codrive: PDO configuration failed: {}\n", m.last_error());
            return kExitFailure;
        }
        restore.assignment = std::move(*current);
    }
    const Duration cycle = microseconds(a.cycle_us);
    ethercat::SyncSettings sync;
    sync.cycle = cycle;
    sync.mode = a.dc
                    ? ethercat::SyncMode::DcSync0
                    : ethercat::sync_mode_from_string(a.sync).value_or(ethercat::SyncMode::FreeRun);
    if (sync.mode == ethercat::SyncMode::DcSync0) {
        if (auto r = m.configure_dc(); !r) {
            fmt::print(stderr, "codrive: distributed clocks: {}\n", m.last_error());
            return kExitFailure;
        }
    }
    auto synced = ethercat::configure_sync(m, *slave, sync);
    if (!synced) {
        fmt::print(stderr, "codrive: {}\n", synced.error());
        return kExitFailure;
    }
    for (const auto& note : synced->notes) {
        fmt::print("{}\n", note);
    }
    if (!m.set_state_all(ethercat::AlState::Op)) {
        fmt::print(stderr, "codrive: OP: {}\n", m.last_error());
        return kExitFailure;
    }
    fmt::print("{}: OP, PDO layout from {}, {} output / {} input bytes, cycle {} µs, {}\n",
               m.slave_label(*slave), ethercat::to_string(layout->source),
               m.slaves()[*slave].output_bytes, m.slaves()[*slave].input_bytes, a.cycle_us,
               sync.mode == ethercat::SyncMode::FreeRun ? "free run"
                                                        : ethercat::sync_mode_name(synced->mode));
    // From here on the cyclic frame carries the process data and the mailbox transfers.
    ethercat::CoeTransport transport(m, *slave, ethercat::CoeTransport::Drive::Cyclic);
    w.transport = &transport;
    TimePoint next = RealClock::instance().now();
    w.why_no_inputs = [&m, &a, at_op = m.stats()] {
        return ethercat::cyclic_shortfall(at_op, m.stats(), microseconds(a.cycle_us));
    };
    w.inputs_in = [&m] { return std::optional<std::uint64_t>(m.stats().input_frames); };
    w.run_until = [&](const std::function<bool()>& pred, Duration timeout) {
        const TimePoint deadline = RealClock::instance().now() + timeout;
        while (!pred()) {
            TimePoint now = RealClock::instance().now();
            if (now >= deadline) {
                return false;
            }
            if (now < next) {
                std::this_thread::sleep_until(next);
                now = RealClock::instance().now();
            }
            next += cycle;
            if (next <= now) {
                next = now + cycle; // late: skip the missed slots
            }
            if (m.send_process_data()) {
                (void)m.receive_process_data(next);
            }
            transport.poll();
            if (attached != nullptr) {
                attached->on_cycle(now);
                if (attached->next_deadline() <= now) {
                    attached->on_tick(now);
                }
            }
        }
        return true;
    };
    const auto texts = drives::emcy_text_provider(*profile);
    m.on_emergency([&](std::size_t from, const emcy::EmcyMessage& e) {
        fmt::print("{}\n", m.describe_emergency(from, e, texts.get()));
        if (attached != nullptr) {
            attached->note_error_code(e.error_code);
        }
    });
    drives::Axis axis(transport, axis_config(a, *profile));
    axis.bind();
    w.attach(&axis);
    const int rc = operate(a, w, axis, *profile);
    w.attach(nullptr);
    m.on_emergency(nullptr);
    return rc;
}

int run_drive(const DriveArgs& a) {
    if (a.iface.empty() == a.ethercat.empty()) {
        fmt::print(stderr, "codrive: drive needs -i IFACE (CAN) or --ethercat IFACE\n");
        return kExitUsage;
    }
    catch_stop_signals();
    return a.ethercat.empty() ? run_drive_can(a) : run_drive_ecat(a);
}

void install_drive(CLI::App& app, int& exit_code) {
    auto a = std::make_shared<DriveArgs>();
    auto* cmd = app.add_subcommand(
        "drive", "Operate one CiA 402 axis (CAN: SDO; EtherCAT: process data in OP)");
    auto* can = cmd->add_option("-i,--iface", a->iface, "CAN interface");
    auto* ecat =
        cmd->add_option("--ethercat", a->ethercat, "EtherCAT: network interface of the segment")
            ->excludes(can);
    cmd->add_option("-n,--node", a->node, "Node id (EtherCAT: slave position from 1)")->required();
    cmd->add_option("--axis", a->axis, "Axis of a multi-axis drive (AKD2G: 1 or 2)")
        ->capture_default_str();
    cmd->footer("SIGINT/SIGTERM: an axis the command has commanded gets quick stop, then "
                "disable voltage (within 1 s; see docs/safe-stop.md); exit status 130/143. Exit "
                "status: 0 done, 1 failed, 2 bad arguments, 3 no interface.");
    cmd->add_option("action", a->action, "status|enable|disable|reset|home|move|jog")
        ->required()
        ->check(CLI::IsMember({"status", "enable", "disable", "reset", "home", "move", "jog"}));
    cmd->add_option("--method", a->method, "Homing method (6098h)")->capture_default_str();
    cmd->add_option("--pp", a->pp, "move: profile position target");
    cmd->add_option("--pv", a->pv, "move: profile velocity");
    cmd->add_option("--velocity", a->jog_velocity, "jog: velocity")->capture_default_str();
    cmd->add_option("--seconds", a->jog_s, "jog: duration")->capture_default_str();
    cmd->add_option("--cycle", a->cycle_us, "EtherCAT: process data cycle in µs")
        ->capture_default_str();
    cmd->add_flag("--dc", a->dc, "EtherCAT: synchronise the slave to DC SYNC0 (= --sync dc)");
    cmd->add_option("--sync", a->sync,
                    "EtherCAT: sync mode written to 1C32h:01/1C33h:01: free (free run, the "
                    "default), sm (synchronous with the SM2 event), dc (DC SYNC0)")
        ->check(CLI::IsMember({"free", "sm", "dc"}));
    cmd->add_option("--esi", a->esi,
                    "EtherCAT: the slave's ESI file (checked against its identity; a drive "
                    "without a codrive profile runs from the file's default PDO assignment)")
        ->needs(ecat);
    cmd->add_option("--timeout", a->timeout_ms, "Operation timeout in ms")->capture_default_str();
    cmd->callback([a, &exit_code] { exit_code = run_drive(*a); });
}

} // namespace
} // namespace codrive::cli

using codrive::cli::install_drive;
CODRIVE_REGISTER_COMMAND(install_drive);
