// SPDX-License-Identifier: Apache-2.0
// Touch probe API: the 60B8h bits of AKD2G §5.4.36, 60B9h decoding, the arm/disarm sequence on
// the wire and the errors a user gets.
#include "rig.hpp"

#include <codrive/drives/touch_probe.hpp>

#include <gtest/gtest.h>

namespace codrive::drives::testing {
namespace {

TEST(TouchProbes, FunctionBitsFollowTheManual) {
    // Probe 1: bit 0 enable, 1 continuous, 3..2 source, 4 rising, 5 falling (§5.4.36).
    EXPECT_EQ(TouchProbes::function_bits(1, ProbeEdge::Rising, ProbeTrigger::FirstEvent), 0x0011);
    EXPECT_EQ(TouchProbes::function_bits(1, ProbeEdge::Falling, ProbeTrigger::Continuous), 0x0023);
    EXPECT_EQ(TouchProbes::function_bits(1, ProbeEdge::Both, ProbeTrigger::FirstEvent,
                                         ProbeSource::ZeroPulse),
              0x0035);
    // Probe 2: the same bits 8 higher.
    EXPECT_EQ(TouchProbes::function_bits(2, ProbeEdge::Rising, ProbeTrigger::Continuous), 0x1300);
    EXPECT_EQ(TouchProbes::function_bits(2, ProbeEdge::Falling, ProbeTrigger::FirstEvent,
                                         ProbeSource::Object60D0),
              0x2900);
    // 60B9h (§5.4.37): bit 0/8 enabled, 1/9 rising stored, 2/10 falling stored.
    const ProbeStatus p1 = TouchProbes::decode_status(0x0503, 1);
    EXPECT_TRUE(p1.enabled);
    EXPECT_TRUE(p1.rising_stored);
    EXPECT_FALSE(p1.falling_stored);
    const ProbeStatus p2 = TouchProbes::decode_status(0x0503, 2);
    EXPECT_TRUE(p2.enabled && !p2.rising_stored && p2.falling_stored);
    EXPECT_TRUE(p2.stored(ProbeEdge::Both));
}

TEST(TouchProbes, ArmDisablesFirstThenEnablesAndKeepsTheOtherProbe) {
    FakeDevice dev(akd2g_profile(), 2);
    FakeTransport tr(dev);
    std::vector<std::uint16_t> writes;
    dev.od().on_write(0x68B8,
                      [&](std::uint16_t, std::uint8_t,
                          std::span<const std::uint8_t> d) -> tl::expected<void, SdoAbort> {
                          writes.push_back(get_le<std::uint16_t>(d.data()));
                          return {};
                      });
    dev.od().set<std::uint16_t>(0x68B8, 0, 0x1300); // probe 2 armed by someone else
    TouchProbes probes(tr, akd2g_profile(), 2);     // axis 2: 68B8h (§4.1.5 table)
    std::optional<DriveVoid> done;
    probes.arm(1, ProbeEdge::Falling, ProbeTrigger::FirstEvent, [&](DriveVoid r) { done = r; });
    for (int i = 0; i < 5; ++i) {
        tr.process();
    }
    ASSERT_TRUE(done.has_value());
    ASSERT_TRUE(done->has_value()) << done->error().message;
    // The enable must be an edge (it re-arms and clears the old latch).
    EXPECT_EQ(writes, (std::vector<std::uint16_t>{0x1300, 0x1321}));

    done.reset();
    probes.disarm(2, [&](DriveVoid r) { done = r; });
    for (int i = 0; i < 5; ++i) {
        tr.process();
    }
    ASSERT_TRUE(done && done->has_value());
    EXPECT_EQ(dev.od().get<std::uint16_t>(0x68B8, 0), 0x0021);
}

TEST(TouchProbes, ReadsStatusAndPositionsOverSdoAndFromTheProcessImage) {
    FakeDevice dev(akd2g_profile(), 1);
    FakeTransport tr(dev);
    dev.od().set<std::uint16_t>(0x60B9, 0, 0x0003);
    dev.od().set<std::int32_t>(0x60BA, 0, -12345);
    dev.od().set<std::int32_t>(0x60BD, 0, 777);
    TouchProbes probes(tr, akd2g_profile());
    std::optional<DriveResult<ProbeStatus>> st;
    probes.read_status(1, [&](DriveResult<ProbeStatus> r) { st = r; });
    std::optional<DriveResult<std::int32_t>> pos;
    probes.read_position(1, ProbeEdge::Rising, [&](DriveResult<std::int32_t> r) { pos = r; });
    std::optional<DriveResult<std::int32_t>> neg2;
    probes.read_position(2, ProbeEdge::Falling, [&](DriveResult<std::int32_t> r) { neg2 = r; });
    tr.process();
    ASSERT_TRUE(st && st->has_value());
    EXPECT_TRUE((*st)->enabled && (*st)->rising_stored);
    ASSERT_TRUE(pos && pos->has_value());
    EXPECT_EQ(**pos, -12345);
    ASSERT_TRUE(neg2 && neg2->has_value());
    EXPECT_EQ(**neg2, 777);

    EXPECT_FALSE(probes.status(1).has_value()) << "60B9h is not mapped";
    tr.map_input(0x60B9, 0);
    tr.map_input(0x60BA, 0);
    probes.bind(); // the mapping changed
    tr.process();
    ASSERT_TRUE(probes.status(1).has_value());
    EXPECT_TRUE(probes.status(1)->rising_stored);
    EXPECT_EQ(probes.position(1, ProbeEdge::Rising), -12345);
}

TEST(TouchProbes, BadRequestsFailWithASentence) {
    FakeDevice dev(akd2g_profile(), 1);
    FakeTransport tr(dev);
    TouchProbes probes(tr, akd2g_profile());
    std::optional<DriveVoid> r;
    probes.arm(3, ProbeEdge::Rising, ProbeTrigger::FirstEvent, [&](DriveVoid v) { r = v; });
    ASSERT_TRUE(r && !r->has_value());
    EXPECT_EQ(r->error().code, DriveErrc::InvalidArgument);
    EXPECT_EQ(r->error().message, "node 5 axis 1: touch probe 3 does not exist (1 or 2)");
    std::optional<DriveResult<std::int32_t>> both;
    probes.read_position(1, ProbeEdge::Both, [&](DriveResult<std::int32_t> v) { both = v; });
    ASSERT_TRUE(both && !both->has_value());
    EXPECT_EQ(both->error().code, DriveErrc::InvalidArgument);

    FakeDevice bvs(ds_bvs_profile(), 1);
    FakeTransport bt(bvs);
    TouchProbes none(bt, ds_bvs_profile());
    r.reset();
    none.arm(1, ProbeEdge::Rising, ProbeTrigger::FirstEvent, [&](DriveVoid v) { r = v; });
    ASSERT_TRUE(r && !r->has_value());
    EXPECT_EQ(r->error().code, DriveErrc::NotSupported);
    EXPECT_NE(r->error().message.find("no touch probe (no object 60B8h)"), std::string::npos)
        << r->error().message;
}

} // namespace
} // namespace codrive::drives::testing
