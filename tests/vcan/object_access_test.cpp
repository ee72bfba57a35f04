// SPDX-License-Identifier: Apache-2.0
// Controller::read_object()/write_object() on CAN (the SDO side of the transport-neutral object
// access; the CoE side is DemoScenarioOverEthercat.* in tests/ethercat): the demo bus file
// against codrive-sim on vcan0, answers and failures as sentences naming node and object.
#include <codrive/controller/controller.hpp>
#include <codrive/testing/process.hpp>
#include <codrive/testing/vcan.hpp>

#include <gtest/gtest.h>

#include <cstdio>
#include <optional>

using namespace std::chrono_literals;
using codrive::testing::Process;
using codrive::testing::tool_path;

namespace codrive {
namespace {

TEST(VcanObjectAccess, ReadsWritesAndNamesNodeAndObjectOnFailure) {
    CODRIVE_REQUIRE_VCAN("vcan0");
    Process sim(
        {tool_path("codrive-sim"), "-i", "vcan0", "--node", "1:akd2g", "--node", "2:ds-bvs"});
    ASSERT_TRUE(sim.wait_for_output("node 2", 30s)) << sim.output();
    auto made = controller::Controller::from_file(std::string(CODRIVE_SOURCE_DIR) +
                                                  "/vcan-scripts/demo-bus.yml");
    ASSERT_TRUE(made) << made.error().detail;
    auto& c = **made;
    auto started = c.start();
    ASSERT_TRUE(started) << started.error().detail;

    // 1018h:01 of the AKD2G: Kollmorgen's vendor id 0000006Ah, little-endian.
    std::optional<drives::DriveResult<drives::Bytes>> vendor;
    c.read_object(0, 1, 0x1018, 1, [&](auto r) { vendor = std::move(r); });
    EXPECT_FALSE(vendor.has_value()) << "completed inside the call";
    ASSERT_TRUE(c.run_until([&] { return vendor.has_value(); }, 5s));
    ASSERT_TRUE(*vendor) << vendor->error().message;
    ASSERT_EQ((*vendor)->size(), 4U);
    EXPECT_EQ((**vendor)[0], 0x6A);

    // The simulator's fault injection, written by SDO: node 2's axis goes to FAULT.
    drives::Axis* spindle = c.axis(2, 1);
    ASSERT_NE(spindle, nullptr);
    std::optional<drives::DriveVoid> wrote;
    c.write_object(0, 2, 0x2FF0, 2, {1}, [&](auto r) { wrote = r; });
    ASSERT_TRUE(c.run_until([&] { return wrote.has_value(); }, 5s));
    ASSERT_TRUE(*wrote) << wrote->error().message;
    EXPECT_TRUE(c.run_until([&] { return spindle->state() == drives::cia402::State::Fault; }, 5s));

    std::optional<drives::DriveResult<drives::Bytes>> missing;
    c.read_object(0, 1, 0x5FFF, 3, [&](auto r) { missing = std::move(r); });
    ASSERT_TRUE(c.run_until([&] { return missing.has_value(); }, 5s));
    ASSERT_FALSE(*missing);
    std::printf("absent object: %s\n", missing->error().message.c_str());
    EXPECT_NE(missing->error().message.find("node 1"), std::string::npos)
        << missing->error().message;
    EXPECT_NE(missing->error().message.find("5FFF"), std::string::npos) << missing->error().message;

    std::optional<drives::DriveVoid> nobody;
    c.write_object(0, 9, 0x2FF0, 2, {0}, [&](auto r) { nobody = r; });
    ASSERT_TRUE(c.run_until([&] { return nobody.has_value(); }, 1s));
    ASSERT_FALSE(*nobody);
    EXPECT_EQ(nobody->error().code, controller::ControllerErrc::NoSuchDevice);
    EXPECT_EQ(nobody->error().message,
              "write of object 2FF0h:02h: node 9 is not in the bus file of CAN bus 0 (vcan0)");
    c.shutdown();
}

} // namespace
} // namespace codrive
