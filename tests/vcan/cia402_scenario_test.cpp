// SPDX-License-Identifier: Apache-2.0
// The CiA 402 scenario on vcan with real processes: this test is the master (controller) and
// `codrive-sim --node 1:akd2g --node 2:ds-bvs` the drives. The steps are the transport-neutral
// ones of <codrive/testing/cia402_scenario.hpp>; only the cycle driver and the fault injection
// (the simulator's 2FF0h control object over SDO) are CANopen-specific here.
#include <codrive/controller/controller.hpp>
#include <codrive/drives/canopen_transport.hpp>
#include <codrive/master/master.hpp>
#include <codrive/sdo/client.hpp>
#include <codrive/sim/sim_device.hpp>
#include <codrive/testing/cia402_scenario.hpp>
#include <codrive/testing/process.hpp>
#include <codrive/testing/vcan.hpp>

#include <gtest/gtest.h>

#include <cstdio>
#include <fstream>
#include <unistd.h>

using namespace codrive;
using namespace std::chrono_literals;
using codrive::testing::Process;
using codrive::testing::tool_path;
namespace sc = codrive::testing::cia402;
using drives::Axis;

namespace {

// SYNC every 4 ms: the User-Mode-Linux guest has one slow CPU. Explicit PDOs: the AKD2G's (the
// CSP layout per axis) add TPDO3 with both axes' following error 60F4h/68F4h; the DS-BVS's give
// PP (6064h) and PV (606Ch) their actual values.
constexpr const char* kBusFile = R"(bus:
  interface: vcan0
  sync_period_us: 4000
  master: {node_id: 127, heartbeat_ms: 100}
nodes:
  - id: 1
    name: gantry
    profile: akd2g
    heartbeat_ms: 100
    pdos:
      rpdo1: {transmission: 1, map: ["0x6040:00", "0x607A:00"]}
      rpdo2: {transmission: 1, map: ["0x6840:00", "0x687A:00"]}
      tpdo1: {transmission: 1, map: ["0x6041:00", "0x6064:00", "0x6061:00"]}
      tpdo2: {transmission: 1, map: ["0x6841:00", "0x6864:00", "0x6861:00"]}
      tpdo3: {transmission: 1, map: ["0x60F4:00", "0x68F4:00"]}
    axes:
      - {axis: 1, mode: csp}
      - {axis: 2, mode: csp}
  - id: 2
    name: spindle
    profile: ds-bvs
    heartbeat_ms: 100
    pdos:
      rpdo1: {transmission: 1, map: ["0x6040:00", "0x607A:00"]}
      rpdo2: {transmission: 1, map: ["0x60FF:00"]}
      tpdo1: {transmission: 1, map: ["0x6041:00", "0x6064:00", "0x6061:00"]}
      tpdo2: {transmission: 1, map: ["0x606C:00"]}
    axes:
      - {axis: 1, mode: pp}
)";

/// Following-error tolerance of the coordinated CSP path: the drive's following error (60F4h)
/// in increments (AKD2G: 65,536 per revolution, so 1,000 ≈ 0.015 rev ≈ 5.5°). The path runs at
/// up to ~130,000 increments/s (~520 per 4 ms cycle). See docs/axis.md for the measured figures.
constexpr double kPathTolerance = 1000;
constexpr std::uint64_t kPathCycles = 1000;

std::string write_bus_file() {
    char path[] = "/tmp/codrive-cia402-XXXXXX.yml";
    const int fd = mkstemps(path, 4);
    EXPECT_GE(fd, 0);
    if (fd >= 0) {
        close(fd);
    }
    std::ofstream(path) << kBusFile;
    return path;
}

struct Rig {
    std::unique_ptr<controller::Controller> c;
    std::vector<std::string> events;
    sc::CycleDriver driver;

    explicit Rig(const std::string& bus_file) {
        auto created = controller::Controller::from_file(bus_file);
        EXPECT_TRUE(created) << (created ? "" : created.error().detail);
        if (!created) {
            return;
        }
        c = std::move(*created);
        c->set_event_callback([this](const std::string& t) {
            events.push_back(t);
            if (t.find("PDO") == std::string::npos) {
                std::printf("  event: %s\n", t.c_str());
            }
        });
        driver.period = microseconds(c->config().sync_period_us);
        driver.run_until = [this](const std::function<bool()>& pred, Duration timeout) {
            return c->run_until(pred, timeout);
        };
        driver.set_cycle_hook = [this](std::function<void(bool)> hook) {
            if (!hook) {
                c->set_cycle_callback(nullptr);
                return;
            }
            // A cycle is disturbed when it started more than two periods after the previous one
            // (the guest's scheduler stalled the controller).
            const Duration period = driver.period;
            c->set_cycle_callback([h = std::move(hook), period,
                                   last = TimePoint{}](const controller::CycleInfo& i) mutable {
                const bool on_time = last == TimePoint{} || i.actual - last <= 2 * period;
                last = i.actual;
                h(on_time);
            });
        };
    }

    /// The simulator's fault injection: 2FF0h + (axis − 1), sub-index `sub` (sim_device.hpp).
    bool control(NodeId node, unsigned axis, std::uint8_t sub, std::uint8_t value) {
        std::optional<std::string> error;
        bool done = false;
        c->master().sdo().client(node).write<std::uint8_t>(
            static_cast<std::uint16_t>(sim::kControlObject + axis - 1), sub, value,
            [&](sdo::SdoResult<void> r) {
                done = true;
                if (!r) {
                    error = r.error().to_string();
                }
            });
        c->run_until([&] { return done; }, 2s);
        EXPECT_TRUE(done && !error) << (error ? *error : "SDO write timed out");
        return done && !error;
    }

    bool saw_event(const std::string& a, const std::string& b) const {
        for (const auto& e : events) {
            if (e.find(a) != std::string::npos && e.find(b) != std::string::npos) {
                return true;
            }
        }
        return false;
    }
};

} // namespace

TEST(VcanCia402, Akd2gBothAxesAndDsBvsRunTheWholeScenario) {
    CODRIVE_REQUIRE_VCAN("vcan0");
    Process sim(
        {tool_path("codrive-sim"), "-i", "vcan0", "--node", "1:akd2g", "--node", "2:ds-bvs"});
    ASSERT_TRUE(sim.wait_for_output("node 2", 10s)) << sim.output();
    const std::string bus_file = write_bus_file();
    Rig rig(bus_file);
    ASSERT_TRUE(rig.c);
    controller::Controller& c = *rig.c;
    const sc::CycleDriver& d = rig.driver;

    // Boot-up and PDO configuration: every node boots, its PDO step succeeds and the axes get
    // their statusword and position by PDO.
    auto started = c.start();
    ASSERT_TRUE(started) << started.error().detail;
    ASSERT_EQ(c.boot_reports().size(), 2U);
    for (const auto& r : c.boot_reports()) {
        EXPECT_TRUE(r.ok) << r.to_string();
        bool pdo_step = false;
        for (const auto& s : r.steps) {
            pdo_step = pdo_step || (s.name == "PDO configuration" && s.ok);
        }
        EXPECT_TRUE(pdo_step) << r.to_string();
        std::printf("%s", r.to_string().c_str());
    }
    Axis* x = c.axis(1, 1);
    Axis* y = c.axis(1, 2);
    Axis* s = c.axis(2, 1);
    ASSERT_TRUE(x != nullptr && y != nullptr && s != nullptr);
    ASSERT_TRUE(c.run_until(
        [&] {
            for (Axis* a : {x, y, s}) {
                if (!a->has_statusword() || !a->position_actual()) {
                    return false;
                }
            }
            return true;
        },
        3s))
        << "statusword and position actual value by TPDO";
    EXPECT_EQ(y->index(0x6041), 0x6841) << "AKD2G axis 2 objects at +0x800";

    // Enable.
    for (Axis* a : {x, y, s}) {
        ASSERT_TRUE(sc::enable(d, *a));
        EXPECT_EQ(a->state(), drives::cia402::State::OperationEnabled);
    }

    // Homing: AKD2G axis 1 searches the home switch (method 24, position := offset), axis 2
    // takes the current position (35); DS-BVS searches its home switch (23, position := 0).
    drives::HomingParams hx;
    hx.method = 24;
    hx.speed_switch = 327680;
    hx.speed_zero = 32768;
    hx.acceleration = 6553600;
    hx.offset = 1000;
    ASSERT_TRUE(sc::home(d, *x, hx, 1000, 700));
    drives::HomingParams hy;
    hy.method = 35;
    hy.offset = -5000;
    ASSERT_TRUE(sc::home(d, *y, hy, -5000, 700));
    drives::HomingParams hs;
    hs.method = 23;
    hs.speed_switch = 300; // rpm
    hs.speed_zero = 30;
    hs.acceleration = 10000;
    ASSERT_TRUE(sc::home(d, *s, hs, 0, 5));

    // PP moves with target reached: both AKD2G axes, and the DS-BVS over 20,000 increments
    // (40 revolutions at 500 increments per revolution).
    ASSERT_TRUE(sc::pp_move(d, *x, 1000 + 327680, 700));
    ASSERT_TRUE(sc::pp_move(d, *y, -5000 - 196608, 700));
    ASSERT_TRUE(sc::pp_move(d, *s, 20000, 5));
    std::printf("PP: x %d, y %d, ds-bvs %d\n", x->position_actual().value_or(0),
                y->position_actual().value_or(0), s->position_actual().value_or(0));

    // PV on the DS-BVS: 600 rpm, verified on 606Ch, then stop.
    sc::PvFigures pv;
    ASSERT_TRUE(sc::pv_run_and_stop(d, *s, 600, 30, &pv));
    std::printf("PV: 606Ch %d rpm at 600 rpm target, %d rpm after the stop\n", pv.at_speed,
                pv.after_stop);

    // 1,000 CSP cycles on a coordinated two-axis path (both AKD2G axes).
    sc::PathFigures path;
    const auto ok =
        sc::csp_path(d, {x, y}, {-200000.0, 150000.0}, kPathCycles, kPathTolerance, &path);
    for (std::size_t i = 0; i < path.max_error.size(); ++i) {
        std::printf("CSP axis %zu: max following error (60F4h) %.0f at cycle %llu, %llu cycles "
                    "over %.0f; end-to-end max %.0f\n",
                    i + 1, path.max_error[i], static_cast<unsigned long long>(path.worst_cycle[i]),
                    static_cast<unsigned long long>(path.cycles_over[i]), kPathTolerance,
                    path.max_path_error[i]);
        std::printf("CSP axis %zu: including the %llu cycles after a late cycle: max %.0f\n", i + 1,
                    static_cast<unsigned long long>(path.disturbed), path.max_error_all[i]);
    }
    ASSERT_TRUE(ok);
    std::printf("CSP path: %llu cycles, max following error x %.0f, y %.0f increments "
                "(tolerance %.0f)\n",
                static_cast<unsigned long long>(path.cycles), path.max_error[0], path.max_error[1],
                kPathTolerance);
    EXPECT_GE(path.cycles, kPathCycles);

    // Quick stop while moving: AKD2G axis 1 (605Ah = 2: ramp, then SWITCH ON DISABLED) and the
    // DS-BVS (605Ah = 6: ramp, stay in QUICK STOP ACTIVE).
    {
        drives::CanopenTransport tx(c.master().sdo().client(1));
        std::int16_t option = -1;
        ASSERT_TRUE(sc::quick_stop_while_moving(d, *x, tx, -327680, 100, &option));
        EXPECT_EQ(option, 2);
        drives::CanopenTransport ts(c.master().sdo().client(2));
        ASSERT_TRUE(sc::quick_stop_while_moving(d, *s, ts, -600, 5, &option));
        EXPECT_EQ(option, 6);
    }

    // Injected faults, EMCY decoded with the vendor text, fault reset back to OPERATION ENABLED:
    // over-current on AKD2G axis 2 (F2002) and on the DS-BVS.
    const auto over_current = [&rig](NodeId node, unsigned axis) {
        return [&rig, node, axis](bool on) {
            return rig.control(node, axis, sim::kControlOverCurrent, on ? 1 : 0);
        };
    };
    ASSERT_TRUE(
        sc::fault_and_recover(d, *y, over_current(1, 2), 0xFF07, "F2002 Output over current"));
    EXPECT_TRUE(rig.saw_event("EMCY", "F2002")) << "the master's EMCY decoder used the AKD2G text";
    ASSERT_TRUE(sc::fault_and_recover(d, *s, over_current(2, 1), 0x2310, "Over current"));
    EXPECT_TRUE(rig.saw_event("0x2310", "Over current")) << "DS-BVS text in the EMCY event";
    for (Axis* a : {x, y, s}) {
        EXPECT_EQ(a->state(), drives::cia402::State::OperationEnabled) << a->name();
    }

    c.shutdown();
    std::remove(bus_file.c_str());
}
