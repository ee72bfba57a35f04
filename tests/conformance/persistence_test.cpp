// SPDX-License-Identifier: Apache-2.0
// Parameter persistence (1010h/1011h) through the master's library calls, against the simulated
// drives: saved values survive reset node, restored defaults come back at the next reset
// (AKD2G §5.2.11/§5.2.12, DS-BVS §6.2.6/§6.2.7, FIO §7.12.4 and §7.13.7/§7.13.8).
#include "conformance.hpp"

#include <codrive/drives/canopen_transport.hpp>
#include <codrive/drives/persistence.hpp>
#include <codrive/ethercat/coe_transport.hpp>

namespace codrive::conformance {
namespace {

/// Runs one library call on the CAN fixture until it completes.
drives::DriveVoid run_can(sim::testing::DeviceFixture& f,
                          const std::function<void(drives::DriveTransport::WriteDone)>& op) {
    std::optional<drives::DriveVoid> out;
    op([&out](drives::DriveVoid r) { out = std::move(r); });
    for (int i = 0; i < 3000 && !out; ++i) {
        f.run_ms(1);
    }
    EXPECT_TRUE(out.has_value());
    return out ? std::move(*out)
               : drives::drive_fail(drives::DriveErrc::Timeout, "no completion in 3 s");
}

void reset_node(sim::testing::DeviceFixture& f, NodeId node) {
    f.send(Frame::make(0x000, {0x81, node})); // NMT reset node (CiA 301 §7.2.8.3.1)
    f.run_ms(10);
}

TEST(Persistence, SavedValueSurvivesResetNodeAndRestoredDefaultReturnsAfterTheNextReset) {
    // DS-BVS §6.2.6: "save" stores all parameters; §6.2.7: "load" restores the defaults,
    // "valid only after the device is reset or power cycled".
    // Node 1, where the drive ships (§6.2.74): restoring all defaults also brings 5000h back to 1.
    CanProbe probe("ds-bvs", 1);
    auto& f = probe.fixture();
    const drives::Profile& p = drives::ds_bvs_profile();
    drives::CanopenTransport t(f.client);
    const std::uint32_t factory = *f.read<std::uint32_t>(0x6065, 0);
    ASSERT_TRUE(f.write<std::uint32_t>(0x6065, 0, factory + 1000));
    reset_node(f, 1);
    EXPECT_EQ(*f.read<std::uint32_t>(0x6065, 0), factory) << "not saved: reset loses it";

    ASSERT_TRUE(f.write<std::uint32_t>(0x6065, 0, factory + 1000));
    auto saved = run_can(f, [&](auto d) { drives::store_parameters(t, p, "all", std::move(d)); });
    ASSERT_TRUE(saved) << saved.error().message;
    reset_node(f, 1);
    EXPECT_EQ(*f.read<std::uint32_t>(0x6065, 0), factory + 1000) << "saved: kept";

    auto restored =
        run_can(f, [&](auto d) { drives::restore_default_parameters(t, p, "all", std::move(d)); });
    ASSERT_TRUE(restored) << restored.error().message;
    EXPECT_EQ(*f.read<std::uint32_t>(0x6065, 0), factory + 1000) << "defaults wait for a reset";
    reset_node(f, 1);
    EXPECT_EQ(*f.read<std::uint32_t>(0x6065, 0), factory) << "default back after the reset";
}

TEST(Persistence, DsBvsRestoreWhilePoweredIsRefusedWithTheDrivesAbortAndTheRule) {
    CanProbe probe("ds-bvs", 4);
    auto& f = probe.fixture();
    drives::CanopenTransport t(f.client);
    for (const int cw : {0x06, 0x07}) {
        ASSERT_TRUE(f.write<std::uint16_t>(0x6040, 0, static_cast<std::uint16_t>(cw)));
        f.run_ms(5);
    }
    auto r = run_can(f, [&](auto d) {
        drives::restore_default_parameters(t, drives::ds_bvs_profile(), "all", std::move(d));
    });
    ASSERT_FALSE(r);
    EXPECT_NE(r.error().message.find("08000022"), std::string::npos) << r.error().message;
    EXPECT_NE(r.error().message.find("pre-operational with the power stage disabled"),
              std::string::npos)
        << r.error().message;
}

TEST(Persistence, DsBvsRestoreOfAllDefaultsBringsTheDriveBackToNode1) {
    // §6.2.74: 5000h is a saved parameter with default 1; restoring the defaults resets it.
    CanProbe probe("ds-bvs", 4);
    auto& f = probe.fixture();
    drives::CanopenTransport t(f.client);
    auto r = run_can(f, [&](auto d) {
        drives::restore_default_parameters(t, drives::ds_bvs_profile(), "all", std::move(d));
    });
    ASSERT_TRUE(r) << r.error().message;
    f.frames.clear();
    reset_node(f, 4);
    EXPECT_EQ(f.with_id(0x701).size(), 1U) << "boot-up at node 1";
    EXPECT_TRUE(f.with_id(0x704).empty());
}

TEST(Persistence, PdoMapsAreNotSavedWhereTheDriveSaysBackupNo) {
    // DS-BVS §6.2.14-§6.2.17 "Backup NO", AKD2G §5.2.11 "1600h to 1603h and 1A00h to 1A03h are
    // not saved"; FIO §7.12.4.3 saves them in the communication category.
    const drives::StoreCategory& all = *drives::ds_bvs_profile().store_category("all");
    EXPECT_FALSE(drives::ds_bvs_profile().saves(all, 0x1600));
    EXPECT_TRUE(drives::ds_bvs_profile().saves(all, 0x6065));
    EXPECT_FALSE(drives::akd2g_profile().saves(all, 0x1A03));
    const drives::Profile& fio = drives::fio_profile();
    EXPECT_TRUE(fio.saves(*fio.store_category("comm"), 0x1600));
    EXPECT_FALSE(fio.saves(*fio.store_category("app"), 0x1600));
    EXPECT_TRUE(fio.saves(*fio.store_category("all"), 0x1600)) << "all = every category";
    EXPECT_FALSE(fio.saves(*fio.store_category("all"), 0x6040)) << "§7.12.4.2 control words";
}

TEST(Persistence, ACategoryTheDriveDoesNotHaveIsRefusedNamingTheOnesItHas) {
    CanProbe probe("ds-bvs", 4);
    auto& f = probe.fixture();
    drives::CanopenTransport t(f.client);
    auto r = run_can(f, [&](auto d) {
        drives::store_parameters(t, drives::ds_bvs_profile(), "comm", std::move(d));
    });
    ASSERT_FALSE(r);
    EXPECT_EQ(r.error().code, drives::DriveErrc::InvalidArgument);
    EXPECT_EQ(r.error().message, "node 4 (DS-BVS/BVM servo drive): no parameter category 'comm' in "
                                 "1010h (it has: all)");
}

TEST(Persistence, FioSavesPerCategoryOverCoeAndRestartsAfterRestore) {
    // §7.12.4.15: a save on one category stores only its objects, 1010h:n reads 1 afterwards;
    // §7.12.4.16: 1011h discards a category's saved data and the unit restarts.
    EcatProbe probe("fio");
    ethercat::CoeTransport t(probe.master(), 0);
    const drives::Profile& p = drives::fio_profile();
    auto run = [&](const std::function<void(drives::DriveTransport::WriteDone)>& op) {
        std::optional<drives::DriveVoid> out;
        op([&out](drives::DriveVoid r) { out = std::move(r); });
        for (int i = 0; i < 10 && !out; ++i) {
            t.poll();
        }
        EXPECT_TRUE(out.has_value());
        return out.value_or(drives::drive_fail(drives::DriveErrc::Timeout, "no completion"));
    };
    auto restart = [&] {
        // The simulated unit restarts 100 ms after the answer; the master brings it back.
        probe.clock().advance(milliseconds(200));
        probe.master().poll_mailboxes();
        auto st = probe.master().read_al_status(0);
        ASSERT_TRUE(st);
        EXPECT_EQ(st->state, ethercat::AlState::Init) << "the unit restarted";
        ASSERT_TRUE(probe.master().request_state(0, ethercat::AlState::PreOp))
            << probe.master().last_error();
    };
    auto u32 = [&](std::uint16_t index, std::uint8_t sub) {
        const Reply r = probe.upload(index, sub);
        EXPECT_TRUE(r.ok && r.data.size() == 4) << std::hex << index;
        return r.ok && r.data.size() == 4 ? get_le<std::uint32_t>(r.data.data()) : 0xFFFFFFFFU;
    };
    const Reply highest = probe.upload(0x1010, 0);
    ASSERT_TRUE(highest.ok && highest.data.size() == 1);
    EXPECT_EQ(highest.data[0], 0x0DU);
    EXPECT_EQ(u32(0x1010, 3), 0U) << "§7.13.7 default 0 before a save";
    ASSERT_TRUE(probe.write<std::uint32_t>(0x6065, 0, 4321).ok); // application category
    ASSERT_TRUE(probe.write<std::uint32_t>(0x3202, 0, 1).ok);    // drive category
    auto saved = run([&](auto d) { drives::store_parameters(t, p, "app", std::move(d)); });
    ASSERT_TRUE(saved) << saved.error().message;
    EXPECT_EQ(u32(0x1010, 3), 1U) << "§7.12.4.15: 1 once saved";
    EXPECT_EQ(u32(0x1010, 5), 0U) << "drive category not saved";

    // Restoring the (unsaved) drive category restarts the unit: 6065h kept, 3202h default.
    auto drive =
        run([&](auto d) { drives::restore_default_parameters(t, p, "drive", std::move(d)); });
    ASSERT_TRUE(drive) << drive.error().message;
    restart();
    EXPECT_EQ(u32(0x6065, 0), 4321U);
    EXPECT_EQ(u32(0x3202, 0), 0U);

    auto app = run([&](auto d) { drives::restore_default_parameters(t, p, "app", std::move(d)); });
    ASSERT_TRUE(app) << app.error().message;
    restart();
    EXPECT_EQ(u32(0x6065, 0), 256U) << "§7.13 6065h default after the restart";
}

} // namespace
} // namespace codrive::conformance
