// SPDX-License-Identifier: Apache-2.0
// Units end to end over CoE: read_si_scale and the factor group read by CoE SDO from the
// simulated FIO, AKD2G and DS-BVS EtherCAT slaves, in-process on a FakeClock.
#include <codrive/drives/units.hpp>
#include <codrive/sim/ecat/drive_profiles.hpp>
#include <codrive/sim/ecat/segment.hpp>
#include <codrive/testing/ecat_cia402_rig.hpp>

#include <gtest/gtest.h>

#include <numbers>

namespace codrive::testing {
namespace {

constexpr double kPi = std::numbers::pi;

struct CoeUnitsRig {
    FakeClock clock;
    sim::ecat::EcatSegment segment;
    std::unique_ptr<sim::ecat::SegmentLink> link;
    std::unique_ptr<ethercat::Master> master;
    std::unique_ptr<EcatCia402Rig> rig;

    CoeUnitsRig() {
        segment.add(sim::ecat::make_drive_slave("fio", 1));
        segment.add(sim::ecat::make_drive_slave("akd2g", 2));
        segment.add(sim::ecat::make_drive_slave("ds-bvs", 3));
        link = std::make_unique<sim::ecat::SegmentLink>(segment, clock);
        master = std::make_unique<ethercat::Master>(*link, clock);
        rig = std::make_unique<EcatCia402Rig>(*master, clock, milliseconds(2), [this](TimePoint t) {
            if (clock.now() < t) {
                clock.set(t);
            }
        });
    }

    drives::DriveResult<drives::SiScale> scale(std::size_t slave, const drives::Profile& p,
                                               bool linear = false) {
        std::optional<drives::DriveResult<drives::SiScale>> out;
        drives::read_si_scale(rig->transport(slave), p, 1, 2 * kPi, linear,
                              [&](drives::DriveResult<drives::SiScale> r) { out = std::move(r); });
        rig->run_until([&] { return out.has_value(); }, seconds(2));
        if (!out) {
            return drives::drive_fail(drives::DriveErrc::Timeout, "read_si_scale never ended");
        }
        return *out;
    }
    template <typename T>
    std::optional<T> read(std::size_t slave, std::uint16_t index, std::uint8_t sub) {
        std::optional<T> out;
        rig->transport(slave).read_as<T>(index, sub, [&](drives::DriveResult<T> r) {
            if (r) {
                out = *r;
            }
        });
        rig->run_until([&] { return out.has_value(); }, seconds(2));
        return out;
    }
};

TEST(CoeUnits, FioSiUnitObjectsReadOverCoeGiveTenthsOfADegreeAndRpm) {
    CoeUnitsRig r;
    ASSERT_TRUE(r.rig->bring_up({"fio", "akd2g", "ds-bvs"}));
    // FIO manual §7.13: 608Fh:01 default 2000, 60A8h = FF410000h (0.1°), 60A9h = 00B44700h (rpm).
    EXPECT_EQ(r.read<std::uint32_t>(0, 0x608F, 1), 2000U);
    EXPECT_EQ(r.read<std::uint32_t>(0, 0x60A8, 0), 0xFF410000U);
    EXPECT_EQ(r.read<std::uint32_t>(0, 0x60A9, 0), 0x00B44700U);
    auto s = r.scale(0, drives::fio_profile());
    ASSERT_TRUE(s) << s.error().message;
    EXPECT_FALSE(s->linear);
    EXPECT_EQ(s->to_position(2 * kPi), 3600); // one revolution in 0.1°
    EXPECT_EQ(s->to_velocity(2 * kPi), 60);   // 1 rev/s in rpm

    // A user who sets millimetres (FD010000h) and mm/s (FD010300h) reads them back as metres.
    ASSERT_TRUE(r.rig->write<std::uint32_t>(0, 0x60A8, 0, 0xFD010000U));
    ASSERT_TRUE(r.rig->write<std::uint32_t>(0, 0x60A9, 0, 0xFD010300U));
    s = r.scale(0, drives::fio_profile(), true);
    ASSERT_TRUE(s) << s.error().message;
    EXPECT_TRUE(s->linear);
    EXPECT_EQ(s->to_position(0.25), 250);
    EXPECT_EQ(s->to_velocity(0.01), 10);

    // Increments (60A8h unit 00h, not SI) are refused with a sentence, not scaled wrongly.
    ASSERT_TRUE(r.rig->write<std::uint32_t>(0, 0x60A8, 0, 0x00000000U));
    s = r.scale(0, drives::fio_profile());
    ASSERT_FALSE(s);
    EXPECT_EQ(s.error().code, drives::DriveErrc::InvalidArgument);
    EXPECT_NE(s.error().message.find("60A8h"), std::string::npos) << s.error().message;
}

TEST(CoeUnits, Akd2gFactorGroupAndDsBvsFixedUnitsReadOverCoe) {
    CoeUnitsRig r;
    ASSERT_TRUE(r.rig->bring_up({"fio", "akd2g", "ds-bvs"}));
    // AKD2G §4.1.4: 6092h:01 = 65536 per revolution; 6096h/6097h exist with 1/1 (§5.4).
    EXPECT_EQ(r.read<std::uint32_t>(1, 0x6096, 1), 1U);
    EXPECT_EQ(r.read<std::uint32_t>(1, 0x6097, 2), 1U);
    auto s = r.scale(1, drives::akd2g_profile());
    ASSERT_TRUE(s) << s.error().message;
    EXPECT_EQ(s->to_position(kPi), 32768);
    EXPECT_EQ(s->to_velocity(100.0 / 60.0 * 2 * kPi), 109227);
    ASSERT_TRUE(r.rig->write<std::uint32_t>(1, 0x6092, 1, 36000));
    ASSERT_TRUE(r.rig->write<std::uint32_t>(1, 0x6096, 1, 60));
    ASSERT_TRUE(r.rig->write<std::uint32_t>(1, 0x6096, 2, 36000));
    s = r.scale(1, drives::akd2g_profile());
    ASSERT_TRUE(s) << s.error().message;
    EXPECT_EQ(s->to_position(kPi), 18000);                  // 0.01°
    EXPECT_EQ(s->to_velocity(100.0 / 60.0 * 2 * kPi), 100); // rpm

    // DS-BVS: fixed units, counts per 608Fh:01 and rpm.
    const auto counts = r.read<std::uint32_t>(2, 0x608F, 1);
    ASSERT_TRUE(counts.has_value());
    s = r.scale(2, drives::ds_bvs_profile());
    ASSERT_TRUE(s) << s.error().message;
    EXPECT_EQ(s->to_position(2 * kPi), static_cast<std::int32_t>(*counts));
    EXPECT_EQ(s->to_velocity(2 * kPi), 60);
}

} // namespace
} // namespace codrive::testing
