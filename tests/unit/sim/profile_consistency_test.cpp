// SPDX-License-Identifier: Apache-2.0
// The simulator's drive models agree with the master-side drive profiles (codrive::drives).
#include <codrive/drives/profile.hpp>
#include <codrive/sim/profile.hpp>

#include <gtest/gtest.h>

#include <algorithm>

using namespace codrive;

namespace {

class ProfileConsistency : public ::testing::TestWithParam<const char*> {};

} // namespace

TEST_P(ProfileConsistency, IdentityModesHomingAndFaultCodesMatch) {
    const sim::SimProfile* s = sim::find_profile(GetParam());
    const drives::Profile* d = drives::find_profile(GetParam());
    ASSERT_NE(s, nullptr);
    ASSERT_NE(d, nullptr);
    const std::uint32_t product = s->max_axes > 1 ? s->product_code_2_axes : s->product_code_1_axis;
    EXPECT_EQ(drives::match_identity(s->device_type, s->vendor_id, product, s->device_name), d)
        << "the master recognises the simulated drive";
    EXPECT_EQ(s->supported_modes, d->supported_modes);
    EXPECT_EQ(s->axis_offset == 0x800 || s->max_axes == 1, true);
    EXPECT_EQ(s->max_axes, d->max_axes);
    for (std::int8_t m : s->accepted_modes) {
        EXPECT_TRUE(d->supports_mode(m)) << "mode " << int(m);
    }
    std::vector<std::int8_t> sim_methods;
    for (const auto& m : s->homing_methods) {
        sim_methods.push_back(m.method);
    }
    std::vector<std::int8_t> drv_methods(d->homing_methods.begin(), d->homing_methods.end());
    std::sort(sim_methods.begin(), sim_methods.end());
    std::sort(drv_methods.begin(), drv_methods.end());
    EXPECT_EQ(sim_methods, drv_methods);
    std::vector<std::int16_t> qs(d->quick_stop_options.begin(), d->quick_stop_options.end());
    std::sort(qs.begin(), qs.end());
    EXPECT_EQ(s->quick_stop_options, qs);
    EXPECT_EQ(s->quick_stop_default, d->default_quick_stop_option);
    for (const sim::FaultCode* c : {&s->over_current, &s->following_error}) {
        EXPECT_FALSE(d->fault_text(c->emcy).empty()) << std::hex << c->emcy;
    }
}

INSTANTIATE_TEST_SUITE_P(Sim, ProfileConsistency, ::testing::Values("akd2g", "ds-bvs", "fio"));
