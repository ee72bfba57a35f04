// SPDX-License-Identifier: Apache-2.0
// Master node supervision on the virtual bus: boot-up, identity checks, heartbeat loss,
// automatic recovery of a rebooted node, EMCY, and the network scan.
#include "test_device.hpp"

#include <codrive/master/master.hpp>
#include <codrive/master/network_scan.hpp>

#include <gtest/gtest.h>

using namespace codrive;
using namespace codrive::master;
using namespace std::chrono_literals;

namespace {

struct Bench {
    FakeClock clock;
    VirtualNetwork net{clock, 100us};
    VirtualBus& master_bus = net.endpoint("master");
    VirtualBus& dev_bus = net.endpoint("device");
    codrive::testing::TestDevice device{dev_bus, 3};
    Master master{master_bus, clock};
    std::vector<MasterEvent> events;

    Bench() {
        master.set_event_handler([this](const MasterEvent& e) { events.push_back(e); });
        net.set_recording(true);
    }
    void run_for(Duration d) {
        std::vector<ITimed*> timed = device.timed();
        timed.push_back(&master);
        net.run_until(clock, clock.now() + d, timed);
    }
    NodeConfig config() {
        NodeConfig c;
        c.id = 3;
        c.name = "drive-x";
        c.identity.device_type = 0x00020192;
        c.identity.vendor_id = 0x6A;
        c.identity.product_code = 0x1234;
        c.writes.push_back(ObjectWrite::of<std::int8_t>(0x6060, 0, 8, "modes of operation = CSP"));
        c.heartbeat_producer = 100ms;
        return c;
    }
    /// The device boots and its boot-up message crosses the bus before the master acts.
    void power_on() {
        device.boot(clock.now());
        run_for(1ms);
    }
    bool has_event(MasterEventKind k) const {
        for (const auto& e : events) {
            if (e.kind == k) {
                return true;
            }
        }
        return false;
    }
    std::string event_text(MasterEventKind k) const {
        for (const auto& e : events) {
            if (e.kind == k) {
                return e.text;
            }
        }
        return {};
    }
};

} // namespace

TEST(Master, BootChecksIdentityConfiguresAndStartsTheNode) {
    Bench b;
    b.power_on();
    b.master.add_node(b.config());
    std::optional<BootReport> report;
    b.master.boot(3, [&](const BootReport& r) { report = r; });
    b.run_for(200ms);
    ASSERT_TRUE(report);
    EXPECT_TRUE(report->ok) << report->to_string();
    EXPECT_EQ(b.device.state(), nmt::NmtState::Operational);
    EXPECT_EQ(b.device.od().get<std::int8_t>(0x6060, 0), 8);
    EXPECT_EQ(b.device.od().get<std::uint16_t>(0x1017, 0), 100);
    // Steps: NMT enter pre-operational, 1000h, 1018h:01, :02, pre-operational check, write
    // 6060h, 1017h, NMT start.
    ASSERT_EQ(report->steps.size(), 8U) << report->to_string();
    EXPECT_EQ(report->steps[0].name, "NMT enter pre-operational");
    EXPECT_EQ(report->steps[1].detail, "0x00020192");
    EXPECT_EQ(report->steps.back().name, "NMT start");
    const std::string text = report->to_string();
    EXPECT_NE(text.find("node 3 (drive-x): boot-up OK"), std::string::npos) << text;
    EXPECT_NE(text.find("modes of operation = CSP"), std::string::npos) << text;
    EXPECT_TRUE(b.has_event(MasterEventKind::BootCompleted));
    EXPECT_EQ(b.master.node(3)->state(), nmt::NmtState::Operational);
}

TEST(Master, IdentityMismatchNamesExpectedAndActual) {
    Bench b;
    b.power_on();
    auto c = b.config();
    c.identity.vendor_id = 0x9A;
    b.master.add_node(c);
    std::optional<BootReport> report;
    b.master.boot(3, [&](const BootReport& r) { report = r; });
    b.run_for(200ms);
    ASSERT_TRUE(report);
    EXPECT_FALSE(report->ok);
    EXPECT_EQ(report->error(), "node 3: identity mismatch: vendor-ID (1018h:01) expected "
                               "0x0000009A, actual 0x0000006A");
    EXPECT_EQ(b.device.state(), nmt::NmtState::PreOperational) << "a wrong device is not started";
    EXPECT_EQ(b.device.writes_to_6060, 0) << "nor configured";
    EXPECT_EQ(b.event_text(MasterEventKind::BootFailed), report->error());
}

TEST(Master, MissingNodeIsReportedAfterRetries) {
    Bench b;
    auto c = b.config();
    c.id = 9;
    b.master.add_node(c);
    std::optional<BootReport> report;
    b.master.boot(9, [&](const BootReport& r) { report = r; });
    b.run_for(5s);
    ASSERT_TRUE(report);
    EXPECT_FALSE(report->ok);
    EXPECT_NE(report->error().find("node 9: does not answer"), std::string::npos)
        << report->error();
    EXPECT_NE(report->error().find("3 attempts"), std::string::npos) << report->error();
}

TEST(Master, WriteAbortIsExplainedInTheReport) {
    Bench b;
    b.power_on();
    auto c = b.config();
    c.writes.push_back(ObjectWrite::of<std::uint32_t>(0x1000, 0, 1, "device type"));
    b.master.add_node(c);
    std::optional<BootReport> report;
    b.master.boot(3, [&](const BootReport& r) { report = r; });
    b.run_for(500ms);
    ASSERT_TRUE(report);
    EXPECT_FALSE(report->ok);
    EXPECT_NE(report->error().find("0x1000:00"), std::string::npos) << report->error();
    EXPECT_NE(report->error().find("0x06010002"), std::string::npos) << report->error();
}

TEST(Master, HeartbeatLossIsReportedWithinConsumerTime) {
    Bench b;
    b.power_on();
    b.master.add_node(b.config());
    b.master.boot(3);
    b.run_for(500ms);
    ASSERT_TRUE(b.master.node(3)->booted());
    EXPECT_FALSE(b.has_event(MasterEventKind::HeartbeatLost));
    b.dev_bus.set_connected(false);
    const TimePoint cut = b.clock.now();
    b.run_for(300ms);
    ASSERT_TRUE(b.has_event(MasterEventKind::HeartbeatLost));
    EXPECT_TRUE(b.master.node(3)->heartbeat_lost());
    TimePoint lost_at{};
    for (const auto& e : b.events) {
        if (e.kind == MasterEventKind::HeartbeatLost) {
            lost_at = e.time;
        }
    }
    // Consumer time 150 ms (1.5 x producer); detection within consumer time + one period.
    EXPECT_LE(lost_at - cut, 150ms + 100ms);
    EXPECT_NE(b.event_text(MasterEventKind::HeartbeatLost).find("node 3: heartbeat lost"),
              std::string::npos);
    b.dev_bus.set_connected(true);
    b.run_for(300ms);
    EXPECT_TRUE(b.has_event(MasterEventKind::HeartbeatRecovered));
    EXPECT_FALSE(b.master.node(3)->heartbeat_lost());
}

TEST(Master, RebootedNodeIsReconfiguredAndReturnedToOperational) {
    Bench b;
    b.power_on();
    b.master.add_node(b.config());
    b.master.boot(3);
    b.run_for(500ms);
    ASSERT_EQ(b.device.state(), nmt::NmtState::Operational);
    ASSERT_EQ(b.device.writes_to_6060, 1);
    b.events.clear();
    b.device.boot(b.clock.now()); // power glitch: the node resets on its own
    EXPECT_EQ(b.device.od().get<std::int8_t>(0x6060, 0), 0);
    b.run_for(500ms);
    EXPECT_TRUE(b.has_event(MasterEventKind::NodeRebooted));
    EXPECT_TRUE(b.has_event(MasterEventKind::Recovered))
        << (b.events.empty() ? std::string() : b.events.back().text);
    EXPECT_EQ(b.device.state(), nmt::NmtState::Operational);
    EXPECT_EQ(b.device.od().get<std::int8_t>(0x6060, 0), 8) << "configuration written again";
    EXPECT_EQ(b.master.node(3)->reboots(), 1U);
    EXPECT_NE(b.event_text(MasterEventKind::Recovered).find("back to operational"),
              std::string::npos)
        << b.event_text(MasterEventKind::Recovered);
}

TEST(Master, NodeLeftPreOperationalComesBackPreOperational) {
    Bench b;
    b.power_on();
    auto c = b.config();
    c.start = false;
    b.master.add_node(c);
    b.master.boot(3);
    b.run_for(500ms);
    ASSERT_EQ(b.device.state(), nmt::NmtState::PreOperational);
    b.device.boot(b.clock.now());
    b.run_for(500ms);
    EXPECT_TRUE(b.has_event(MasterEventKind::Recovered));
    EXPECT_EQ(b.device.state(), nmt::NmtState::PreOperational);
}

TEST(Master, EmcyIsReportedAndRemembered) {
    Bench b;
    b.master.add_node(b.config());
    ASSERT_TRUE(b.dev_bus.send(Frame::make(0x83, {0x10, 0x23, 0x03, 0, 0, 0, 0, 0})));
    b.run_for(1ms);
    ASSERT_TRUE(b.has_event(MasterEventKind::Emcy));
    const auto& last = b.master.node(3)->last_emcy();
    ASSERT_TRUE(last);
    EXPECT_EQ(last->message.error_code, 0x2310);
    EXPECT_NE(b.event_text(MasterEventKind::Emcy).find("node 3"), std::string::npos);
}

TEST(Master, BusEventsBecomeMasterEvents) {
    Bench b;
    b.net.set_bus_off(true);
    EXPECT_EQ(b.event_text(MasterEventKind::BusEvent), "master: bus state bus-off");
}

TEST(NetworkScan, FindsExactlyTheNodesPresent) {
    FakeClock clock;
    VirtualNetwork net(clock, 100us);
    auto& mbus = net.endpoint("master");
    auto& d5 = net.endpoint("d5");
    auto& d17 = net.endpoint("d17");
    codrive::testing::TestDevice dev5(d5, 5);
    codrive::testing::TestDevice dev17(d17, 17, 0x9A);
    dev5.boot(clock.now());
    dev17.boot(clock.now());
    Master m(mbus, clock);
    net.run_until(clock, clock.now() + 1ms, {&m}); // boot-up messages cross first
    std::vector<ScanRow> rows;
    bool done = false;
    NetworkScan scan(m.sdo(), &m.nmt().states(), ScanOptions{});
    scan.start([&](std::vector<ScanRow> r) {
        rows = std::move(r);
        done = true;
    });
    std::vector<ITimed*> timed{&m};
    for (auto* t : dev5.timed()) {
        timed.push_back(t);
    }
    for (auto* t : dev17.timed()) {
        timed.push_back(t);
    }
    net.run_until(clock, clock.now() + 2s, timed);
    ASSERT_TRUE(done);
    ASSERT_EQ(rows.size(), 2U);
    EXPECT_EQ(rows[0].node, 5);
    EXPECT_EQ(rows[1].node, 17);
    EXPECT_EQ(rows[1].vendor_id, 0x9AU);
    EXPECT_EQ(rows[0].name, "TestDrive");
    EXPECT_EQ(rows[0].state, nmt::NmtState::PreOperational);
    const std::string table = format_scan_table(rows);
    EXPECT_NE(table.find("2 nodes found"), std::string::npos) << table;
}

TEST(Master, NodeThatDiesBeforeItsFirstHeartbeatIsReportedLost) {
    Bench b;
    b.power_on();
    b.master.add_node(b.config());
    b.master.boot(3);
    // Cut the node off as soon as its boot-up completed: no heartbeat ever reaches the master.
    b.net.set_fault_filter([&](const std::string& sender, const Frame& f) {
        FaultAction a;
        a.drop = sender == "device" && (f.id & 0x780) == 0x700 && b.master.node(3)->booted();
        return a;
    });
    b.run_for(500ms);
    ASSERT_TRUE(b.master.node(3)->booted());
    ASSERT_TRUE(b.has_event(MasterEventKind::HeartbeatLost));
    // Boot-up completes on the first heartbeat reporting operational (NMT start verification);
    // the consumer, which has seen that heartbeat, reports the loss.
    EXPECT_NE(b.event_text(MasterEventKind::HeartbeatLost)
                  .find("node 3: heartbeat lost after 150 ms (consumer time 150 ms)"),
              std::string::npos)
        << b.event_text(MasterEventKind::HeartbeatLost);
    b.net.set_fault_filter(nullptr);
    b.run_for(300ms);
    EXPECT_TRUE(b.has_event(MasterEventKind::HeartbeatRecovered));
    EXPECT_FALSE(b.master.node(3)->heartbeat_lost());
}

// NMT start is unconfirmed (CiA 301 §7.2.8.3.1): a lost start frame left the node
// pre-operational while the master reported it started. Boot-up now waits for a heartbeat
// reporting operational and repeats the command.
TEST(Master, LostNmtStartIsRepeatedUntilTheHeartbeatReportsOperational) {
    Bench b;
    b.power_on();
    b.master.add_node(b.config());
    int starts_sent = 0;
    b.net.set_fault_filter([&](const std::string& sender, const Frame& f) {
        FaultAction a;
        if (sender == "master" && f.id == 0x000 && f.len == 2 && f.data[0] == 0x01) {
            a.drop = ++starts_sent == 1; // the first NMT start is lost
        }
        return a;
    });
    std::optional<BootReport> report;
    b.master.boot(3, [&](const BootReport& r) { report = r; });
    b.run_for(100ms);
    EXPECT_FALSE(report) << "boot-up must not report success before the node is operational";
    EXPECT_EQ(b.device.state(), nmt::NmtState::PreOperational);
    b.run_for(500ms);
    ASSERT_TRUE(report);
    EXPECT_TRUE(report->ok) << report->to_string();
    EXPECT_EQ(starts_sent, 2);
    EXPECT_EQ(b.device.state(), nmt::NmtState::Operational);
    EXPECT_EQ(report->steps.back().name, "NMT start");
    EXPECT_EQ(report->steps.back().detail,
              "operational (confirmed by heartbeat after 2 NMT start commands)");
    EXPECT_EQ(b.master.node(3)->state(), nmt::NmtState::Operational);
}

TEST(Master, NodeThatNeverReachesOperationalFailsBootWithASentence) {
    Bench b;
    b.power_on();
    NodeConfig c = b.config();
    c.start_retries = 2;
    b.master.add_node(c);
    int starts_sent = 0;
    b.net.set_fault_filter([&](const std::string& sender, const Frame& f) {
        FaultAction a;
        if (sender == "master" && f.id == 0x000 && f.len == 2 && f.data[0] == 0x01) {
            ++starts_sent;
            a.drop = true;
        }
        return a;
    });
    std::optional<BootReport> report;
    b.master.boot(3, [&](const BootReport& r) { report = r; });
    b.run_for(2s);
    ASSERT_TRUE(report);
    EXPECT_FALSE(report->ok);
    EXPECT_EQ(starts_sent, 3); // the first and two repeats
    EXPECT_EQ(report->error(), "node 3: did not reach operational after 3 NMT start commands "
                               "(150 ms apart): its heartbeat reports pre-operational");
    EXPECT_TRUE(b.has_event(MasterEventKind::BootFailed));
}

// A node that resets during its boot-up (a power glitch, a watchdog) has lost the configuration
// written so far: the sequence starts again from the probe instead of failing.
TEST(Master, NodeRebootDuringBootUpRestartsTheSequence) {
    Bench b;
    b.power_on();
    b.master.add_node(b.config());
    bool reboot_due = false;
    bool rebooted = false;
    b.net.set_fault_filter([&](const std::string& sender, const Frame& f) {
        FaultAction a;
        // The write of 6060h reaches the device: it reboots instead of answering.
        if (!reboot_due && sender == "master" && f.id == 0x603 && f.data[1] == 0x60 &&
            f.data[2] == 0x60) {
            reboot_due = true;
            a.drop = true;
        }
        return a;
    });
    std::optional<BootReport> report;
    b.master.boot(3, [&](const BootReport& r) { report = r; });
    for (int i = 0; i < 1000 && !report; ++i) {
        b.run_for(1ms);
        if (reboot_due && !rebooted) {
            rebooted = true;
            b.device.boot(b.clock.now());
        }
    }
    ASSERT_TRUE(rebooted);
    ASSERT_TRUE(report);
    EXPECT_TRUE(report->ok) << report->to_string();
    bool restarted = false;
    for (const auto& s : report->steps) {
        restarted = restarted || (s.name == "restart" &&
                                  s.detail.find("node 3 rebooted (boot-up message) during step "
                                                "\"write 0x6060:00\"") == 0);
    }
    EXPECT_TRUE(restarted) << report->to_string();
    EXPECT_EQ(b.device.state(), nmt::NmtState::Operational);
    EXPECT_FALSE(b.has_event(MasterEventKind::BootFailed));
}
