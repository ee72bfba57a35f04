// SPDX-License-Identifier: Apache-2.0
// DS-BVS commissioning (manual §6.2.74 5000h node-ID, §6.2.76 5002h CAN bit rate): written,
// saved, effective after a restart — through the master's library call, on the CAN simulator.
#include "conformance.hpp"

#include <codrive/drives/canopen_transport.hpp>
#include <codrive/drives/commissioning.hpp>

namespace codrive::conformance {
namespace {

drives::DriveVoid run(sim::testing::DeviceFixture& f,
                      const std::function<void(drives::DriveTransport::WriteDone)>& op) {
    std::optional<drives::DriveVoid> out;
    op([&out](drives::DriveVoid r) { out = std::move(r); });
    for (int i = 0; i < 3000 && !out; ++i) {
        f.run_ms(1);
    }
    EXPECT_TRUE(out.has_value());
    return out.value_or(drives::drive_fail(drives::DriveErrc::Timeout, "no completion in 3 s"));
}

TEST(Commissioning, NewNodeIdAndBitRateTakeEffectAfterSaveAndResetNode) {
    CanProbe probe("ds-bvs", 1); // §6.2.74: every drive ships at node 1
    auto& f = probe.fixture();
    drives::CanopenTransport t(f.client);
    const drives::Profile& p = drives::ds_bvs_profile();
    EXPECT_EQ(*f.read<std::uint8_t>(0x5002, 0), 5U) << "§6.2.76 default 5 = 250 kbps";
    auto r = run(f, [&](auto d) { drives::commission_node(t, p, 5, 500, std::move(d)); });
    ASSERT_TRUE(r) << r.error().message;
    EXPECT_EQ(f.device.node(), 1U) << "not before a restart";
    f.frames.clear();
    f.send(Frame::make(0x000, {0x81, 1})); // NMT reset node
    f.run_ms(10);
    EXPECT_EQ(f.device.node(), 5U);
    ASSERT_EQ(f.with_id(0x705).size(), 1U) << "boot-up at the new node-ID";
    EXPECT_EQ(f.with_id(0x705)[0].data[0], 0x00);
    EXPECT_TRUE(f.with_id(0x701).empty()) << "nothing from the old node-ID";
    EXPECT_EQ(f.device.bit_rate_code(), 6U) << "500 kbit/s recorded";

    sdo::SdoClient five(f.master, f.clock, sdo::ClientConfig{.node = 5});
    f.master.set_frame_handler([&](const Frame& fr, TimePoint at) { five.on_frame(fr, at); });
    std::optional<sdo::SdoResult<std::uint8_t>> id;
    five.read<std::uint8_t>(0x5000, 0, [&](sdo::SdoResult<std::uint8_t> v) { id = v; });
    for (int i = 0; i < 1000 && !id; ++i) {
        f.net.run_until(f.clock, f.clock.now() + milliseconds(1), {&f.device, &five});
    }
    ASSERT_TRUE(id && *id);
    EXPECT_EQ(**id, 5U);
}

TEST(Commissioning, UnsupportedBitRateAndADriveWithoutNodeIdObjectAreRefused) {
    CanProbe probe("ds-bvs", 1);
    auto& f = probe.fixture();
    drives::CanopenTransport t(f.client);
    // §6.2.76: 800 kbps "Not supported".
    auto r = run(f, [&](auto d) {
        drives::commission_node(t, drives::ds_bvs_profile(), 5, 800, std::move(d));
    });
    ASSERT_FALSE(r);
    EXPECT_EQ(r.error().message, "node 1 (DS-BVS/BVM servo drive): 800 kbit/s is not supported "
                                 "(it takes: 20, 50, 125, 250, 500, 1000)");
    auto akd = run(f, [&](auto d) {
        drives::commission_node(t, drives::akd2g_profile(), 5, std::nullopt, std::move(d));
    });
    ASSERT_FALSE(akd);
    EXPECT_EQ(akd.error().code, drives::DriveErrc::NotSupported);
}

} // namespace
} // namespace codrive::conformance
