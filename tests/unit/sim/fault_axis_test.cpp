// SPDX-License-Identifier: Apache-2.0
// The master finds the axis of a fault on the simulated two-axis AKD2G the way the drive offers
// it: the EMCY names no axis (manual §4.3), AXIS#.FAULT1..10 (5004h/5104h, §5.3.84) do.
#include "od_transport.hpp"
#include "sim_test_support.hpp"

#include <codrive/drives/drive_device.hpp>

using namespace codrive;
using namespace codrive::sim;
using namespace codrive::sim::testing;

namespace {

/// The EMCY the simulated device sends for an axis event: the code, no axis byte.
emcy::EmcyEvent emcy_of(const AxisEvent& e) {
    emcy::EmcyEvent ev;
    ev.message.node = 7;
    ev.message.error_code = e.kind == AxisEvent::Kind::FaultsCleared ? 0 : e.code.emcy;
    ev.reset = ev.message.error_code == 0;
    return ev;
}

void settle(AxisFixture& f, OdTransport& t, drives::DriveDevice& d) {
    for (int i = 0; i < 20; ++i) {
        t.process();
        f.run_ms(1);
        d.on_tick(TimePoint{} + milliseconds(25 * i));
    }
}

} // namespace

TEST(SimFaultAxis, OverCurrentOnEitherAxisIsAttributedToThatAxisOnly) {
    for (unsigned faulty = 1; faulty <= 2; ++faulty) {
        AxisFixture f("akd2g", 2);
        OdTransport t(f.od);
        drives::DriveDevice dev(t, drives::akd2g_profile(), 2);
        std::vector<std::pair<unsigned, drives::AxisFault>> reported;
        for (unsigned a = 1; a <= 2; ++a) {
            dev.axis(a).on_fault(
                [&reported, a](const drives::AxisFault& x) { reported.emplace_back(a, x); });
        }
        f.enable(0);
        f.enable(1);
        f.events.clear();
        f.axis(faulty - 1).inject(FaultKind::OverCurrent);
        ASSERT_FALSE(f.events.empty());
        EXPECT_EQ(f.events[0].code.emcy, 0xFF07);
        dev.on_emcy(emcy_of(f.events[0]));
        settle(f, t, dev);
        const unsigned other = 3 - faulty;
        ASSERT_EQ(reported.size(), 1U) << "axis " << faulty;
        EXPECT_EQ(reported[0].first, faulty);
        EXPECT_EQ(reported[0].second.text, "F2002 Output over current");
        EXPECT_EQ(dev.axis(faulty).last_error_code(), 0xFF07);
        EXPECT_EQ(dev.axis(other).last_error_code(), 0) << "axis " << other << " lists no fault";
        EXPECT_NE(dev.axis(faulty).diagnose().find("F2002 Output over current"), std::string::npos)
            << dev.axis(faulty).diagnose();
    }
}
