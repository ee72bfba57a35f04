// SPDX-License-Identifier: Apache-2.0
// NetworkScan on a slow bus: the identity of a found node survives a transmit queue full of probes.
#include "test_device.hpp"

#include <codrive/master/master.hpp>
#include <codrive/master/network_scan.hpp>

#include <gtest/gtest.h>

using namespace codrive;
using namespace codrive::master;
using namespace std::chrono_literals;

namespace {

// Found with CANopenNode's demo device (canopend) on a loaded vcan: the scan queued 127 probes,
// the device answered its 1000h probe at once, and the 1018h:01 request queued behind the other
// 126 probes; the device answered it 1 ms after it reached the bus, but the client's 300 ms had
// run since it was queued, so the scan printed vendor "-". The model below is the master's
// transmit queue: its frames leave one at a time, 3 ms each (an 8-byte frame near 40 kbit/s, or
// a slow virtual bus). The devices' answers are not queued behind them (their lower COB-IDs
// 580h+n win the arbitration against the master's 600h+n on a real bus).
struct MasterTxQueue {
    FakeClock& clock;
    TimePoint busy_until{};
    Duration frame_time = 3ms;
    FaultAction operator()(const std::string& sender, const Frame& /*f*/) {
        if (sender != "master") {
            return FaultAction::none();
        }
        busy_until = std::max(busy_until, clock.now()) + frame_time;
        FaultAction a;
        a.delay = busy_until - clock.now();
        return a;
    }
};

struct ScanBench {
    FakeClock clock;
    VirtualNetwork net{clock, 100us};
    VirtualBus& mbus = net.endpoint("master");
    VirtualBus& d5bus = net.endpoint("d5");
    VirtualBus& d17bus = net.endpoint("d17");
    codrive::testing::TestDevice dev5{d5bus, 5, 0x11};
    codrive::testing::TestDevice dev17{d17bus, 17, 0x9A};
    Master m{mbus, clock};

    std::vector<ScanRow> scan(ScanOptions o) {
        dev5.boot(clock.now());
        dev17.boot(clock.now());
        net.run_until(clock, clock.now() + 1ms, {&m});
        std::vector<ScanRow> rows;
        bool done = false;
        NetworkScan scan(m.sdo(), &m.nmt().states(), o);
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
        net.run_until(clock, clock.now() + 5s, timed);
        EXPECT_TRUE(done);
        return rows;
    }
};

} // namespace

TEST(NetworkScan, IdentityOfFoundNodesIsReadOnASlowBus) {
    ScanBench b;
    MasterTxQueue wire{b.clock};
    b.net.set_fault_filter([&wire](const std::string& s, const Frame& f) { return wire(s, f); });
    const auto rows = b.scan(ScanOptions{});
    ASSERT_EQ(rows.size(), 2U);
    EXPECT_EQ(rows[0].node, 5);
    ASSERT_TRUE(rows[0].vendor_id.has_value()) << format_scan_table(rows);
    EXPECT_EQ(*rows[0].vendor_id, 0x11U);
    EXPECT_EQ(rows[0].name, "TestDrive");
    EXPECT_EQ(rows[1].node, 17);
    ASSERT_TRUE(rows[1].vendor_id.has_value()) << format_scan_table(rows);
    EXPECT_EQ(*rows[1].vendor_id, 0x9AU);
    EXPECT_EQ(format_scan_table(rows).find(" - "), std::string::npos) << format_scan_table(rows);
}

TEST(NetworkScan, AbsentNodeCostsOneProbeOnly) {
    ScanBench b;
    std::vector<Frame> to_absent;
    b.net.set_fault_filter([&](const std::string& sender, const Frame& f) {
        if (sender == "master" && f.id == 0x600 + 9) {
            to_absent.push_back(f);
        }
        return FaultAction::none();
    });
    ScanOptions o;
    o.first = 1;
    o.last = 20;
    const auto rows = b.scan(o);
    ASSERT_EQ(rows.size(), 2U);
    // Node 9 is absent: one 1000h request and the client's timeout abort (CiA 301 05040000h),
    // no repeats (the detail retries are for nodes that answered).
    ASSERT_EQ(to_absent.size(), 2U);
    EXPECT_EQ(to_absent[0].data[0], 0x40);
    EXPECT_EQ(to_absent[1].data[0], 0x80);
}
