// SPDX-License-Identifier: Apache-2.0
// codrive-demo: the README's main job. Boots a bus of simulated (or real) drives from a bus
// file (CAN or EtherCAT: the program is the same, only the file's transport section differs) and
// walks through what a motion controller does: boot report, enable, homing, a
// coordinated two-axis CSP move, a velocity move, an injected fault diagnosed with the vendor's
// text and recovered, a live status table, and a summary. Exit status 0 only if every step
// worked; on SIGINT/SIGTERM it stops where it is with the safe shutdown and exits 128 + the
// signal number (130, 143).   codrive-demo BUS.yml [--fault-node N]
#include <codrive/controller/controller.hpp>
#include <codrive/drives/coordinated.hpp>
#include <codrive/drives/profile.hpp>

#include <fmt/format.h>

#include <algorithm>
#include <csignal>
#include <cstring>
#include <memory>
#include <optional>
#include <string>
#include <vector>

using namespace codrive;
using drives::Axis;
using drives::DriveVoid;

namespace {

struct Demo {
    explicit Demo(controller::Controller& ctl) : c(ctl) {}
    controller::Controller& c;
    std::vector<std::string> failures;
    TimePoint t0 = SteadyClock::now();

    void say(const std::string& s) const {
        fmt::print("[{:7.3f} s] {}\n",
                   std::chrono::duration<double>(SteadyClock::now() - t0).count(), s);
        std::fflush(stdout);
    }
    void step(const std::string& title) const { fmt::print("\n\033[1m== {}\033[0m\n", title); }

    /// Runs an asynchronous axis operation to its end.
    bool wait(const std::string& what, const std::function<void(Axis::Done)>& op,
              Duration timeout = seconds(10)) {
        // Shared with the callback: on Ctrl-C the wait ends first and the shutdown cancels the
        // operation later.
        auto done = std::make_shared<bool>(false);
        auto error = std::make_shared<std::string>();
        op([done, error](DriveVoid r) {
            *done = true;
            *error = r ? "" : r.error().message;
        });
        c.run_until([&] { return *done; }, timeout);
        if (c.stop_requested()) {
            return false; // not a failure of the step: main() stops the demo
        }
        return finished(what, *done, *error, timeout);
    }

    /// Records how a wait ended: "ok", or a failure with its sentence.
    bool finished(const std::string& what, bool done, std::string error, Duration timeout) {
        if (!done) {
            error = what + ": did not finish within " + fmt::format("{:.0f} ms", to_ms(timeout));
        }
        if (!error.empty()) {
            failures.push_back(error);
            say("FAILED: " + error);
            return false;
        }
        say(what + ": ok");
        return true;
    }

    void table() const {
        fmt::print("  {:<26} {:<20} {:<6} {:>12} {:>10} {:>7}  {}\n", "axis", "state", "mode",
                   "position", "velocity", "torque", "last EMCY");
        for (const auto& ref : c.axes()) {
            const Axis& a = *ref.axis;
            // The last emergency's error code as the axis noted it (CAN EMCY or CoE emergency).
            std::string emcy = "-";
            if (const std::uint16_t code = a.last_error_code(); code != 0) {
                emcy = fmt::format("0x{:04X}", code);
                const std::string vendor = a.profile().fault_text(code);
                if (!vendor.empty()) {
                    emcy += " " + vendor;
                }
            }
            fmt::print("  {:<26} {:<20} {:<6} {:>12} {:>10} {:>7}  {}\n", ref.name,
                       drives::cia402::to_string(a.state()),
                       a.mode_display() ? std::to_string(*a.mode_display()) : "-",
                       a.position_actual() ? std::to_string(*a.position_actual()) : "-",
                       a.velocity_actual() ? std::to_string(*a.velocity_actual()) : "-",
                       a.torque_actual() ? std::to_string(*a.torque_actual()) : "-", emcy);
        }
    }

    /// SIGINT/SIGTERM: the safe shutdown now, then exit status 128 + the signal.
    int stop_now() const {
        c.set_cycle_callback(nullptr);
        step(fmt::format("{} received: safe shutdown (quick stop, disable, NMT pre-operational)",
                         c.stop_signal() == SIGTERM ? "SIGTERM" : "SIGINT"));
        c.shutdown();
        table();
        return 128 + (c.stop_signal() != 0 ? c.stop_signal() : SIGINT);
    }

    /// Writes one byte to an object of a CAN node or EtherCAT slave (whatever the bus file's
    /// transport), to its end.
    bool write_u8(std::size_t bus, NodeId node, std::uint16_t index, std::uint8_t sub,
                  std::uint8_t v) {
        auto done = std::make_shared<bool>(false); // outlives a wait ended by Ctrl-C
        auto error = std::make_shared<std::string>();
        c.write_object(bus, node, index, sub, {v}, [done, error](drives::DriveVoid r) {
            *done = true;
            *error = r ? "" : r.error().message;
        });
        c.run_until([&] { return *done; }, seconds(2));
        if (!*done || !error->empty()) {
            failures.push_back(*done ? *error
                                     : fmt::format("write of object {:04X}h:{:02X}h to node {} "
                                                   "did not finish within 2 s",
                                                   index, sub, node));
            return false;
        }
        return true;
    }
};

} // namespace

int main(int argc, char** argv) {
    if (argc < 2) {
        fmt::print(stderr, "usage: {} BUS.yml [--fault-node N]\n", argv[0]);
        return 2;
    }
    // The fault goes to axis 1 of the second device of the first bus (CAN node 2, or EtherCAT
    // slave 1, in the demo's bus files) unless --fault-node names another.
    std::optional<NodeId> fault_node;
    for (int i = 2; i + 1 < argc; ++i) {
        if (std::strcmp(argv[i], "--fault-node") == 0) {
            fault_node = static_cast<NodeId>(std::stoi(argv[i + 1]));
        }
    }
    auto created = controller::Controller::from_file(argv[1]);
    if (!created) {
        fmt::print(stderr, "codrive-demo: {}\n", created.error().detail);
        return 1;
    }
    controller::Controller& c = **created;
    Demo d{c};
    c.stop_on_signals();
    // PDO timing events are counted in the summary; on a loaded machine (or the 1-CPU vcan
    // guest) a late TPDO now and then is normal and would drown the story.
    std::size_t pdo_events = 0;
    c.set_event_callback([&](const std::string& text) {
        if (text.find("TPDO") != std::string::npos || text.find("RPDO") != std::string::npos) {
            ++pdo_events;
        } else if (text.find('\n') == std::string::npos) {
            d.say(text);
        }
    });

    d.step("boot-up: identity check, configuration, PDO mapping, NMT start");
    if (auto r = c.start(); !r) {
        fmt::print(stderr, "codrive-demo: {}\n", r.error().detail);
        return c.stop_signal() != 0 ? 128 + c.stop_signal() : 1;
    }
    for (const auto& r : c.boot_reports()) {
        fmt::print("{}", r.to_string());
    }
    const auto axes = c.axes();
    if (!c.run_until(
            [&] {
                for (const auto& a : axes) {
                    if (!a.axis->has_statusword()) {
                        return false;
                    }
                }
                return true;
            },
            seconds(3))) {
        if (c.stop_requested()) {
            return d.stop_now();
        }
        fmt::print(stderr, "codrive-demo: not every axis reported a statusword by PDO\n");
        return 1;
    }
    d.table();

    d.step("enable every axis");
    for (const auto& a : axes) {
        Axis* ax = a.axis;
        d.wait(a.name + " enable", [&](Axis::Done done) { ax->enable(std::move(done)); });
    }
    if (c.stop_requested()) {
        return d.stop_now();
    }

    // The first two CSP axes form the gantry; the first CSV axis is the spindle.
    std::vector<Axis*> gantry;
    std::size_t gantry_bus = 0;
    Axis* spindle = nullptr;
    for (const auto& a : axes) {
        const std::int8_t mode = a.mode.value_or(0);
        if (mode == 8 && gantry.size() < 2) {
            gantry.push_back(a.axis);
            gantry_bus = a.bus;
        } else if (mode == 9 && spindle == nullptr) {
            spindle = a.axis;
        }
    }

    if (!gantry.empty()) {
        Axis* ax = gantry[0];
        const auto& methods = ax->profile().homing_methods;
        const std::int8_t method = std::find(methods.begin(), methods.end(), 35) != methods.end()
                                       ? 35
                                   : methods.empty() ? 35
                                                     : methods.back();
        d.step(fmt::format("homing {} (method {}), then back to CSP", ax->name(), method));
        d.wait("mode HM", [&](Axis::Done done) {
            ax->set_mode(drives::cia402::Mode::Homing, std::move(done));
        });
        drives::HomingParams hp;
        hp.method = method;
        hp.speed_switch = 20000;
        hp.speed_zero = 5000;
        hp.acceleration = 100000;
        d.wait("homing", [&](Axis::Done done) { ax->home(hp, std::move(done)); });
        d.wait("mode CSP", [&](Axis::Done done) {
            ax->set_mode(drives::cia402::Mode::CyclicSyncPosition, std::move(done));
        });
    }
    if (c.stop_requested()) {
        return d.stop_now();
    }

    if (gantry.size() == 2) {
        d.step("coordinated two-axis CSP move (jerk-limited, one set-point per axis per SYNC)");
        const Duration period = c.cycle_period(gantry_bus);
        drives::CoordinatedMotion motion(gantry, period);
        c.set_cycle_callback([&](const controller::CycleInfo&) { motion.on_sync(); });
        Eigen::VectorXd end(2);
        end << static_cast<double>(gantry[0]->position_actual().value_or(0) + 400000),
            static_cast<double>(gantry[1]->position_actual().value_or(0) - 200000);
        Eigen::VectorXd vmax = Eigen::VectorXd::Constant(2, 400000.0);
        Eigen::VectorXd amax = Eigen::VectorXd::Constant(2, 2000000.0);
        Eigen::VectorXd jmax = Eigen::VectorXd::Constant(2, 40000000.0);
        bool done = false;
        std::string error;
        auto started = motion.start(end, vmax, amax, jmax, drives::ProfileShape::JerkLimited,
                                    [&](DriveVoid r) {
                                        done = true;
                                        error = r ? "" : r.error().message;
                                    });
        if (!started) {
            d.failures.push_back(started.error().message);
            d.say("FAILED: " + started.error().message);
        } else {
            int ticks = 0;
            while (!done && ticks < 100 && !c.stop_requested()) {
                c.run_for(milliseconds(250));
                ++ticks;
                if (ticks % 2 == 0) {
                    d.table();
                }
            }
            c.run_for(milliseconds(100));
            if (c.stop_requested()) {
                return d.stop_now();
            }
            if (!done || !error.empty()) {
                d.failures.push_back(done ? error : "coordinated move did not finish");
            }
            const double err0 = std::abs(gantry[0]->position_actual().value_or(0) - end[0]);
            const double err1 = std::abs(gantry[1]->position_actual().value_or(0) - end[1]);
            d.say(fmt::format("coordinated move done in {} cycles; final position error {:.0f} / "
                              "{:.0f} increments",
                              motion.cycles(), err0, err1));
            if (err0 > 1000 || err1 > 1000) {
                d.failures.push_back("coordinated move ended off target");
            }
        }
        c.set_cycle_callback(nullptr);
    }

    if (spindle != nullptr) {
        d.step(fmt::format("{}: cyclic synchronous velocity", spindle->name()));
        spindle->set_target_velocity(50000);
        c.run_for(milliseconds(500));
        d.table();
        spindle->set_target_velocity(0);
        c.run_for(milliseconds(300));
    }
    if (c.stop_requested()) {
        return d.stop_now();
    }

    if (!fault_node) {
        std::vector<NodeId> devices;
        for (const auto& a : axes) {
            if (a.bus == axes.front().bus &&
                std::find(devices.begin(), devices.end(), a.node) == devices.end()) {
                devices.push_back(a.node);
            }
        }
        fault_node = devices.size() > 1 ? devices[1] : devices.empty() ? NodeId{1} : devices[0];
    }
    Axis* victim = nullptr;
    std::size_t victim_bus = 0;
    for (const auto& a : axes) {
        if (a.node == *fault_node && a.number == 1 && victim == nullptr) {
            victim = a.axis;
            victim_bus = a.bus;
        }
    }
    d.step(fmt::format("inject an over-current fault on {} and recover",
                       victim != nullptr ? victim->name() : fmt::format("node {}", *fault_node)));
    // The simulators' fault injection (sim_device.hpp): object 2FF0h sub 2 = 1 raises an
    // over-current fault on the axis, 0 removes its cause. Written by SDO on CAN, CoE on EtherCAT.
    if (victim == nullptr) {
        d.failures.push_back(fmt::format("node {} has no axis 1", *fault_node));
    } else if (d.write_u8(victim_bus, *fault_node, 0x2FF0, 2, 1)) {
        c.run_until([&] { return victim->state() == drives::cia402::State::Fault; }, seconds(2));
        // The emergency that names the fault may arrive a cycle or two after the statusword.
        c.run_until([&] { return victim->last_error_code() != 0; }, seconds(1));
        d.say(fmt::format("{} is in {}: {}", victim->name(),
                          drives::cia402::to_string(victim->state()), victim->diagnose()));
        d.table();
        if (victim->state() != drives::cia402::State::Fault) {
            d.failures.push_back("the injected fault did not bring the axis to FAULT");
        }
        d.write_u8(victim_bus, *fault_node, 0x2FF0, 2, 0); // the cause goes away
        d.wait("fault reset", [&](Axis::Done done) { victim->fault_reset(std::move(done)); });
        d.wait("enable again", [&](Axis::Done done) { victim->enable(std::move(done)); });
        d.table();
    }
    if (c.stop_requested()) {
        return d.stop_now();
    }

    d.step("safe shutdown: quick stop, disable, NMT pre-operational");
    c.shutdown();
    d.table();
    d.step("summary");
    fmt::print("  {}\n  PDO timing events: {}\n", c.stats().to_string(), pdo_events);
    if (d.failures.empty()) {
        fmt::print("  demo OK: every step worked\n");
        return 0;
    }
    fmt::print("  demo FAILED: {} step(s) failed:\n", d.failures.size());
    for (const auto& f : d.failures) {
        fmt::print("   - {}\n", f);
    }
    return 1;
}
