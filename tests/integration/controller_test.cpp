// SPDX-License-Identifier: Apache-2.0
// The controller end to end on an in-process bus with simulated drives (real time and a stopper
// thread, so integration, not unit): boot-up with PDO configuration, enable, CSP motion every
// SYNC, safe shutdown, resources, start-up refusals.
#include <codrive/controller/controller.hpp>
#include <codrive/core/virtual_bus.hpp>
#include <codrive/master/master.hpp>
#include <codrive/sim/profile.hpp>
#include <codrive/sim/sim_device.hpp>
#include <codrive/testing/soak.hpp>

#include <gtest/gtest.h>

#include <atomic>
#include <thread>

using namespace codrive;
using namespace codrive::controller;
using namespace std::chrono_literals;

namespace {

struct ControllerRig {
    std::string profile = "akd2g";
    unsigned axes = 2;
    VirtualNetwork net{RealClock::instance()};
    VirtualBus& ctl_bus = net.endpoint("controller");
    VirtualBus& sim_bus = net.endpoint("akd2g");
    std::unique_ptr<sim::SimDevice> drive;
    std::unique_ptr<Controller> controller;
    std::vector<std::string> events;

    master::BusConfig config() {
        master::BusConfig c;
        c.file = "test";
        c.iface = "virtual";
        c.sync_period_us = 2000;
        master::NodeEntry n;
        n.id = 1;
        n.name = "gantry";
        n.profile = profile;
        n.heartbeat = 100ms;
        for (unsigned a = 1; a <= axes; ++a) {
            master::AxisConfig ax;
            ax.axis = a;
            ax.mode = 8; // CSP
            n.axes.push_back(ax);
        }
        c.nodes.push_back(n);
        return c;
    }

    bool start() {
        sim::SimDeviceConfig sc;
        sc.node = 1;
        sc.profile = sim::find_profile(profile);
        sc.axes = axes;
        EXPECT_NE(sc.profile, nullptr);
        drive = std::make_unique<sim::SimDevice>(sim_bus, sc);
        sim_bus.set_frame_handler([this](const Frame& f, TimePoint t) { drive->on_frame(f, t); });
        ControllerOptions o;
        o.buses = {&ctl_bus};
        std::vector<master::BusConfig> v{config()};
        auto c = Controller::create(std::move(v), o);
        EXPECT_TRUE(c) << (c ? "" : c.error().detail);
        controller = std::move(*c);
        controller->set_event_callback([this](const std::string& t) { events.push_back(t); });
        controller->loop().add_timed(&net);
        controller->loop().add_timed(drive.get());
        drive->start(SteadyClock::now());
        controller->run_for(20ms); // the drive powers up before the controller starts
        auto r = controller->start();
        EXPECT_TRUE(r) << (r ? "" : r.error().detail);
        return r.has_value();
    }
    ~ControllerRig() {
        if (controller) {
            controller->shutdown();
            controller->loop().remove_timed(&net);
            controller->loop().remove_timed(drive.get());
        }
    }
    std::string all_events() const {
        std::string s;
        for (const auto& e : events) {
            s += e + "\n";
        }
        return s;
    }
};

} // namespace

// The DS-BVS in CSP: its profile's PDO layout is configured at boot (its PDO maps are empty by
// default, ds-bvs.md §4), the axis enables from SWITCH ON DISABLED (statusword 0x0240: bit 4
// "voltage enabled" is 0 there, which is not a missing main voltage) and follows a ramp.
TEST(Controller, BootsADsBvsInCspEnablesItAndFollowsARamp) {
    ControllerRig rig;
    rig.profile = "ds-bvs";
    rig.axes = 1;
    ASSERT_TRUE(rig.start()) << rig.all_events();
    ASSERT_EQ(rig.controller->boot_reports().size(), 1U);
    ASSERT_TRUE(rig.controller->boot_reports()[0].ok)
        << rig.controller->boot_reports()[0].to_string();
    auto* a = rig.controller->axis(1, 1);
    ASSERT_NE(a, nullptr);
    ASSERT_TRUE(rig.controller->run_until([&] { return a->has_statusword(); }, 2s))
        << rig.all_events();
    std::optional<drives::DriveVoid> enabled;
    a->enable([&](drives::DriveVoid r) { enabled = r; });
    ASSERT_TRUE(rig.controller->run_until([&] { return enabled.has_value(); }, 3s))
        << rig.all_events();
    ASSERT_TRUE(*enabled) << enabled->error().message << "\n" << rig.all_events();
    const std::int32_t start = a->position_actual().value_or(0);
    std::int32_t step = 0;
    rig.controller->set_cycle_callback([&](const CycleInfo&) {
        step = std::min(step + 1, 200);
        a->set_target_position(start + step * 100);
    });
    rig.controller->run_until([&] { return step >= 200; }, 5s);
    rig.controller->run_for(100ms);
    rig.controller->set_cycle_callback(nullptr);
    EXPECT_NEAR(a->position_actual().value_or(0), start + 20000, 200) << rig.all_events();
    EXPECT_EQ(a->state(), drives::cia402::State::OperationEnabled);
}

TEST(Controller, BootsConfiguresPdosAndRunsCspOnBothAxes) {
    ControllerRig rig;
    ASSERT_TRUE(rig.start()) << rig.all_events();
    ASSERT_EQ(rig.controller->boot_reports().size(), 1U);
    EXPECT_TRUE(rig.controller->boot_reports()[0].ok)
        << rig.controller->boot_reports()[0].to_string();
    auto* a1 = rig.controller->axis(1, 1);
    auto* a2 = rig.controller->axis(1, 2);
    ASSERT_TRUE(a1 && a2);
    // The first TPDOs tell the axes their state.
    ASSERT_TRUE(
        rig.controller->run_until([&] { return a1->has_statusword() && a2->has_statusword(); }, 2s))
        << rig.all_events();
    int enabled = 0;
    std::string failure;
    for (auto* a : {a1, a2}) {
        a->enable([&](drives::DriveVoid r) {
            if (r) {
                ++enabled;
            } else {
                failure += r.error().message + "\n";
            }
        });
    }
    ASSERT_TRUE(rig.controller->run_until([&] { return enabled == 2 || !failure.empty(); }, 3s))
        << rig.all_events();
    ASSERT_EQ(enabled, 2) << failure << rig.all_events();
    EXPECT_EQ(a1->state(), drives::cia402::State::OperationEnabled);

    // A ramp on both axes, one set-point per SYNC.
    const std::int32_t start1 = a1->position_actual().value_or(0);
    const std::int32_t start2 = a2->position_actual().value_or(0);
    std::int32_t step = 0;
    rig.controller->set_cycle_callback([&](const CycleInfo&) {
        if (step < 200) {
            ++step;
        }
        a1->set_target_position(start1 + step * 500);
        a2->set_target_position(start2 - step * 250);
    });
    rig.controller->run_until([&] { return step >= 200; }, 5s);
    rig.controller->run_for(100ms);
    ASSERT_EQ(step, 200);
    ASSERT_TRUE(a1->position_actual());
    EXPECT_NEAR(*a1->position_actual(), start1 + 100000, 2000) << rig.all_events();
    EXPECT_NEAR(*a2->position_actual(), start2 - 50000, 2000);
    const auto stats = rig.controller->stats();
    EXPECT_GT(stats.cycles, 200U);
    EXPECT_GT(stats.tpdos_received, 200U);
    EXPECT_EQ(stats.tpdos_missing, 0U) << rig.all_events();

    rig.controller->set_cycle_callback(nullptr);
    rig.controller->shutdown();
    EXPECT_EQ(a1->state(), drives::cia402::State::SwitchOnDisabled) << rig.all_events();
    EXPECT_EQ(a2->state(), drives::cia402::State::SwitchOnDisabled);
    rig.controller->run_for(20ms);
    EXPECT_EQ(rig.drive->nmt_state(), nmt::NmtState::PreOperational);
}

namespace {

int open_fds() {
    return codrive::testing::count_dir_entries("/proc/self/fd") - 1; // minus opendir()'s own
}
int threads() {
    return codrive::testing::count_threads();
}

} // namespace

TEST(ControllerResources, DestroyedControllerLeavesNoFileDescriptorsOrThreads) {
    const int fds_before = open_fds();
    codrive::testing::start_runtime_threads(); // a sanitizer's own thread is not the controller's
    const int threads_before = threads();
    {
        ControllerRig rig;
        ASSERT_TRUE(rig.start()) << rig.all_events();
        rig.controller->run_for(50ms);
        EXPECT_GT(open_fds(), fds_before); // the loop's epoll and timer descriptors
    }
    EXPECT_EQ(open_fds(), fds_before);
    EXPECT_EQ(codrive::testing::threads_after_joins(threads_before), threads_before);
}

TEST(ControllerResources, StopRequestEndsRunWithSafeShutdownWithinOneSecond) {
    ControllerRig rig;
    ASSERT_TRUE(rig.start()) << rig.all_events();
    auto* a1 = rig.controller->axis(1, 1);
    ASSERT_NE(a1, nullptr);
    ASSERT_TRUE(rig.controller->run_until([&] { return a1->has_statusword(); }, 2s));
    bool enabled = false;
    a1->enable([&](drives::DriveVoid r) { enabled = r.has_value(); });
    ASSERT_TRUE(rig.controller->run_until([&] { return enabled; }, 3s)) << rig.all_events();
    std::atomic<std::int64_t> requested_ns{0};
    std::thread stopper([&] {
        std::this_thread::sleep_for(100ms);
        requested_ns = SteadyClock::now().time_since_epoch().count();
        rig.controller->request_stop();
    });
    rig.controller->run(); // returns after the safe shutdown
    const auto returned = SteadyClock::now().time_since_epoch().count();
    stopper.join();
    const double ms = static_cast<double>(returned - requested_ns.load()) / 1e6;
    std::printf("stop request to run() returning (single-thread mode): %.1f ms\n", ms);
    EXPECT_LT(ms, 1000.0);
    EXPECT_EQ(a1->state(), drives::cia402::State::SwitchOnDisabled) << rig.all_events();
}

TEST(ControllerThreading, DedicatedCyclicModeRefusesInProcessBusesWithAReason) {
    ControllerOptions o;
    VirtualNetwork net{RealClock::instance()};
    o.buses = {&net.endpoint("controller")};
    o.threading = Threading::DedicatedCyclic;
    master::BusConfig c;
    c.iface = "virtual";
    std::vector<master::BusConfig> v{c};
    auto ctl = Controller::create(std::move(v), o);
    ASSERT_TRUE(ctl);
    auto r = (*ctl)->start();
    ASSERT_FALSE(r);
    EXPECT_EQ(r.error().code, ControllerErrc::InvalidConfiguration);
    EXPECT_NE(r.error().detail.find("DedicatedCyclic needs SocketCAN interfaces"),
              std::string::npos)
        << r.error().detail;
}

TEST(ControllerThreading, MissingEthercatInterfaceIsReportedByName) {
    ControllerOptions o;
    o.threading = Threading::DedicatedCyclic;
    EcatSegmentConfig seg;
    seg.iface = "nosuch0";
    auto ctl = Controller::create({}, {seg}, o);
    ASSERT_TRUE(ctl);
    auto r = (*ctl)->start();
    ASSERT_FALSE(r);
    EXPECT_EQ(r.error().code, ControllerErrc::SegmentFailed);
    EXPECT_NE(r.error().detail.find("nosuch0"), std::string::npos) << r.error().detail;
}

// A node that never answers: start() fails with NodeBootFailed, so a program can tell it from a
// bus it could not open; the sentence is the one it always was ("boot-up failed:" and each
// failed node's boot step), and a second start() is refused with AlreadyStarted.
TEST(ControllerErrors, ANodeThatDoesNotBootIsNodeBootFailedAndStartRunsOnce) {
    VirtualNetwork net{RealClock::instance()};
    ControllerOptions o;
    o.buses = {&net.endpoint("controller")};
    master::BusConfig c;
    c.file = "test";
    c.iface = "virtual";
    master::NodeEntry n;
    n.id = 5;
    n.name = "absent";
    n.profile = "akd2g";
    n.sdo_timeout = 100ms;
    c.nodes.push_back(n);
    std::vector<master::BusConfig> v{c};
    auto ctl = Controller::create(std::move(v), o);
    ASSERT_TRUE(ctl) << ctl.error().detail;
    (*ctl)->loop().add_timed(&net);
    auto r = (*ctl)->start();
    ASSERT_FALSE(r);
    EXPECT_EQ(r.error().code, ControllerErrc::NodeBootFailed) << r.error().detail;
    EXPECT_FALSE(r.error().cause);
    ASSERT_EQ((*ctl)->boot_reports().size(), 1U);
    EXPECT_FALSE((*ctl)->boot_reports()[0].ok);
    EXPECT_EQ(r.error().detail, "boot-up failed:\n  " + (*ctl)->boot_reports()[0].error());
    EXPECT_NE(r.error().detail.find("node 5"), std::string::npos) << r.error().detail;

    auto again = (*ctl)->start();
    ASSERT_FALSE(again);
    EXPECT_EQ(again.error().code, ControllerErrc::AlreadyStarted);
    EXPECT_EQ(again.error().detail,
              "start() was already called on this controller; a controller starts once");
    (*ctl)->loop().remove_timed(&net);
}

// start() on a running controller is refused and leaves it running: the drives keep their
// SYNC, PDOs and axes.
TEST(ControllerErrors, StartingARunningControllerIsAlreadyStartedAndKeepsItRunning) {
    ControllerRig rig;
    rig.axes = 1;
    ASSERT_TRUE(rig.start()) << rig.all_events();
    const auto cycles = rig.controller->stats().cycles;
    auto again = rig.controller->start();
    ASSERT_FALSE(again);
    EXPECT_EQ(again.error().code, ControllerErrc::AlreadyStarted);
    EXPECT_TRUE(rig.controller->running());
    rig.controller->run_for(50ms);
    EXPECT_GT(rig.controller->stats().cycles, cycles);
    EXPECT_TRUE(rig.controller->boot_reports()[0].ok);
}
