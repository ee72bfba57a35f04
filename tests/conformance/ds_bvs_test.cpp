// SPDX-License-Identifier: Apache-2.0
// DS-BVS/BVM conformance (manual 003_*.txt, chapter 6.2): the object table and the behaviours
// fixed for issue 15, checked on the CAN simulator over SDO and on the master's profile.
#include "conformance.hpp"

#include <codrive/drives/cia402.hpp>

#include <array>

namespace codrive::conformance {
namespace {

TEST(DsBvsConformance, ObjectTableMatchesTheManual) {
    CanProbe can("ds-bvs");
    EcatProbe ecat("ds-bvs");
    check_facts("ds-bvs", drives::ds_bvs_profile(), &can, &ecat, DeviceFiles::of("ds-bvs"),
                ds_bvs_facts(), ds_bvs_known());
}

TEST(DsBvsConformance, SupportedHomingMethodsInTheManualsOrder60E3h) {
    // §6.2.140: sub 01h..07h = 17, 18, 23, 27, 37, -3, -4; the master's list is the same.
    const std::array<std::int8_t, 7> manual{17, 18, 23, 27, 37, -3, -4};
    const auto listed = drives::ds_bvs_profile().homing_methods;
    ASSERT_EQ(listed.size(), manual.size());
    EXPECT_TRUE(std::equal(listed.begin(), listed.end(), manual.begin()));
    CanProbe probe("ds-bvs");
    auto& f = probe.fixture();
    EXPECT_EQ(*f.read<std::uint8_t>(0x60E3, 0), 7U);
    for (std::uint8_t i = 0; i < manual.size(); ++i) {
        EXPECT_EQ(*f.read<std::int16_t>(0x60E3, static_cast<std::uint8_t>(i + 1)), manual[i])
            << "sub " << int(i + 1);
    }
}

TEST(DsBvsConformance, VelocityWindow606DhTakesAFourByteWrite) {
    // §6.2.104: UNSIGNED32, range 0..4294967295.
    CanProbe probe("ds-bvs");
    auto& f = probe.fixture();
    ASSERT_TRUE(f.write<std::uint32_t>(0x606D, 0, 100000U));
    EXPECT_EQ(*f.read<std::uint32_t>(0x606D, 0), 100000U);
    const auto two = f.write<std::uint16_t>(0x606D, 0, 40);
    ASSERT_FALSE(two);
    // 06070010h length mismatch or its specific form 06070013h (length too low).
    EXPECT_EQ(two.error().abort_code().value_or(0) & 0xFFFFFFF0U, 0x06070010U);
}

TEST(DsBvsConformance, AbortConnectionOption6007hRefusesReservedValue1) {
    // §6.2.78: 0 no action, 1 reserved, 2 disable voltage, 3 quick stop, 4.. reserved.
    CanProbe probe("ds-bvs");
    auto& f = probe.fixture();
    const auto one = f.write<std::int16_t>(0x6007, 0, 1);
    ASSERT_FALSE(one);
    EXPECT_EQ(one.error().abort_code(), 0x06090030U);
    EXPECT_EQ(*f.read<std::int16_t>(0x6007, 0), 0) << "the refused value is not stored";
    for (const std::int16_t v : {std::int16_t{0}, std::int16_t{2}, std::int16_t{3}}) {
        EXPECT_TRUE(f.write<std::int16_t>(0x6007, 0, v)) << v;
    }
    const auto four = f.write<std::int16_t>(0x6007, 0, 4);
    ASSERT_FALSE(four);
}

TEST(DsBvsConformance, HaltOption605Dh0DisablesTheDriveFunction) {
    // §6.2.92: 0 = disable drive function: with halt set the motor gets no torque and coasts;
    // the drive stays in operation enabled.
    CanProbe probe("ds-bvs");
    auto& f = probe.fixture();
    ASSERT_TRUE(f.write<std::int16_t>(0x605D, 0, 0));
    ASSERT_TRUE(f.write<std::int32_t>(0x60FF, 0, 1000)); // PV (default mode 3), 1000 rpm
    for (const int cw : {0x06, 0x07, 0x0F}) {
        ASSERT_TRUE(f.write<std::uint16_t>(0x6040, 0, static_cast<std::uint16_t>(cw)));
        f.run_ms(5);
    }
    f.run_ms(1500);
    ASSERT_GT(*f.read<std::int32_t>(0x606C, 0), 500) << "running before the halt";
    ASSERT_TRUE(f.write<std::uint16_t>(0x6040, 0, 0x010F)); // halt
    f.run_ms(20);
    EXPECT_EQ(*f.read<std::int16_t>(0x6077, 0), 0) << "no torque: the drive function is off";
    EXPECT_EQ(*f.read<std::uint16_t>(0x6041, 0) & 0x6F, 0x27) << "still operation enabled";
}

TEST(DsBvsConformance, Restore1011hOnlyInPreOperationalWithPowerDisabled) {
    // §6.2.7: restoring "can be performed only in the NMT state [Pre-Operational] and device
    // state [Power Disable]".
    constexpr std::uint32_t kLoad = 0x64616F6C; // "load"
    CanProbe probe("ds-bvs");
    auto& f = probe.fixture();
    for (const int cw : {0x06, 0x07}) {
        ASSERT_TRUE(f.write<std::uint16_t>(0x6040, 0, static_cast<std::uint16_t>(cw)));
        f.run_ms(5);
    }
    const auto powered = f.write<std::uint32_t>(0x1011, 1, kLoad);
    ASSERT_FALSE(powered) << "switched on: power enabled";
    EXPECT_EQ(powered.error().abort_code(), 0x08000022U);
    ASSERT_TRUE(f.write<std::uint16_t>(0x6040, 0, 0x00)); // disable voltage
    f.run_ms(5);
    EXPECT_TRUE(f.write<std::uint32_t>(0x1011, 1, kLoad));
    f.send(Frame::make(0x000, {0x01, 1})); // NMT start: operational
    const auto operational = f.write<std::uint32_t>(0x1011, 1, kLoad);
    ASSERT_FALSE(operational);
    EXPECT_EQ(operational.error().abort_code(), 0x08000022U);
}

TEST(DsBvsConformance, PdoMapsAreNotSavedBy1010h) {
    // §6.2.14-§6.2.17: every PDO mapping object is "Backup NO"; a saved parameter (6065h,
    // "Backup YES") survives the reset, the map does not.
    constexpr std::uint32_t kSave = 0x65766173; // "save"
    CanProbe probe("ds-bvs");
    auto& f = probe.fixture();
    ASSERT_TRUE(f.write<std::uint32_t>(0x1600, 1, 0x60400010));
    ASSERT_TRUE(f.write<std::uint8_t>(0x1600, 0, 1));
    ASSERT_TRUE(f.write<std::uint32_t>(0x6065, 0, 1234));
    ASSERT_TRUE(f.write<std::uint32_t>(0x1010, 1, kSave));
    f.send(Frame::make(0x000, {0x81, 1})); // NMT reset node
    f.run_ms(10);
    EXPECT_EQ(*f.read<std::uint8_t>(0x1600, 0), 0U);
    EXPECT_EQ(*f.read<std::uint32_t>(0x6065, 0), 1234U);
}

TEST(DsBvsConformance, ModesTheSimulatorCannotRunAreRefusedLikeUnsupportedValues) {
    // §6.2.94 lists -12 (CRM) and -128 (MSM); the simulator does not run them, so 6060h
    // refuses them with 06090030h instead of accepting and ignoring them.
    CanProbe probe("ds-bvs");
    auto& f = probe.fixture();
    for (const std::int8_t mode : {std::int8_t{-12}, std::int8_t{-128}}) {
        const auto r = f.write<std::int8_t>(0x6060, 0, mode);
        ASSERT_FALSE(r) << int(mode);
        EXPECT_EQ(r.error().abort_code(), 0x06090030U) << int(mode);
    }
    EXPECT_EQ(*f.read<std::int8_t>(0x6060, 0), 3);
    EXPECT_TRUE(f.write<std::int8_t>(0x6060, 0, -8)) << "PRM runs as CSP";
}

TEST(DsBvsConformance, OneIdentityOnCanAndEtherCat1018h) {
    // §6.2.11: the manual gives no vendor ID or product code; the simulator's placeholders
    // are one pair, the same on both buses.
    CanProbe can("ds-bvs");
    EcatProbe ecat("ds-bvs");
    for (const std::uint8_t sub : {std::uint8_t{1}, std::uint8_t{2}, std::uint8_t{3}}) {
        const Reply c = can.upload(0x1018, sub);
        const Reply e = ecat.upload(0x1018, sub);
        ASSERT_TRUE(c.ok && e.ok) << "sub " << int(sub);
        EXPECT_EQ(c.data, e.data) << "1018h:" << int(sub);
    }
    const auto& sii = ecat.master().slaves().at(0).sii;
    EXPECT_EQ(sii.vendor_id, get_le<std::uint32_t>(can.upload(0x1018, 1).data.data()));
    EXPECT_EQ(sii.product_code, get_le<std::uint32_t>(can.upload(0x1018, 2).data.data()));
}

} // namespace
} // namespace codrive::conformance
