// SPDX-License-Identifier: Apache-2.0
// The EtherCAT demo: a bus file with an `ethercat:` segment, one drive enabled and moved in CSP
// over the CoE transport, status printed while it moves, safe shutdown, summary. SIGINT/SIGTERM
// end it early with the same safe shutdown and exit status 128 + the signal number.
//   codrive-ecat_demo BUS.yml [DISTANCE]
#include <codrive/controller/controller.hpp>

#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <string>

using namespace codrive;

namespace {

/// SIGINT/SIGTERM arrived: the safe shutdown (quick stop, disable, PRE-OP), exit 128 + signal.
int stopped(controller::Controller& c) {
    c.set_cycle_callback(nullptr);
    std::printf("== %s received: shutdown (quick stop, disable, PRE-OP)\n",
                c.stop_signal() == SIGTERM ? "SIGTERM" : "SIGINT");
    c.shutdown();
    for (const auto& a : c.axes()) {
        std::printf("  %s is %s\n", a.name.c_str(),
                    std::string(drives::cia402::to_string(a.axis->state())).c_str());
    }
    return 128 + (c.stop_signal() != 0 ? c.stop_signal() : SIGINT);
}

} // namespace

int main(int argc, char** argv) {
    if (argc < 2) {
        std::fprintf(stderr, "usage: %s BUS.yml [DISTANCE]\n", argv[0]);
        return 2;
    }
    const std::int32_t distance = argc > 2 ? std::stoi(argv[2]) : 20000;
    auto controller = controller::Controller::from_file(argv[1]);
    if (!controller) {
        std::fprintf(stderr, "%s", controller.error().detail.c_str());
        return 1;
    }
    auto& c = **controller;
    c.set_event_callback([](const std::string& t) { std::printf("  event: %s\n", t.c_str()); });
    c.stop_on_signals();
    std::printf("== bring-up (ESM to OP, PDO layout from the profile)\n");
    if (auto started = c.start(); !started) {
        std::fprintf(stderr, "%s\n", started.error().detail.c_str());
        return c.stop_signal() != 0 ? 128 + c.stop_signal() : 1;
    }
    drives::Axis* axis = nullptr;
    for (const auto& a : c.axes()) {
        std::printf("  axis: %s (bus %zu)\n", a.name.c_str(), a.bus);
        if (axis == nullptr && a.bus >= c.can_bus_count()) {
            axis = a.axis;
        }
    }
    if (axis == nullptr || !c.run_until([&] { return axis->has_statusword(); }, seconds(2))) {
        if (c.stop_requested()) {
            return stopped(c);
        }
        std::fprintf(stderr, "no EtherCAT axis with a cyclic statusword\n");
        return 1;
    }
    std::printf("== enable: %s, statusword 0x%04X\n",
                std::string(drives::cia402::to_string(axis->state())).c_str(), axis->statusword());
    std::string error;
    bool done = false;
    axis->enable([&](drives::DriveVoid r) {
        error = r ? "" : r.error().message;
        done = true;
    });
    if (!c.run_until([&] { return done; }, seconds(3)) || !error.empty()) {
        if (c.stop_requested()) {
            return stopped(c);
        }
        std::fprintf(stderr, "enable failed: %s\n", done ? error.c_str() : "timeout");
        return 1;
    }
    std::printf("  %s is %s\n", axis->name().c_str(),
                std::string(drives::cia402::to_string(axis->state())).c_str());

    std::printf("== CSP move by %d increments, one set-point per cycle\n", distance);
    const std::int32_t start = axis->position_actual().value_or(0);
    std::int32_t offset = 0;
    c.set_cycle_callback([&](const controller::CycleInfo&) {
        offset = distance > 0 ? std::min(offset + 50, distance) : std::max(offset - 50, distance);
        axis->set_target_position(start + offset);
    });
    for (int i = 0; i < 200 && offset != distance && !c.stop_requested(); ++i) {
        c.run_for(milliseconds(250));
        std::printf("  target %8d  actual %8d  %s\n", start + offset,
                    axis->position_actual().value_or(0),
                    std::string(drives::cia402::to_string(axis->state())).c_str());
    }
    c.run_for(milliseconds(200));
    if (c.stop_requested()) {
        return stopped(c);
    }
    const std::int32_t end = axis->position_actual().value_or(0);
    std::printf("  %s moved from %d to %d\n", axis->name().c_str(), start, end);
    c.set_cycle_callback(nullptr);
    std::printf("== statistics: %s\n", c.stats().to_string().c_str());
    std::printf("== shutdown (quick stop, disable, PRE-OP)\n");
    c.shutdown();
    std::printf("  %s is %s\n", axis->name().c_str(),
                std::string(drives::cia402::to_string(axis->state())).c_str());
    const bool ok = std::abs(end - (start + distance)) <= 100 &&
                    axis->state() == drives::cia402::State::SwitchOnDisabled;
    std::printf("== %s\n", ok ? "demo finished: OK" : "demo FAILED");
    return ok ? 0 : 1;
}
