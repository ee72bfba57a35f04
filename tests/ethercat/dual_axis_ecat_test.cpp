// SPDX-License-Identifier: Apache-2.0
// A dual-axis AKD2G on EtherCAT, as `codrive run` boots it from a bus file: one simulated slave
// (codrive-ecat-sim) on a veth pair, both axes bound to (slave 0, axis 1|2) with their objects at
// +800h, enabled, following CSP ramps in opposite directions, a fault on axis 2 reported on
// axis 2 with the drive's text, fault reset and the safe stop.
#include "veth_segment.hpp"

#include <codrive/controller/controller.hpp>
#include <codrive/drives/profile.hpp>

#include <fmt/format.h>

#include <csignal>
#include <cstdio>
#include <fstream>
#include <sched.h>
#include <sstream>

namespace codrive::testing {
namespace {

using namespace std::chrono_literals;
using drives::cia402::State;

class DualAxisAkd2gOverEthercat : public EcatVethTest {
protected:
    void SetUp() override {
        // SIGRTMIN injects an over-current on slave 0's axis 2 (2FF1h:02 in the simulator).
        start_for_controller({"--slave", "akd2g", "--fault-on-signal", "0:2"});
    }
    /// The bus file of docs/ethercat.md "Two axes of one AKD2G", exactly as printed there, with
    /// this test's interface in place of ecm0.
    std::string write_bus_file() {
        std::ifstream in(std::string(CODRIVE_SOURCE_DIR) + "/docs/ethercat.md");
        std::stringstream doc;
        doc << in.rdbuf();
        const std::string text = doc.str();
        const auto at = text.find("# dual-axis AKD2G");
        EXPECT_NE(at, std::string::npos) << "docs/ethercat.md lost its dual-axis bus file";
        const auto end = text.find("```", at);
        std::string yaml = at == std::string::npos ? std::string() : text.substr(at, end - at);
        const std::string iface = "interface: ecm0";
        if (const auto p = yaml.find(iface); p != std::string::npos) {
            yaml.replace(p, iface.size(), "interface: " + veth_->master_if());
        }
        path_ = write_temp_file("dual", yaml);
        return path_;
    }
    std::string path_;
};

TEST_F(DualAxisAkd2gOverEthercat, BothAxesEnableFollowCspAndAFaultOnAxis2IsReportedOnAxis2) {
    if (IsSkipped() || HasFatalFailure()) {
        return;
    }
    auto made = controller::Controller::from_file(write_bus_file());
    ASSERT_TRUE(made) << made.error().detail;
    auto& c = **made;
    std::string events;
    c.set_event_callback([&events](const std::string& t) { events += t + "\n"; });
    auto started = c.start();
    ASSERT_TRUE(started) << started.error().detail << events;
    // Both axes' maps assigned: 1600h/1601h (6 bytes each) out, 1A00h/1A01h (7 bytes each) in.
    EXPECT_NE(events.find("slave 0 (AKD2G): OP, 2 axis(es), 12 output / 14 input bytes"),
              std::string::npos)
        << events;
    drives::Axis* a1 = c.axis(0, 1, 0);
    drives::Axis* a2 = c.axis(0, 2, 0);
    ASSERT_NE(a1, nullptr);
    ASSERT_NE(a2, nullptr);
    EXPECT_EQ(a1->name(), "slave 0 axis 1 (gantry)");
    EXPECT_EQ(a2->name(), "slave 0 axis 2 (gantry)");
    ASSERT_TRUE(c.run_until([&] { return a1->has_statusword() && a2->has_statusword(); }, 3s))
        << events;

    std::optional<drives::DriveVoid> e1;
    std::optional<drives::DriveVoid> e2;
    a1->enable([&](drives::DriveVoid r) { e1 = r; });
    a2->enable([&](drives::DriveVoid r) { e2 = r; });
    ASSERT_TRUE(c.run_until([&] { return e1 && e2; }, 5s)) << events;
    ASSERT_TRUE(*e1) << e1->error().message << events;
    ASSERT_TRUE(*e2) << e2->error().message << events;
    EXPECT_EQ(a1->state(), State::OperationEnabled);
    EXPECT_EQ(a2->state(), State::OperationEnabled);

    // CSP: axis 1 ramps up, axis 2 down; each must follow its own set-points (a mix-up of the
    // two axes' objects would move both the same way).
    const std::int32_t s1 = a1->position_actual().value_or(0);
    const std::int32_t s2 = a2->position_actual().value_or(0);
    std::int32_t offset = 0;
    c.set_cycle_callback([&](const controller::CycleInfo&) {
        offset = std::min(offset + 40, 20000);
        a1->set_target_position(s1 + offset);
        a2->set_target_position(s2 - offset);
    });
    ASSERT_TRUE(c.run_until([&] { return offset == 20000; }, 10s)) << events;
    c.run_for(200ms);
    EXPECT_NEAR(a1->position_actual().value_or(0), s1 + 20000, 100) << events;
    EXPECT_NEAR(a2->position_actual().value_or(0), s2 - 20000, 100) << events;

    // A fault on axis 2: axis 2 goes to FAULT with the AKD2G's text for EMCY FF07h (F2002), the
    // text the CAN side gives from the same profile; axis 1 keeps running.
    ASSERT_EQ(::kill(sim_->pid(), SIGRTMIN), 0);
    ASSERT_TRUE(c.run_until([&] { return a2->state() == State::Fault; }, 3s)) << events;
    c.run_until([&] { return a2->last_error_code() != 0; }, 1s);
    EXPECT_EQ(a2->last_error_code(), 0xFF07);
    EXPECT_EQ(a2->diagnose(), "the drive is in FAULT: error code 0xFF07 (" +
                                  drives::akd2g_profile().fault_text(0xFF07) + ")");
    EXPECT_NE(drives::akd2g_profile().fault_text(0xFF07).find("F2002"), std::string::npos);
    // The sentence docs/ethercat.md shows.
    EXPECT_NE(events.find("slave 0 (AKD2G): EMCY 0xFF07 device specific (class 0xFF00): F2002 "
                          "Output over current"),
              std::string::npos)
        << events;
    EXPECT_EQ(a1->state(), State::OperationEnabled) << events;

    std::optional<drives::DriveVoid> reset;
    a2->fault_reset([&](drives::DriveVoid r) { reset = r; });
    ASSERT_TRUE(c.run_until([&] { return reset.has_value(); }, 3s)) << events;
    ASSERT_TRUE(*reset) << reset->error().message << events;
    EXPECT_NE(a2->state(), State::Fault);
    e2.reset();
    a2->enable([&](drives::DriveVoid r) { e2 = r; });
    ASSERT_TRUE(c.run_until([&] { return e2.has_value(); }, 5s)) << events;
    ASSERT_TRUE(*e2) << e2->error().message << events;
    EXPECT_EQ(a2->state(), State::OperationEnabled);

    // Safe stop: both axes end disabled.
    c.set_cycle_callback(nullptr);
    c.shutdown();
    EXPECT_EQ(a1->state(), State::SwitchOnDisabled) << events;
    EXPECT_EQ(a2->state(), State::SwitchOnDisabled) << events;
    const auto stats = c.stats();
    std::printf("dual-axis AKD2G over EtherCAT, 2 ms cycle: %s\n", stats.to_string().c_str());
    EXPECT_LE(stats.ecat_wire_errors(), stats.cycles / 50) << events;
}

} // namespace
} // namespace codrive::testing
