// SPDX-License-Identifier: Apache-2.0
// Units: the AKD2G manual's factor-group examples, FIO 60A8h/60A9h decoding, DS-BVS fixed units,
// reading the unit objects from a drive and the SI axis.
#include "rig.hpp"

#include <codrive/drives/units.hpp>

#include <gtest/gtest.h>

#include <numbers>

namespace codrive::drives {
namespace {

constexpr double kPi = std::numbers::pi;

TEST(Units, Akd2gManualExamples) {
    FactorGroup fg;
    fg.feed = {65536, 1};
    // 180 degrees with 65536 per revolution, gear 1/1 → 32768.
    SiScale s = SiScale::from_factor_group(fg, 2 * kPi);
    EXPECT_EQ(s.to_position(kPi), 32768);
    // 100 rpm → 109226.67 → 109227 (the manual's 109266.6667 is a typo).
    EXPECT_NEAR(fg.velocity_value(100.0 / 60.0 * 65536.0), 109226.6667, 1e-3);
    EXPECT_EQ(s.to_velocity(100.0 / 60.0 * 2 * kPi), 109227);
    // 606Ch = 250000 → 228.9 rpm (the manual prints 289).
    EXPECT_NEAR(s.from_velocity(250000) / (2 * kPi) * 60.0, 228.88, 0.01);

    FactorGroup deg;
    deg.feed = {36000, 1};
    deg.velocity = {60, 36000};
    SiScale d = SiScale::from_factor_group(deg, 2 * kPi);
    EXPECT_EQ(d.to_position(kPi), 18000);
    EXPECT_EQ(d.to_velocity(100.0 / 60.0 * 2 * kPi), 100); // rpm
    EXPECT_EQ(d.to_velocity(200.0 / 60.0 * 2 * kPi), 200);

    FactorGroup screw; // 2 mm lead, gear 5:1, 2000 units per shaft revolution (1 µm)
    screw.feed = {2000, 1};
    screw.gear = {5, 1};
    SiScale l = SiScale::from_factor_group(screw, 0.002, true);
    EXPECT_EQ(l.to_position(0.025), 25000);
    EXPECT_DOUBLE_EQ(screw.position_units_per_motor_rev(), 400.0);

    FactorGroup acc; // 120000 counts/s in 5 s → 24000
    EXPECT_DOUBLE_EQ(acc.acceleration_value(120000.0 / 5.0), 24000.0);

    FactorGroup inc;
    inc.increments_per_motor_rev = 4294967296.0;
    inc.feed = {65536, 1};
    EXPECT_DOUBLE_EQ(inc.to_increments(32768), 2147483648.0);
    EXPECT_DOUBLE_EQ(inc.from_increments(2147483648.0), 32768);
}

TEST(Units, FioSiUnitObjects) {
    // Defaults: 0.1 degree and rpm.
    auto s = SiScale::from_si_unit_objects(0xFF410000, 0x00B44700);
    ASSERT_TRUE(s.has_value()) << s.error().message;
    EXPECT_EQ(s->to_position(2 * kPi), 3600); // one revolution = 3600 tenths of a degree
    EXPECT_EQ(s->to_velocity(2 * kPi), 60);   // 1 rev/s = 60 rpm
    EXPECT_FALSE(s->linear);
    // mm and mm/s.
    auto mm = SiScale::from_si_unit_objects(0xFD010000, 0xFD010300);
    ASSERT_TRUE(mm.has_value());
    EXPECT_EQ(mm->to_position(0.5), 500);
    EXPECT_EQ(mm->to_velocity(0.01), 10);
    EXPECT_TRUE(mm->linear);
    // Increments are not SI.
    auto inc = SiScale::from_si_unit_objects(0x00B50000, 0x00B44700);
    ASSERT_FALSE(inc.has_value());
    EXPECT_EQ(inc.error().message, "position unit 60A8h = 0x00B50000 is not an SI length or angle");
}

TEST(Units, DsBvsFixedUnits) {
    SiScale s = SiScale::fixed_rpm(2000);
    EXPECT_EQ(s.to_position(2 * kPi), 2000);
    EXPECT_EQ(s.to_velocity(2 * kPi), 60);
    EXPECT_EQ(s.to_acceleration(2 * kPi), 60U);
}

TEST(Units, ReadsTheFactorGroupFromTheDrive) {
    testing::Rig rig(akd2g_profile(), true, 2);
    rig.dev.od().set<std::uint32_t>(0x6896, 1, 60);
    rig.dev.od().set<std::uint32_t>(0x6896, 2, 65536);
    std::optional<DriveResult<FactorGroup>> got;
    read_factor_group(rig.tr, akd2g_profile(), 2, [&](DriveResult<FactorGroup> r) { got = r; });
    for (int i = 0; i < 20 && !got; ++i) {
        rig.cycle();
    }
    ASSERT_TRUE(got && got->has_value());
    EXPECT_EQ((*got)->feed.num, 65536U);
    EXPECT_EQ((*got)->velocity.num, 60U);
    EXPECT_EQ((*got)->velocity.den, 65536U);
    EXPECT_DOUBLE_EQ((*got)->increments_per_motor_rev, 4294967296.0);

    std::optional<DriveResult<SiScale>> fio;
    testing::Rig f(fio_profile());
    read_si_scale(f.tr, fio_profile(), 1, 0, false, [&](DriveResult<SiScale> r) { fio = r; });
    for (int i = 0; i < 20 && !fio; ++i) {
        f.cycle();
    }
    ASSERT_TRUE(fio && fio->has_value());
    EXPECT_EQ((*fio)->to_position(2 * kPi), 3600);

    std::optional<DriveResult<SiScale>> ds;
    testing::Rig d(ds_bvs_profile());
    read_si_scale(d.tr, ds_bvs_profile(), 1, 0, false, [&](DriveResult<SiScale> r) { ds = r; });
    for (int i = 0; i < 20 && !ds; ++i) {
        d.cycle();
    }
    ASSERT_TRUE(ds && ds->has_value());
    EXPECT_EQ((*ds)->to_position(2 * kPi), 500); // 608Fh:1 default 500
}

TEST(Units, SiAxisMovesInRadians) {
    testing::Rig rig(generic_profile());
    rig.cycles(2);
    ASSERT_TRUE(rig.run([&](auto d) { rig.axis().set_mode(cia402::Mode::ProfilePosition, d); }));
    ASSERT_TRUE(rig.run([&](auto d) { rig.axis().enable(d); }));
    FactorGroup fg;
    fg.feed = {3600, 1};
    SiAxis si(rig.axis(), SiScale::from_factor_group(fg, 2 * kPi));
    ASSERT_TRUE(rig.run([&](auto d) { si.move_to(kPi / 2, {}, d); }));
    EXPECT_EQ(rig.dev.model(1).position, 900);
    ASSERT_TRUE(si.position().has_value());
    EXPECT_NEAR(*si.position(), kPi / 2, 1e-9);
}

} // namespace
} // namespace codrive::drives
