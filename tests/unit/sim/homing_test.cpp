// SPDX-License-Identifier: Apache-2.0
// Every homing method of every simulated profile finds its home as the manual describes.
#include "sim_test_support.hpp"

#include <cmath>

using namespace codrive;
using namespace codrive::sim;
using namespace codrive::sim::testing;
namespace obj = cia::obj;
namespace sw = cia::sw;

namespace {

struct Case {
    const char* profile;
    std::int8_t method;
};

std::string case_name(const ::testing::TestParamInfo<Case>& info) {
    std::string n = info.param.profile;
    for (auto& c : n) {
        if (c == '-') {
            c = '_';
        }
    }
    return n + "_" + (info.param.method < 0 ? "m" : "") +
           std::to_string(std::abs(info.param.method));
}

std::vector<Case> all_cases() {
    std::vector<Case> out;
    for (const char* name : {"akd2g", "ds-bvs", "fio"}) {
        for (const std::int8_t m : find_profile(name)->drive->homing_methods) {
            out.push_back({name, m});
        }
    }
    return out;
}

/// Where the method's reference is, in revolutions of the default machine.
double expected_world_rev(const HomingMethod& m, const MachineConfig& mc, double cpr) {
    const auto next_index = [&](double from, int dir) {
        double k =
            dir > 0 ? std::ceil(from - mc.index_phase_rev) : std::floor(from - mc.index_phase_rev);
        return k + mc.index_phase_rev;
    };
    (void)cpr;
    switch (m.ref) {
    case HomingRef::CurrentPosition:
        return 0;
    case HomingRef::LimitSwitch: {
        const double edge = m.direction < 0 ? mc.neg_limit_rev : mc.pos_limit_rev;
        return m.index ? next_index(edge, -m.direction) : edge;
    }
    case HomingRef::HomeSwitch: {
        const double edge = m.edge < 0 ? mc.home_low_rev : mc.home_high_rev;
        return m.index ? next_index(edge, m.edge) : edge;
    }
    case HomingRef::HardStop:
        return m.direction < 0 ? mc.neg_stop_rev : mc.pos_stop_rev;
    case HomingRef::IndexPulse:
        return next_index(0, m.direction);
    }
    return 0;
}

class SimHoming : public ::testing::TestWithParam<Case> {};

TEST_P(SimHoming, MethodFindsHomeAndSetsAttained) {
    const Case c = GetParam();
    AxisFixture f(c.profile);
    const HomingMethod* m = f.profile.find_homing(c.method);
    ASSERT_NE(m, nullptr);
    ASSERT_TRUE(f.write<std::int8_t>(obj::kModesOfOperation, 6));
    ASSERT_TRUE(f.write<std::int8_t>(obj::kHomingMethod, c.method));
    // DS-BVS moves by the offset after homing: away from a mechanical stop, not into it.
    const std::int32_t offset = (m->ref == HomingRef::HardStop && m->direction > 0) ? -100 : 100;
    ASSERT_TRUE(f.write<std::int32_t>(obj::kHomeOffset, offset));
    if (f.profile.velocity_in_rpm) {
        // Faster than the defaults so the test stays short: 300 rpm search, 30 rpm creep.
        f.write<std::uint32_t>(obj::kHomingSpeeds, 300, 0, 1);
        f.write<std::uint32_t>(obj::kHomingSpeeds, 30, 0, 2);
        f.write<std::uint32_t>(obj::kHomingAcceleration, 10000);
    }
    f.enable();
    EXPECT_NE(f.statusword() & sw::kTargetReached, 0) << "not started yet";
    f.controlword(0x1F);
    f.run_ms(2);
    if (m->ref != HomingRef::CurrentPosition) {
        EXPECT_EQ(f.statusword() & (sw::kTargetReached | sw::kOpMode12 | sw::kOpMode13), 0)
            << "in progress";
    }
    ASSERT_TRUE(f.run_until(
        [&] {
            return (f.statusword() & (sw::kOpMode12 | sw::kTargetReached)) ==
                       (sw::kOpMode12 | sw::kTargetReached) ||
                   (f.statusword() & sw::kOpMode13) != 0;
        },
        60000));
    ASSERT_EQ(f.statusword() & sw::kOpMode13, 0) << "homing error";
    const double cpr = f.profile.counts_per_rev;
    const auto& mc = f.axis().motor().config();
    const double home_world = expected_world_rev(*m, mc, cpr) * cpr;
    const double world = f.axis().motor().world();
    const double pos = f.read<std::int32_t>(obj::kPositionActual);
    const double tolerance = std::max(0.01 * cpr, 3.0);
    if (f.profile.homing_moves_by_offset) {
        // DS-BVS: moved by the offset from the reference, which then became 0.
        EXPECT_NEAR(world, home_world + offset, tolerance);
        EXPECT_NEAR(pos, 0, tolerance);
        EXPECT_NE(f.statusword() & 0x8000, 0) << "bit 15 referenced";
    } else {
        EXPECT_NEAR(world, home_world, tolerance);
        EXPECT_NEAR(pos, offset, tolerance);
    }
    f.controlword(0x0F);
    f.run_ms(1);
    EXPECT_NE(f.statusword() & sw::kOpMode12, 0) << "attained stays after bit 4 is cleared";
}

INSTANTIATE_TEST_SUITE_P(AllProfiles, SimHoming, ::testing::ValuesIn(all_cases()), case_name);

TEST(SimHomingControl, ClearingBit4InterruptsHoming) {
    AxisFixture f("akd2g");
    f.write<std::int8_t>(obj::kModesOfOperation, 6);
    f.write<std::int8_t>(obj::kHomingMethod, 17);
    f.enable();
    f.controlword(0x1F);
    f.run_ms(100);
    f.controlword(0x0F);
    f.run_ms(300);
    EXPECT_EQ(f.statusword() & (sw::kTargetReached | sw::kOpMode12 | sw::kOpMode13),
              sw::kTargetReached)
        << "interrupted";
}

TEST(SimHomingControl, MissingHomeSwitchIsAHomingError) {
    MachineConfig mc;
    mc.home_low_rev = 50; // outside the travel range
    mc.home_high_rev = 51;
    ObjectDictionary od;
    DriveCore axis(od, *find_profile("akd2g"), 0, mc);
    std::uint8_t buf[2];
    const auto cw = [&](std::uint16_t v) {
        put_le<std::uint16_t>(buf, v);
        ASSERT_TRUE(od.write(0x6040, 0, {buf, 2}));
    };
    std::uint8_t m = 6;
    ASSERT_TRUE(od.write(0x6060, 0, {&m, 1}));
    m = 24;
    ASSERT_TRUE(od.write(0x6098, 0, {&m, 1}));
    cw(0x06);
    cw(0x07);
    cw(0x0F);
    axis.step(0.001);
    cw(0x1F);
    for (int k = 0; k < 20000 && (axis.statusword() & sw::kOpMode13) == 0; ++k) {
        axis.step(0.001);
    }
    EXPECT_NE(axis.statusword() & sw::kOpMode13, 0);
    EXPECT_EQ(axis.statusword() & sw::kOpMode12, 0);
}

} // namespace
