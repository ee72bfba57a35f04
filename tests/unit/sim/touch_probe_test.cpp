// SPDX-License-Identifier: Apache-2.0
// The simulated AKD2G touch probes (manual §4.1.5, §5.4.36-§5.4.41), driven through the master's
// TouchProbes API on the simulator's own dictionary, one 1 ms step at a time.
#include "od_transport.hpp"
#include "sim_test_support.hpp"

#include <codrive/drives/touch_probe.hpp>

using namespace codrive;
using namespace codrive::sim;
using namespace codrive::sim::testing;
using drives::ProbeEdge;
using drives::ProbeTrigger;
using drives::TouchProbes;
namespace obj = cia::obj;
namespace sw = cia::sw;

namespace {

drives::DriveVoid arm(OdTransport& t, TouchProbes& p, unsigned probe, ProbeEdge e,
                      ProbeTrigger trig) {
    return await<drives::DriveVoid>(t, [&](auto done) { p.arm(probe, e, trig, done); });
}

drives::ProbeStatus status(OdTransport& t, TouchProbes& p, unsigned probe) {
    auto r = await<drives::DriveResult<drives::ProbeStatus>>(
        t, [&](auto done) { p.read_status(probe, done); });
    EXPECT_TRUE(r.has_value());
    return r.value_or(drives::ProbeStatus{});
}

std::int32_t latched(OdTransport& t, TouchProbes& p, unsigned probe, ProbeEdge e) {
    auto r = await<drives::DriveResult<std::int32_t>>(
        t, [&](auto done) { p.read_position(probe, e, done); });
    EXPECT_TRUE(r.has_value());
    return r.value_or(-1);
}

/// PP move to `target` (counts), stepping until target reached.
void move(AxisFixture& f, std::int32_t target, unsigned i = 0) {
    ASSERT_TRUE(f.write<std::int32_t>(obj::kTargetPosition, target, i));
    f.controlword(0x1F, i);
    f.run_ms(2);
    f.controlword(0x0F, i);
    ASSERT_TRUE(f.run_until([&] { return (f.statusword(i) & sw::kTargetReached) != 0; }, 10000));
}

} // namespace

TEST(SimTouchProbe, ObjectsHaveTheManualsTypesAccessAndMapping) {
    AxisFixture f("akd2g", 2);
    for (const unsigned axis_offset : {0U, 0x800U}) {
        const auto* fn = f.od.find(static_cast<std::uint16_t>(0x60B8 + axis_offset), 0);
        ASSERT_NE(fn, nullptr);
        EXPECT_EQ(fn->type, DataType::Unsigned16);
        EXPECT_TRUE(fn->pdo_mappable);
        EXPECT_TRUE(writable(fn->access)); // §5.4.36 Read/Write, PDO mappable
        const auto* st = f.od.find(static_cast<std::uint16_t>(0x60B9 + axis_offset), 0);
        ASSERT_NE(st, nullptr);
        EXPECT_EQ(st->type, DataType::Unsigned16);
        EXPECT_FALSE(writable(st->access)); // §5.4.37 Read only
        for (std::uint16_t i = 0x60BA; i <= 0x60BD; ++i) {
            const auto* pos = f.od.find(static_cast<std::uint16_t>(i + axis_offset), 0);
            ASSERT_NE(pos, nullptr);
            EXPECT_EQ(pos->type, DataType::Integer32); // §5.4.38-41 Signed32, ro, mappable
            EXPECT_FALSE(writable(pos->access));
            EXPECT_TRUE(pos->pdo_mappable);
        }
    }
    // A DS-BVS has none: the API says so rather than writing to a missing object.
    AxisFixture bvs("ds-bvs");
    EXPECT_EQ(bvs.axis().touch_probe(), nullptr);
    EXPECT_EQ(bvs.od.find(0x60B8, 0), nullptr);
}

TEST(SimTouchProbe, RisingEdgeLatchesTheSensorPositionOnceInFirstEventMode) {
    AxisFixture f("akd2g");
    OdTransport t(f.od);
    TouchProbes probes(t, drives::akd2g_profile());
    f.axis().touch_probe()->set_trigger_position(1, 200000); // a sensor at ~3 rev
    ASSERT_TRUE(f.write<std::int8_t>(obj::kModesOfOperation, 1));
    f.enable();

    ASSERT_TRUE(arm(t, probes, 1, ProbeEdge::Rising, ProbeTrigger::FirstEvent).has_value());
    auto st = status(t, probes, 1);
    EXPECT_TRUE(st.enabled);
    EXPECT_FALSE(st.rising_stored);

    move(f, 400000);
    st = status(t, probes, 1);
    EXPECT_TRUE(st.rising_stored);
    EXPECT_FALSE(st.falling_stored) << "falling edge sampling was not enabled";
    EXPECT_EQ(latched(t, probes, 1, ProbeEdge::Rising), 200000);

    // First event: going back and forth again does not overwrite the latch.
    f.axis().touch_probe()->set_trigger_position(1, 300000);
    move(f, 100000);
    move(f, 400000);
    EXPECT_EQ(latched(t, probes, 1, ProbeEdge::Rising), 200000);

    // Arming again clears the stored bit and latches the next edge.
    ASSERT_TRUE(arm(t, probes, 1, ProbeEdge::Rising, ProbeTrigger::FirstEvent).has_value());
    EXPECT_FALSE(status(t, probes, 1).rising_stored);
    move(f, 100000);
    move(f, 400000);
    EXPECT_TRUE(status(t, probes, 1).rising_stored);
    EXPECT_EQ(latched(t, probes, 1, ProbeEdge::Rising), 300000);

    // Disarmed: §5.4.37 "the latched bits ... are always 0".
    ASSERT_TRUE(
        await<drives::DriveVoid>(t, [&](auto done) { probes.disarm(1, done); }).has_value());
    st = status(t, probes, 1);
    EXPECT_FALSE(st.enabled || st.rising_stored || st.falling_stored);
}

TEST(SimTouchProbe, ContinuousProbeTwoLatchesEveryFallingEdgeOnAxisTwo) {
    AxisFixture f("akd2g", 2);
    OdTransport t(f.od);
    TouchProbes probes(t, drives::akd2g_profile(), 2);
    TouchProbes axis1(t, drives::akd2g_profile(), 1);
    TouchProbe& sim = *f.axis(1).touch_probe();
    ASSERT_TRUE(arm(t, probes, 2, ProbeEdge::Falling, ProbeTrigger::Continuous).has_value());
    EXPECT_EQ(f.od.get<std::uint16_t>(0x68B8, 0), 0x2300);
    EXPECT_EQ(f.od.get<std::uint16_t>(0x60B8, 0), 0) << "axis 1 untouched";

    sim.set_input(2, true, 1000);
    EXPECT_FALSE(status(t, probes, 2).falling_stored) << "a rising edge is not sampled";
    sim.set_input(2, false, 1500);
    EXPECT_TRUE(status(t, probes, 2).falling_stored);
    EXPECT_EQ(latched(t, probes, 2, ProbeEdge::Falling), 1500);
    sim.set_input(2, true, 1700);
    sim.set_input(2, false, 2500);
    EXPECT_EQ(latched(t, probes, 2, ProbeEdge::Falling), 2500) << "continuous: every edge";
    EXPECT_EQ(f.od.get<std::int32_t>(0x68BD, 0), 2500);
    EXPECT_EQ(f.od.get<std::int32_t>(0x60BD, 0), 0);
    EXPECT_FALSE(status(t, axis1, 2).enabled) << "axis 1's probe 2 is a different probe";
}

TEST(SimTouchProbe, ReservedTriggerSelectionIsRefused) {
    AxisFixture f("akd2g");
    // 60B8h bits 3,2 = 11b are "Reserved" (§5.4.36).
    EXPECT_FALSE(f.write<std::uint16_t>(0x60B8, 0x001D).has_value());
    EXPECT_FALSE(f.write<std::uint16_t>(0x60B8, 0x1D00).has_value());
    EXPECT_TRUE(f.write<std::uint16_t>(0x60B8, 0x0011).has_value());
}
