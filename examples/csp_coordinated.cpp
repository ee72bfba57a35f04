// SPDX-License-Identifier: Apache-2.0
// Coordinated CSP motion: two axes trace a square, one set-point per axis per SYNC, with a
// jerk-limited profile; prints the position error at each corner.
//   codrive-csp_coordinated BUS.yml [SIDE]
#include <codrive/controller/controller.hpp>
#include <codrive/drives/coordinated.hpp>

#include <fmt/format.h>

using namespace codrive;

int main(int argc, char** argv) {
    if (argc < 2) {
        fmt::print(stderr, "usage: {} BUS.yml [SIDE]\n", argv[0]);
        return 2;
    }
    const double side = argc > 2 ? std::stod(argv[2]) : 200000.0;
    auto created = controller::Controller::from_file(argv[1]);
    if (!created) {
        fmt::print(stderr, "{}", created.error().detail);
        return 1;
    }
    auto& c = **created;
    c.stop_on_signals();
    if (auto r = c.start(); !r) {
        fmt::print(stderr, "{}\n", r.error().detail);
        return 1;
    }
    std::vector<drives::Axis*> xy;
    for (const auto& ref : c.axes()) {
        if (xy.size() < 2) {
            xy.push_back(ref.axis);
        }
    }
    if (xy.size() != 2 ||
        !c.run_until([&] { return xy[0]->has_statusword() && xy[1]->has_statusword(); },
                     seconds(3))) {
        fmt::print(stderr, "need two axes with cyclic statusword\n");
        return 1;
    }
    int enabled = 0;
    for (auto* a : xy) {
        a->enable([&](drives::DriveVoid r) { enabled += r ? 1 : 100; });
    }
    c.run_until([&] { return enabled >= 2; }, seconds(5));
    if (enabled != 2) {
        fmt::print(stderr, "enable failed\n");
        return 1;
    }
    drives::CoordinatedMotion motion(xy, microseconds(c.config().sync_period_us));
    c.set_cycle_callback([&](const controller::CycleInfo&) { motion.on_sync(); });
    const Eigen::Vector2d origin(xy[0]->position_actual().value_or(0),
                                 xy[1]->position_actual().value_or(0));
    const Eigen::Vector2d corners[] = {{side, 0}, {side, side}, {0, side}, {0, 0}};
    const Eigen::VectorXd v = Eigen::VectorXd::Constant(2, 400000.0);
    const Eigen::VectorXd acc = Eigen::VectorXd::Constant(2, 2000000.0);
    const Eigen::VectorXd jerk = Eigen::VectorXd::Constant(2, 40000000.0);
    int failures = 0;
    for (const auto& corner : corners) {
        if (c.stop_requested()) {
            break; // Ctrl-C: no further corner; the shutdown below stops the axes
        }
        const Eigen::VectorXd end = origin + corner;
        bool done = false;
        auto started = motion.start(end, v, acc, jerk, drives::ProfileShape::JerkLimited,
                                    [&](drives::DriveVoid r) {
                                        done = true;
                                        failures += r ? 0 : 1;
                                    });
        if (!started) {
            fmt::print(stderr, "{}\n", started.error().message);
            return 1;
        }
        c.run_until([&] { return done; }, seconds(20));
        c.run_for(milliseconds(50));
        const double ex = xy[0]->position_actual().value_or(0) - end[0];
        const double ey = xy[1]->position_actual().value_or(0) - end[1];
        fmt::print("corner ({:.0f}, {:.0f}) reached in {} cycles, error ({:.0f}, {:.0f})\n",
                   corner[0], corner[1], motion.cycles(), ex, ey);
        failures += (std::abs(ex) > 1000 || std::abs(ey) > 1000) ? 1 : 0;
    }
    c.set_cycle_callback(nullptr); // the motion's callback holds the loop's locals
    c.shutdown();
    fmt::print("{}\n", c.stats().to_string());
    if (c.stop_requested()) {
        return 128 + c.stop_signal();
    }
    return failures == 0 ? 0 : 1;
}
