// SPDX-License-Identifier: Apache-2.0
// Trajectories: limits respected, exact end, same-SYNC set-points for every axis, coordinated
// stop.
#include "rig.hpp"

#include <codrive/drives/coordinated.hpp>
#include <codrive/drives/trajectory.hpp>

#include <gtest/gtest.h>

namespace codrive::drives {
namespace {

struct Extremes {
    double v = 0;
    double a = 0;
    double j = 0;
};

Extremes sample_extremes(const ScalarProfile& p, double dt) {
    Extremes e;
    MotionState prev = p.at(0);
    for (double t = dt; t <= p.duration() + dt; t += dt) {
        const MotionState s = p.at(t);
        e.v = std::max(e.v, std::abs(s.v));
        e.a = std::max(e.a, std::abs(s.a));
        e.j = std::max(e.j, std::abs(s.a - prev.a) / dt);
        prev = s;
    }
    return e;
}

TEST(Trajectory, TrapezoidRespectsLimitsAndEndsExactly) {
    for (double dist : {0.001, 0.5, 10.0, 1000.0}) {
        auto p = ScalarProfile::rest_to_rest(dist, 2.0, 4.0, 0, ProfileShape::Trapezoidal);
        const Extremes e = sample_extremes(p, 1e-4);
        EXPECT_LE(e.v, 2.0 + 1e-9) << dist;
        EXPECT_LE(e.a, 4.0 + 1e-9) << dist;
        EXPECT_DOUBLE_EQ(p.at(p.duration() + 1).p, dist);
        EXPECT_NEAR(p.at(p.duration() - 1e-9).p, dist, 1e-6);
    }
    // Long move: cruise at vmax; time = d/v + v/a.
    auto p = ScalarProfile::rest_to_rest(1000.0, 2.0, 4.0, 0, ProfileShape::Trapezoidal);
    EXPECT_NEAR(p.duration(), 1000.0 / 2.0 + 2.0 / 4.0, 1e-9);
}

TEST(Trajectory, JerkLimitedRespectsLimitsAndEndsExactly) {
    for (double dist : {0.0001, 0.05, 1.0, 100.0}) {
        auto p = ScalarProfile::rest_to_rest(dist, 2.0, 4.0, 20.0, ProfileShape::JerkLimited);
        const Extremes e = sample_extremes(p, 1e-4);
        EXPECT_LE(e.v, 2.0 + 1e-6) << dist;
        EXPECT_LE(e.a, 4.0 + 1e-6) << dist;
        EXPECT_LE(e.j, 20.0 * 1.001) << dist;
        EXPECT_NEAR(p.at(p.duration() - 1e-9).p, dist, 1e-6) << dist;
        EXPECT_NEAR(p.at(p.duration() - 1e-9).v, 0, 1e-6) << dist;
    }
}

TEST(Trajectory, StopFromMotionRespectsLimits) {
    auto p = ScalarProfile::rest_to_rest(100.0, 2.0, 4.0, 20.0, ProfileShape::JerkLimited);
    for (double t : {0.05, 0.2, 0.4, 5.0}) {
        const MotionState s = p.at(t);
        auto stop = ScalarProfile::stop_from(s, 4.0, 20.0, ProfileShape::JerkLimited);
        const Extremes e = sample_extremes(stop, 1e-4);
        EXPECT_LE(e.a, 4.0 + 1e-6) << t;
        EXPECT_NEAR(stop.at(stop.duration() - 1e-9).v, 0, 1e-3) << t;
        EXPECT_GE(stop.end().p, s.p);
    }
    // While already braking (a < 0): both the "fade out first" and "standstill while fading"
    // cases.
    for (double before_end : {0.6, 0.3, 0.05}) {
        const MotionState s = p.at(p.duration() - before_end);
        ASSERT_LT(s.a, 0) << before_end;
        auto stop = ScalarProfile::stop_from(s, 4.0, 20.0, ProfileShape::JerkLimited);
        const Extremes e = sample_extremes(stop, 1e-5);
        EXPECT_LE(e.a, 4.0 + 1e-6) << before_end;
        EXPECT_LE(e.j, 20.0 * 1.001) << before_end;
        EXPECT_NEAR(stop.at(stop.duration() - 1e-9).v, 0, 1e-3) << before_end;
        EXPECT_LE(stop.end().p, p.end().p + 1e-6) << before_end; // never beyond the target
    }
    auto trap = ScalarProfile::stop_from({1.0, 2.0, 0}, 4.0, 0, ProfileShape::Trapezoidal);
    EXPECT_NEAR(trap.duration(), 0.5, 1e-12);
    EXPECT_NEAR(trap.at(trap.duration()).p, 1.5, 1e-12);
}

TEST(Trajectory, LinearMoveKeepsEveryAxisWithinItsLimitsAndArrivesTogether) {
    Eigen::VectorXd start(3), end(3), v(3), a(3), j(3);
    start << 0, 100, -50;
    end << 10000, 100, 2000;
    v << 5000, 1000, 500;
    a << 20000, 5000, 1000;
    j << 1e6, 1e5, 5e4;
    for (auto shape : {ProfileShape::Trapezoidal, ProfileShape::JerkLimited}) {
        LinearTrajectory tr(start, end, v, a, j, shape);
        const double dt = 0.001;
        for (double t = 0; t <= tr.duration() + dt; t += dt) {
            const Eigen::VectorXd vel = tr.velocity(t);
            const Eigen::VectorXd acc = tr.acceleration(t);
            for (int i = 0; i < 3; ++i) {
                ASSERT_LE(std::abs(vel[i]), v[i] * (1 + 1e-6)) << "axis " << i << " t " << t;
                ASSERT_LE(std::abs(acc[i]), a[i] * (1 + 1e-6)) << "axis " << i << " t " << t;
            }
            // On the line: every axis has covered the same fraction of its distance.
            const Eigen::VectorXd p = tr.position(t);
            const double f0 = (p[0] - start[0]) / (end[0] - start[0]);
            const double f2 = (p[2] - start[2]) / (end[2] - start[2]);
            ASSERT_NEAR(f0, f2, 1e-9);
            ASSERT_DOUBLE_EQ(p[1], 100);
        }
        EXPECT_TRUE(tr.position(tr.duration() + 1).isApprox(end));
    }
}

struct CoordRig {
    testing::Rig rig{akd2g_profile(), true, 2};
    testing::FakeDevice dev2{generic_profile(), 1};
    testing::FakeTransport tr2{dev2, "node 6"};
    std::unique_ptr<Axis> third;

    CoordRig() {
        for (std::uint16_t o : std::initializer_list<std::uint16_t>{0x6040, 0x6060, 0x607A}) {
            tr2.map_output(o, 0);
        }
        for (std::uint16_t i : std::initializer_list<std::uint16_t>{0x6041, 0x6061, 0x6064}) {
            tr2.map_input(i, 0);
        }
        AxisConfig cfg;
        cfg.profile = &generic_profile();
        third = std::make_unique<Axis>(tr2, cfg);
    }
    /// One SYNC period for both nodes.
    void cycle(CoordinatedMotion* cm = nullptr) {
        if (cm != nullptr) {
            cm->on_sync(); // set-points for the coming SYNC
        }
        rig.clock.advance(std::chrono::milliseconds(1));
        rig.tr.apply_outputs();
        tr2.apply_outputs();
        rig.dev.step();
        dev2.step();
        rig.tr.process();
        tr2.process();
        for (auto& ax : rig.axes) {
            ax->on_cycle(rig.clock.now());
        }
        third->on_cycle(rig.clock.now());
    }
    bool bring_up() {
        std::vector<Axis*> all{&rig.axis(1), &rig.axis(2), third.get()};
        for (Axis* a : all) {
            std::optional<DriveVoid> r;
            a->set_mode(cia402::Mode::CyclicSyncPosition, [&](DriveVoid x) { r = x; });
            for (int i = 0; i < 50 && !r; ++i) {
                cycle();
            }
            if (!r || !*r) {
                return false;
            }
            r.reset();
            a->enable([&](DriveVoid x) { r = x; });
            for (int i = 0; i < 50 && !r; ++i) {
                cycle();
            }
            if (!r || !*r) {
                return false;
            }
        }
        return true;
    }
};

TEST(CoordinatedMotion, EveryAxisGetsItsSetPointForTheSameSync) {
    CoordRig c;
    ASSERT_TRUE(c.bring_up());
    std::vector<Axis*> axes{&c.rig.axis(1), &c.rig.axis(2), c.third.get()};
    CoordinatedMotion cm(axes, std::chrono::milliseconds(1));
    Eigen::VectorXd end(3), v(3), a(3), j(3);
    end << 4000, -2000, 1000;
    v << 40000, 40000, 40000;
    a << 400000, 400000, 400000;
    j << 1e7, 1e7, 1e7;
    std::optional<DriveVoid> done;
    auto started =
        cm.start(end, v, a, j, ProfileShape::JerkLimited, [&](DriveVoid r) { done = r; });
    ASSERT_TRUE(started.has_value()) << started.error().message;
    int n = 0;
    while (!done && n++ < 2000) {
        c.cycle(&cm);
        // The devices applied the targets of the same SYNC: all on one line (±1 for rounding).
        const double f0 = static_cast<double>(c.rig.dev.model(1).position) / 4000.0;
        const double f1 = static_cast<double>(c.rig.dev.model(2).position) / -2000.0;
        const double f2 = static_cast<double>(c.dev2.model(1).position) / 1000.0;
        ASSERT_NEAR(f0, f1, 1.0 / 1000.0) << "cycle " << n;
        ASSERT_NEAR(f0, f2, 1.0 / 500.0) << "cycle " << n;
    }
    ASSERT_TRUE(done.has_value());
    EXPECT_TRUE(done->has_value());
    c.cycle();
    EXPECT_EQ(c.rig.dev.model(1).position, 4000);
    EXPECT_EQ(c.rig.dev.model(2).position, -2000);
    EXPECT_EQ(c.dev2.model(1).position, 1000);
    EXPECT_EQ(c.rig.dev.od().get<std::int32_t>(0x687A, 0), -2000); // axis 2 at 687Ah
}

TEST(CoordinatedMotion, CoordinatedStopHaltsAllAxesOnThePath) {
    CoordRig c;
    ASSERT_TRUE(c.bring_up());
    std::vector<Axis*> axes{&c.rig.axis(1), &c.rig.axis(2), c.third.get()};
    CoordinatedMotion cm(axes, std::chrono::milliseconds(1));
    Eigen::VectorXd end(3), v(3), a(3), j(3);
    end << 100000, 50000, -100000;
    v << 20000, 20000, 20000;
    a << 100000, 100000, 100000;
    j << 0, 0, 0;
    std::optional<DriveVoid> move;
    ASSERT_TRUE(cm.start(end, v, a, j, ProfileShape::Trapezoidal, [&](DriveVoid r) { move = r; }));
    for (int i = 0; i < 300; ++i) {
        c.cycle(&cm);
    }
    std::optional<DriveVoid> stopped;
    cm.stop([&](DriveVoid r) { stopped = r; });
    ASSERT_TRUE(move.has_value());
    EXPECT_EQ(move->error().code, DriveErrc::Cancelled);
    std::int64_t prev = c.rig.dev.model(1).position;
    double max_step = 0;
    for (int i = 0; i < 2000 && !stopped; ++i) {
        c.cycle(&cm);
        const std::int64_t p = c.rig.dev.model(1).position;
        max_step = std::max(max_step, static_cast<double>(p - prev));
        prev = p;
    }
    ASSERT_TRUE(stopped.has_value());
    EXPECT_TRUE(stopped->has_value());
    c.cycle();
    const double f0 = static_cast<double>(c.rig.dev.model(1).position) / 100000.0;
    const double f1 = static_cast<double>(c.rig.dev.model(2).position) / 50000.0;
    const double f2 = static_cast<double>(c.dev2.model(1).position) / -100000.0;
    EXPECT_LT(f0, 1.0); // stopped before the end
    EXPECT_NEAR(f0, f1, 1e-4);
    EXPECT_NEAR(f0, f2, 1e-4);
    EXPECT_LE(max_step, 20000 * 0.001 + 1); // never faster than vmax per SYNC
    // Standing still now.
    const auto p = c.rig.dev.model(1).position;
    c.cycle(&cm);
    EXPECT_EQ(c.rig.dev.model(1).position, p);
}

TEST(CoordinatedMotion, RefusesAxesNotReady) {
    testing::Rig rig(generic_profile());
    rig.cycles(2);
    CoordinatedMotion cm({&rig.axis()}, std::chrono::milliseconds(1));
    Eigen::VectorXd e(1), v(1), a(1), j(1);
    e << 100;
    v << 1;
    a << 1;
    j << 1;
    auto r = cm.start(e, v, a, j, ProfileShape::Trapezoidal, nullptr);
    ASSERT_FALSE(r.has_value());
    EXPECT_EQ(r.error().message,
              "node 5 axis 1: coordinated move needs OPERATION ENABLED, the axis "
              "is in SWITCH ON DISABLED");
}

} // namespace
} // namespace codrive::drives
