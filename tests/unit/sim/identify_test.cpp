// SPDX-License-Identifier: Apache-2.0
// drives::identify_device() and identify_profile() on a simulated drive's dictionary and on a
// plain CANopen device that is not a drive (CiA 301 §7.5.2.1: 1000h bits 0..15 name the device
// profile; 402 is a drive, 401 an I/O module, 0 no standard profile).
#include "device_test_support.hpp"
#include "od_transport.hpp"

#include <codrive/drives/persistence.hpp>

#include <gtest/gtest.h>

using namespace codrive;
using namespace codrive::sim::testing;

namespace {

/// A CANopen device with 1000h = `device_type`, 1018h:1/:2 and the CiA 301 store/restore
/// objects (sub-index 1: all parameters), the way an I/O module's dictionary has them.
ObjectDictionary plain_device(std::uint32_t device_type) {
    ObjectDictionary od;
    od.add_var(0x1000, "Device type", DataType::Unsigned32, Access::Ro,
               *Value::from_uint(DataType::Unsigned32, device_type));
    for (const auto& [sub, value] : {std::pair<std::uint8_t, std::uint32_t>{1, 0x0000ABCD},
                                     std::pair<std::uint8_t, std::uint32_t>{2, 0x00000042}}) {
        od.add_sub(0x1018,
                   SubObject::make(sub, "Identity", DataType::Unsigned32, Access::Ro,
                                   *Value::from_uint(DataType::Unsigned32, value)),
                   "Identity object");
    }
    od.add_sub(0x1010,
               SubObject::make(1, "Save all parameters", DataType::Unsigned32, Access::Rw,
                               Value::zero(DataType::Unsigned32)),
               "Store parameters");
    return od;
}

TEST(Identify, ASimulatedDriveIsFoundByItsIdentity) {
    DeviceFixture f("ds-bvs");
    OdTransport t(f.device.od());
    auto id = await<drives::DriveResult<drives::DeviceIdentity>>(
        t, [&](auto done) { drives::identify_device(t, done); });
    ASSERT_TRUE(id) << id.error().message;
    EXPECT_TRUE(id->is_drive());
    EXPECT_EQ(id->profile, &drives::ds_bvs_profile());
    EXPECT_EQ(id->label(), drives::ds_bvs_profile().title);
    auto p = await<drives::DriveResult<const drives::Profile*>>(
        t, [&](auto done) { drives::identify_profile(t, done); });
    ASSERT_TRUE(p) << p.error().message;
    EXPECT_EQ(*p, &drives::ds_bvs_profile());
}

TEST(Identify, AnIoModuleIsACanopenDeviceNotADrive) {
    ObjectDictionary od = plain_device(0x00030191); // CiA 401: digital inputs and outputs
    OdTransport t(od);
    auto id = await<drives::DriveResult<drives::DeviceIdentity>>(
        t, [&](auto done) { drives::identify_device(t, done); });
    ASSERT_TRUE(id) << id.error().message;
    EXPECT_FALSE(id->is_drive());
    EXPECT_EQ(id->vendor_id, 0x0000ABCDU);
    EXPECT_EQ(id->product_code, 0x42U);
    EXPECT_EQ(id->device_name, "") << "1008h is optional";
    EXPECT_EQ(id->profile, &drives::canopen_device_profile());
    EXPECT_EQ(id->label(), "CANopen device, device type 00030191h (CiA 401 profile)");

    // A caller that needs a drive gets a sentence, not the generic CiA 402 profile.
    auto p = await<drives::DriveResult<const drives::Profile*>>(
        t, [&](auto done) { drives::identify_profile(t, done); });
    ASSERT_FALSE(p);
    EXPECT_EQ(p.error().code, drives::DriveErrc::NotSupported);
    EXPECT_EQ(p.error().message, "node 7 is not a CiA 402 drive: it is a CANopen device, device "
                                 "type 00030191h (CiA 401 profile)");

    // It still saves its parameters (CiA 301 §7.5.2.13: "save" at 1010h:01).
    auto saved = await<drives::DriveVoid>(
        t, [&](auto done) { drives::store_parameters(t, *id->profile, "all", done); });
    ASSERT_TRUE(saved) << saved.error().message;
    EXPECT_EQ(od.get<std::uint32_t>(0x1010, 1), 0x65766173U);
    auto wrong = await<drives::DriveVoid>(
        t, [&](auto done) { drives::store_parameters(t, *id->profile, "comm", done); });
    ASSERT_FALSE(wrong);
    EXPECT_EQ(wrong.error().message, "node 7 (CANopen device, not a CiA 402 drive): no parameter "
                                     "category 'comm' in 1010h (it has: all)");
}

TEST(Identify, ADeviceTypeOfZeroSaysNoStandardProfile) {
    ObjectDictionary od = plain_device(0);
    OdTransport t(od);
    auto id = await<drives::DriveResult<drives::DeviceIdentity>>(
        t, [&](auto done) { drives::identify_device(t, done); });
    ASSERT_TRUE(id) << id.error().message;
    EXPECT_EQ(id->label(), "CANopen device, device type 00000000h (no standard profile)");
}

TEST(Identify, ADeviceWithout1000hIsATransportError) {
    ObjectDictionary od; // CiA 301 §7.5.2.1: 1000h is mandatory; this device breaks that
    OdTransport t(od);
    auto id = await<drives::DriveResult<drives::DeviceIdentity>>(
        t, [&](auto done) { drives::identify_device(t, done); });
    ASSERT_FALSE(id);
    EXPECT_EQ(id.error().code, drives::DriveErrc::Transport);
    EXPECT_NE(id.error().message.find("1000"), std::string::npos) << id.error().message;
}

} // namespace
