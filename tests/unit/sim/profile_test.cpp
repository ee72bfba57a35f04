// SPDX-License-Identifier: Apache-2.0
// The simulated drive models build on the drives/ profiles: identity, homing methods, EMCY codes.
#include <codrive/drives/profile.hpp>
#include <codrive/sim/profile.hpp>

#include <gtest/gtest.h>

using namespace codrive;

namespace {

class SimProfileOf : public ::testing::TestWithParam<const char*> {};

TEST_P(SimProfileOf, UsesTheDriveProfileOfTheSameName) {
    const sim::SimProfile* s = sim::find_profile(GetParam());
    ASSERT_NE(s, nullptr);
    EXPECT_EQ(s->drive, drives::find_profile(GetParam()));
    EXPECT_EQ(s->name(), GetParam());
}

TEST_P(SimProfileOf, SimulatedUnitIdentityIsRecognisedByTheMaster) {
    const sim::SimProfile* s = sim::find_profile(GetParam());
    ASSERT_NE(s, nullptr);
    const std::uint32_t product = s->identity_product_code(s->max_axes());
    EXPECT_EQ(
        drives::match_identity(s->device_type(), s->identity_vendor_id(), product, s->device_name),
        s->drive);
    EXPECT_EQ(s->drive->axes_from_product_code(product), s->max_axes());
}

TEST_P(SimProfileOf, EveryHomingMethodOfTheProfileHasASimulatedBehaviour) {
    const sim::SimProfile* s = sim::find_profile(GetParam());
    ASSERT_NE(s, nullptr);
    for (const std::int8_t m : s->drive->homing_methods) {
        const sim::HomingMethod* h = s->find_homing(m);
        ASSERT_NE(h, nullptr) << "method " << int(m);
        EXPECT_EQ(h->method, m);
    }
    EXPECT_NE(s->find_homing(s->default_homing_method), nullptr);
}

TEST_P(SimProfileOf, InjectedFaultsRaiseProfileCodesWithTheVendorText) {
    const sim::SimProfile* s = sim::find_profile(GetParam());
    ASSERT_NE(s, nullptr);
    for (auto k :
         {sim::FaultKind::Sto, sim::FaultKind::OverCurrent, sim::FaultKind::FollowingError}) {
        const sim::FaultCode c = s->code_for(k);
        EXPECT_NE(s->drive->fault(c.emcy), nullptr) << to_string(k);
        EXPECT_EQ(c.text, s->drive->fault_text(c.emcy)) << to_string(k);
        EXPECT_NE(c.error_register & 0x01, 0) << "generic error bit";
    }
}

INSTANTIATE_TEST_SUITE_P(Builtin, SimProfileOf, ::testing::Values("akd2g", "ds-bvs", "fio"));

TEST(SimProfile, HomingMethodOutsideTheProfileIsRejected) {
    const sim::SimProfile* s = sim::find_profile("ds-bvs");
    ASSERT_NE(s, nullptr);
    EXPECT_EQ(s->find_homing(35), nullptr) << "DS-BVS uses 37, not 35";
    EXPECT_NE(s->find_homing(37), nullptr);
}

TEST(SimProfile, OptionCodeDefaultsComeFromTheDriveProfile) {
    const sim::SimProfile* s = sim::find_profile("ds-bvs");
    ASSERT_NE(s, nullptr);
    EXPECT_EQ(s->quick_stop_default(), 6);
    EXPECT_EQ(s->object_default(0x605D, 0, -1), 1);
    EXPECT_EQ(s->object_default(0x1234, 0, -1), -1);
}

} // namespace
