// SPDX-License-Identifier: Apache-2.0
// The smallest useful program: boot the bus from a file, enable one axis, move it, stop.
//   codrive-minimal_axis BUS.yml [NODE] [DISTANCE]
#include <codrive/controller/controller.hpp>

#include <cstdio>
#include <string>

using namespace codrive;

int main(int argc, char** argv) {
    if (argc < 2) {
        std::fprintf(stderr, "usage: %s BUS.yml [NODE] [DISTANCE]\n", argv[0]);
        return 2;
    }
    const auto node = static_cast<NodeId>(argc > 2 ? std::stoi(argv[2]) : 1);
    const std::int32_t distance = argc > 3 ? std::stoi(argv[3]) : 100000;

    auto controller = controller::Controller::from_file(argv[1]);
    if (!controller) {
        std::fprintf(stderr, "%s", controller.error().detail.c_str());
        return 1;
    }
    auto& c = **controller;
    c.stop_on_signals();
    if (auto started = c.start(); !started) {
        std::fprintf(stderr, "%s\n", started.error().detail.c_str());
        return 1;
    }
    drives::Axis* axis = c.axis(node);
    if (axis == nullptr || !c.run_until([&] { return axis->has_statusword(); }, seconds(2))) {
        std::fprintf(stderr, "node %d has no axis with a statusword\n", node);
        return 1;
    }
    std::string error;
    bool done = false;
    axis->enable([&](drives::DriveVoid r) {
        error = r ? "" : r.error().message;
        done = true;
    });
    c.run_until([&] { return done; }, seconds(3));
    if (!error.empty() || !done) {
        std::fprintf(stderr, "%s\n", done ? error.c_str() : "enable did not finish");
        return 1;
    }
    // Cyclic synchronous position: a new set-point every SYNC, 100 increments per cycle.
    const std::int32_t start = axis->position_actual().value_or(0);
    std::int32_t offset = 0;
    c.set_cycle_callback([&](const controller::CycleInfo&) {
        offset = distance > 0 ? std::min(offset + 100, distance) : std::max(offset - 100, distance);
        axis->set_target_position(start + offset);
    });
    c.run_until([&] { return offset == distance; }, seconds(30));
    c.run_for(milliseconds(200));
    std::printf("%s moved from %d to %d\n", axis->name().c_str(), start,
                axis->position_actual().value_or(0));
    c.shutdown();
    return c.stop_requested() ? 128 + c.stop_signal() : 0; // Ctrl-C: stopped safely, 130
}
