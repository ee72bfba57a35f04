// SPDX-License-Identifier: Apache-2.0
// The Controller in both threading modes against a simulated AKD2G on vcan: enable and a CSP
// ramp driven from the cycle callback, no overrun or missing TPDO once moving, no allocation on
// the dedicated cyclic thread, stop within 1 s, and no descriptor or thread left behind.
#include <codrive/controller/controller.hpp>
#include <codrive/testing/enable_then_ramp.hpp>
#include <codrive/testing/process.hpp>
#include <codrive/testing/soak.hpp>
#include <codrive/testing/stop_latency.hpp>
#include <codrive/testing/vcan.hpp>

// One program-wide counting operator new (included once per program): the dedicated cyclic
// thread's allocations are counted from its cycle callback.
#include <codrive/testing/counting_new.hpp>

#include <gtest/gtest.h>

#include <cstdio>
#include <pthread.h>
#include <sched.h>

using namespace std::chrono_literals;
using namespace codrive;
using codrive::testing::Process;
using codrive::testing::tool_path;

namespace {

int open_fds() {
    return codrive::testing::count_dir_entries("/proc/self/fd") - 1; // minus opendir()'s own
}
int threads() {
    return codrive::testing::count_threads();
}

master::BusConfig akd2g_bus() {
    master::BusConfig c;
    c.file = "controller_threads_test";
    c.iface = "vcan0";
    c.sync_period_us = 4000; // the User-Mode-Linux guest has one slow CPU
    master::NodeEntry n;
    n.id = 1;
    n.name = "gantry";
    n.profile = "akd2g";
    n.heartbeat = 100ms;
    master::AxisConfig ax;
    ax.axis = 1;
    ax.mode = 8; // CSP
    n.axes.push_back(ax);
    c.nodes.push_back(n);
    return c;
}

/// Enable + 40000-increment CSP ramp, all started from the cycle callback (the thread that owns
/// the axes in both modes); the test thread only watches atomics.
void enable_move_stop(controller::Threading mode, const char* label) {
    Process sim{{tool_path("codrive-sim"), "-i", "vcan0", "--node", "1:akd2g"}};
    ASSERT_TRUE(sim.wait_for_output("ready", 10s)) << sim.output();
    const int fds_before = open_fds();
    codrive::testing::start_runtime_threads(); // a sanitizer's own thread is not the controller's
    const int threads_before = threads();
    {
        controller::ControllerOptions o;
        o.threading = mode;
        o.realtime.fifo = true; // a warning (not an error) where it is not permitted
        std::vector<master::BusConfig> v{akd2g_bus()};
        auto created = controller::Controller::create(std::move(v), o);
        ASSERT_TRUE(created) << created.error().detail;
        auto& c = **created;
        std::string events;
        c.set_event_callback([&](const std::string& t) { events += t + "\n"; });
        auto started = c.start();
        ASSERT_TRUE(started) << started.error().detail << events;
        if (mode == controller::Threading::DedicatedCyclic) {
            EXPECT_EQ(threads(), threads_before + 1) << "one cyclic thread";
        }
        drives::Axis* axis = c.axis(1, 1);
        ASSERT_NE(axis, nullptr);
        codrive::testing::EnableThenRamp ramp(*axis, 200, 40000);
        // Dedicated mode: the cyclic thread's allocations over 500 cycles once the axis moves.
        codrive::testing::CycleAllocations allocations(10, 500);
        const bool dedicated = mode == controller::Threading::DedicatedCyclic;
        c.set_cycle_callback([&](const controller::CycleInfo&) {
            ramp.on_cycle();
            if (dedicated) {
                allocations.on_cycle(ramp.phase() == ramp.Moving || ramp.phase() == ramp.Done);
            }
        });
        ASSERT_TRUE(c.run_until(
            [&] { return ramp.phase() != ramp.Waiting && ramp.phase() != ramp.Enabling; }, 30s))
            << "phase " << ramp.phase() << "\n"
            << events;
        const auto moving = c.stats(); // steady state from here: enabled, following the ramp
        ASSERT_TRUE(c.run_until([&] { return ramp.finished(); }, 30s))
            << "phase " << ramp.phase() << "\n"
            << events;
        ASSERT_TRUE(ramp.done()) << ramp.failure() << events;
        c.run_for(300ms);
        if (dedicated) {
            ASSERT_TRUE(c.run_until([&] { return allocations.done(); }, 10s));
            std::printf("%s: %llu allocations on the cyclic thread in %llu cycles\n", label,
                        static_cast<unsigned long long>(allocations.count()),
                        static_cast<unsigned long long>(allocations.cycles()));
            EXPECT_EQ(allocations.count(), 0U);
        }
        EXPECT_NEAR(ramp.position(), ramp.start() + 40000, 1000) << events;
        const auto steady = c.stats();
        if (dedicated) {
            // The guest has one CPU and shares the host with CI's parallel fuzz stage, and its
            // timer runs coarse (docs/vcan.md): there a TPDO often arrives after the next SYNC
            // (counted "missing" by then, though it is received) and a SYNC slot is skipped now
            // and then. The exact claim, 0 overruns and 0 missing TPDOs, is proven where time is
            // not starved: tests/integration (in-process bus) and tests/ethercat (veth). Here the
            // cyclic thread must keep at least three of every four slots and receive (late or not)
            // at least three TPDOs of every four cycles.
            const auto cycles = steady.cycles - moving.cycles;
            EXPECT_LE((steady.overruns - moving.overruns) * 4, cycles) << steady.to_string();
            EXPECT_GE((steady.tpdos_received - moving.tpdos_received) * 4, cycles * 3)
                << steady.to_string();
        }

        const double stop_ms = codrive::testing::run_and_measure_stop(c);
        const auto stats = c.stats();
        std::printf("%s: SYNC 4 ms: %s; stop request to run() returning %.1f ms\n", label,
                    stats.to_string().c_str(), stop_ms);
        EXPECT_LT(stop_ms, 1000.0);
        EXPECT_EQ(axis->state(), drives::cia402::State::SwitchOnDisabled) << events;
        EXPECT_GT(stats.tpdos_received, 100U);
        if (stats.sdo_failed != 0) {
            std::printf("note: %llu SDO transfer(s) failed; events:\n%s",
                        static_cast<unsigned long long>(stats.sdo_failed), events.c_str());
        }
    }
    EXPECT_EQ(open_fds(), fds_before);
    EXPECT_EQ(codrive::testing::threads_after_joins(threads_before), threads_before);
    // Threading::Single ran SCHED_FIFO on this (the caller's) thread: the controller gives the
    // thread back as it found it, or every later process on this CPU would starve.
    int policy = -1;
    sched_param sp{};
    ASSERT_EQ(pthread_getschedparam(pthread_self(), &policy, &sp), 0);
    EXPECT_EQ(policy, SCHED_OTHER)
        << label << ": the caller's thread was left at policy " << policy;
}

} // namespace

TEST(VcanControllerThreading, SingleThreadModeEnablesMovesAndStopsCleanly) {
    CODRIVE_REQUIRE_VCAN("vcan0");
    enable_move_stop(controller::Threading::Single, "single-thread mode");
}

TEST(VcanControllerThreading, DedicatedCyclicThreadEnablesMovesAndStopsCleanly) {
    CODRIVE_REQUIRE_VCAN("vcan0");
    enable_move_stop(controller::Threading::DedicatedCyclic, "dedicated cyclic thread");
}
