// SPDX-License-Identifier: Apache-2.0
// The controller end to end on an in-process bus with simulated drives (real time, short):
// boot-up with PDO configuration, enable, CSP motion every SYNC, safe shutdown.
#include <codrive/controller/controller.hpp>
#include <codrive/core/virtual_bus.hpp>
#include <codrive/master/master.hpp>
#include <codrive/sim/profile.hpp>
#include <codrive/sim/sim_device.hpp>

#include <gtest/gtest.h>

using namespace codrive;
using namespace codrive::controller;
using namespace std::chrono_literals;

namespace {

struct Rig {
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
        n.profile = "akd2g";
        n.heartbeat = 100ms;
        for (unsigned a = 1; a <= 2; ++a) {
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
        sc.profile = sim::find_profile("akd2g");
        EXPECT_NE(sc.profile, nullptr);
        drive = std::make_unique<sim::SimDevice>(sim_bus, sc);
        sim_bus.set_frame_handler([this](const Frame& f, TimePoint t) { drive->on_frame(f, t); });
        ControllerOptions o;
        o.buses = {&ctl_bus};
        std::vector<master::BusConfig> v{config()};
        auto c = Controller::create(std::move(v), o);
        EXPECT_TRUE(c) << (c ? "" : c.error());
        controller = std::move(*c);
        controller->set_event_callback([this](const std::string& t) { events.push_back(t); });
        controller->loop().add_timed(&net);
        controller->loop().add_timed(drive.get());
        drive->start(SteadyClock::now());
        controller->run_for(20ms); // the drive powers up before the controller starts
        auto r = controller->start();
        EXPECT_TRUE(r) << (r ? "" : r.error());
        return r.has_value();
    }
    ~Rig() {
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

TEST(Controller, BootsConfiguresPdosAndRunsCspOnBothAxes) {
    Rig rig;
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
