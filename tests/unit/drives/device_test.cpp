// SPDX-License-Identifier: Apache-2.0
// Multi-axis devices (EMCY routing, shared transport), interpolated position and the blocking
// helper's header.
#include "rig.hpp"

#include <codrive/drives/blocking.hpp>
#include <codrive/drives/drive_device.hpp>

#include <gtest/gtest.h>

namespace codrive::drives::testing {
namespace {

TEST(DriveDevice, Akd2gEmcyGoesToTheAxisWhoseFaultListHoldsIt) {
    FakeDevice dev(akd2g_profile(), 2);
    FakeTransport tr(dev);
    DriveDevice d(tr, akd2g_profile(), 5); // clamped to 2
    ASSERT_EQ(d.axis_count(), 2U);
    EXPECT_EQ(d.axis(2).name(), "node 5 axis 2");
    EXPECT_EQ(d.axis(2).index(0x6041), 0x6841);

    emcy::EmcyConsumer consumer;
    d.attach_emcy_text(consumer, 5);
    std::string text;
    consumer.set_handler([&](const emcy::EmcyEvent& e) {
        text = e.text;
        d.on_emcy(e);
    });
    std::vector<std::pair<unsigned, AxisFault>> reported;
    for (unsigned a = 1; a <= 2; ++a) {
        d.axis(a).on_fault([&reported, a](const AxisFault& f) { reported.emplace_back(a, f); });
    }
    // The EMCY names no axis (AKD2G §4.3); the drive lists the fault in AXIS2.FAULT1 (5104h:01,
    // §5.3.84), so only axis 2 takes it.
    dev.trigger_fault(2, 0x8611);
    emcy::EmcyMessage m;
    m.node = 5;
    m.error_code = 0x8611;
    m.error_register = 1;
    consumer.on_frame(emcy::make_emcy_frame(m), TimePoint{});
    EXPECT_NE(text.find("F6001 Following error magnitude fault"), std::string::npos) << text;
    for (int i = 0; i < 12; ++i) {
        tr.process(); // the fault-list reads complete (one sub-index per round trip)
    }
    EXPECT_EQ(d.axis(1).last_error_code(), 0) << "axis 1 lists no fault";
    EXPECT_EQ(d.axis(2).last_error_code(), 0x8611);
    ASSERT_EQ(reported.size(), 1U);
    EXPECT_EQ(reported[0].first, 2U);
    EXPECT_EQ(reported[0].second.code, 0x8611);
    EXPECT_EQ(reported[0].second.text, "F6001 Following error magnitude fault");
    m.error_code = 0;
    consumer.on_frame(emcy::make_emcy_frame(m), TimePoint{});
    EXPECT_EQ(d.axis(2).last_error_code(), 0);
}

TEST(DriveDevice, Akd2gFaultListEntriesGiveTheDrivesFaultText) {
    FakeDevice dev(akd2g_profile(), 2);
    FakeTransport tr(dev);
    DriveDevice d(tr, akd2g_profile(), 2);
    // The manual does not say whether AXIS#.FAULT# holds the EMCY code or the fault number:
    // both name the same row.
    dev.od().set<std::uint16_t>(0x5004, 1, 0xFF07);
    dev.od().set<std::uint16_t>(0x5004, 2, 2006);
    std::optional<DriveResult<std::vector<AxisFault>>> faults;
    d.axis(1).read_faults([&](DriveResult<std::vector<AxisFault>> r) { faults = std::move(r); });
    for (int i = 0; i < 4; ++i) {
        tr.process();
    }
    ASSERT_TRUE(faults && faults->has_value());
    ASSERT_EQ((*faults)->size(), 2U);
    EXPECT_EQ((**faults)[0].text, "F2002 Output over current");
    EXPECT_EQ((**faults)[1].code, 0x3210);
    EXPECT_EQ((**faults)[1].text, "F2006 Bus over voltage");

    std::optional<DriveResult<std::vector<AxisFault>>> none;
    d.axis(2).read_faults([&](DriveResult<std::vector<AxisFault>> r) { none = std::move(r); });
    tr.process();
    tr.process();
    ASSERT_TRUE(none && none->has_value());
    EXPECT_TRUE((*none)->empty());

    // A drive without such a list says so.
    FakeDevice bvs(ds_bvs_profile(), 1);
    FakeTransport bt(bvs);
    AxisConfig cfg;
    cfg.profile = &ds_bvs_profile();
    Axis ax(bt, cfg);
    std::optional<DriveResult<std::vector<AxisFault>>> no_list;
    ax.read_faults([&](DriveResult<std::vector<AxisFault>> r) { no_list = std::move(r); });
    ASSERT_TRUE(no_list && !no_list->has_value());
    EXPECT_EQ(no_list->error().code, DriveErrc::NotSupported);
}

TEST(DriveDevice, PollsEveryAxisWithoutProcessData) {
    FakeClock clock;
    FakeDevice dev(akd2g_profile(), 2);
    FakeTransport tr(dev);
    AxisConfig base;
    base.poll_period = milliseconds(2);
    DriveDevice d(tr, akd2g_profile(), 2, base);
    std::optional<DriveVoid> r1;
    std::optional<DriveVoid> r2;
    d.axis(1).enable([&](DriveVoid r) { r1 = r; });
    d.axis(2).enable([&](DriveVoid r) { r2 = r; });
    for (int i = 0; i < 300 && !(r1 && r2); ++i) {
        clock.advance(milliseconds(1));
        dev.step();
        tr.process();
        if (d.next_deadline() <= clock.now()) {
            d.on_tick(clock.now());
        }
    }
    ASSERT_TRUE(r1 && r2);
    EXPECT_TRUE(r1->has_value()) << r1->error().message;
    EXPECT_TRUE(r2->has_value()) << r2->error().message;
    EXPECT_EQ(dev.model(1).state, cia402::State::OperationEnabled);
    EXPECT_EQ(dev.model(2).state, cia402::State::OperationEnabled);
}

TEST(AxisModes, InterpolatedPositionWritesDataRecordAndEnableBit) {
    Rig rig(generic_profile());
    rig.tr.map_output(0x60C1, 1);
    rig.axis().bind();
    rig.cycles(2);
    ASSERT_TRUE(
        rig.run([&](auto d) { rig.axis().set_mode(cia402::Mode::InterpolatedPosition, d); }));
    ASSERT_TRUE(rig.run([&](auto d) { rig.axis().enable(d); }));
    rig.axis().set_ip_enabled(true);
    rig.axis().set_ip_target(1234);
    rig.cycles(2);
    EXPECT_EQ(rig.dev.od().get<std::int32_t>(0x60C1, 1), 1234);
    EXPECT_EQ(rig.dev.controlword_log(1).back(), 0x001F);
}

} // namespace
} // namespace codrive::drives::testing
