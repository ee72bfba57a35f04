// SPDX-License-Identifier: Apache-2.0
// PDO layout choice for an axis driven from process data, and the 1C32h/1C33h writes before
// SAFE-OP, against simulated slaves in-process (fake clock).
#include <codrive/drives/profile.hpp>
#include <codrive/ethercat/drive_layout.hpp>
#include <codrive/testing/sim_segment.hpp>

#include <gtest/gtest.h>

#include <algorithm>

namespace codrive::ethercat {
namespace {

using drives::cia402::Mode;

bool maps(const std::vector<PdoMapping>& pdos, std::uint16_t index) {
    for (const auto& m : pdos) {
        for (const auto& e : m.entries) {
            if (e.index == index) {
                return true;
            }
        }
    }
    return false;
}

class DriveLayoutTest : public codrive::testing::SimSegmentTest {
protected:
    DriveLayoutTest() {
        segment_.add(sim::ecat::make_drive_slave("fio", 1));
        segment_.add(sim::ecat::make_drive_slave("akd2g", 2));
        segment_.add(sim::ecat::make_drive_slave("generic", 3));
        segment_.add(sim::ecat::make_drive_slave("generic-nopdo", 4));
    }
    void SetUp() override { bring_up(AlState::PreOp); }
    std::pair<std::vector<PdoMapping>, std::vector<PdoMapping>> assignment(std::size_t slave) {
        auto a = master_.read_pdo_assignment(slave);
        EXPECT_TRUE(a) << master_.last_error();
        return a ? *a : std::pair<std::vector<PdoMapping>, std::vector<PdoMapping>>{};
    }
};

TEST_F(DriveLayoutTest, AKnownDriveUsesItsProfileLayoutForTheMode) {
    const auto a = assignment(1);
    auto pv = choose_layout(drives::akd2g_profile(), 1, Mode::ProfileVelocity, a.first, a.second);
    ASSERT_TRUE(pv) << pv.error();
    EXPECT_EQ(pv->source, LayoutSource::Profile);
    EXPECT_TRUE(maps(pv->rx, 0x6040));
    EXPECT_TRUE(maps(pv->rx, 0x60FF)); // the velocity set-point of PV
    EXPECT_TRUE(maps(pv->tx, 0x6041));
    // Axis 2 of the AKD2G: its objects at +0x800 (manual §2.4.2).
    auto axis2 =
        choose_layout(drives::akd2g_profile(), 2, Mode::ProfilePosition, a.first, a.second);
    ASSERT_TRUE(axis2) << axis2.error();
    EXPECT_TRUE(maps(axis2->rx, 0x6840));
    EXPECT_TRUE(maps(axis2->tx, 0x6841));
    EXPECT_FALSE(maps(axis2->rx, 0x6040));
}

TEST_F(DriveLayoutTest, AnUnknownSlaveKeepsItsOwnAssignmentWhenItHoldsControlAndStatusword) {
    const auto own = assignment(2); // generic: 1600h 6040/6060/607A, 1A00h 6041/6061/6064
    ASSERT_TRUE(holds_controlword_statusword(own.first, own.second, 0x6040, 0x6041));
    auto l =
        choose_layout(drives::generic_profile(), 1, Mode::ProfilePosition, own.first, own.second);
    ASSERT_TRUE(l) << l.error();
    EXPECT_EQ(l->source, LayoutSource::SlaveAssignment);
    EXPECT_TRUE(l->rx.empty()); // nothing to write
}

TEST_F(DriveLayoutTest, AnUnknownSlaveWithoutControlwordGetsTheGenericLayoutThatRunsInOp) {
    const auto none = assignment(3); // generic-nopdo: nothing assigned
    EXPECT_TRUE(none.first.empty());
    auto l =
        choose_layout(drives::generic_profile(), 1, Mode::ProfilePosition, none.first, none.second);
    ASSERT_TRUE(l) << l.error();
    EXPECT_EQ(l->source, LayoutSource::Generic);
    EXPECT_TRUE(maps(l->rx, 0x6040));
    EXPECT_TRUE(maps(l->rx, 0x607A));
    EXPECT_TRUE(maps(l->tx, 0x6041));
    EXPECT_TRUE(maps(l->tx, 0x6064));
    ASSERT_TRUE(master_.configure_pdos(3, l->rx, l->tx)) << master_.last_error();
    ASSERT_TRUE(master_.set_state_all(AlState::Op)) << master_.last_error();
    EXPECT_GE(master_.slaves()[3].output_bytes, 6U);
    EXPECT_GE(master_.slaves()[3].input_bytes, 6U);
}

TEST_F(DriveLayoutTest, AnUnknownSlavesEsiDefaultComesBeforeItsOwnAssignment) {
    const auto own = assignment(2);
    EsiDefaultPdos esi;
    esi.rx = {{0x1601, {{0x6040, 0, 16}, {0x607A, 0, 32}}}};
    esi.tx = {{0x1A01, {{0x6041, 0, 16}, {0x6064, 0, 32}}}};
    auto l = choose_layout(drives::generic_profile(), 1, Mode::ProfilePosition, own.first,
                           own.second, &esi);
    ASSERT_TRUE(l) << l.error();
    EXPECT_EQ(l->source, LayoutSource::Esi);
    ASSERT_EQ(l->rx.size(), 1U);
    EXPECT_EQ(l->rx[0].index, 0x1601);
    EXPECT_EQ(l->tx[0].index, 0x1A01);
    // An ESI default without the statusword is not a CiA 402 layout: the slave's own is kept.
    esi.tx = {{0x1A01, {{0x6064, 0, 32}}}};
    l = choose_layout(drives::generic_profile(), 1, Mode::ProfilePosition, own.first, own.second,
                      &esi);
    ASSERT_TRUE(l) << l.error();
    EXPECT_EQ(l->source, LayoutSource::SlaveAssignment);
    // A drive codrive knows keeps its profile's layout, whatever the file says.
    esi.tx = {{0x1A01, {{0x6041, 0, 16}}}};
    l = choose_layout(drives::fio_profile(), 1, Mode::ProfilePosition, own.first, own.second, &esi);
    ASSERT_TRUE(l) << l.error();
    EXPECT_EQ(l->source, LayoutSource::Profile);
}

SyncSettings sync_at(Duration cycle, bool dc, std::string name = {}) {
    SyncSettings s;
    s.cycle = cycle;
    s.mode = dc ? SyncMode::DcSync0 : SyncMode::FreeRun;
    s.name = std::move(name);
    return s;
}

TEST_F(DriveLayoutTest, SyncObjectsAreWrittenWhereWritableAndTheMinimumCycleRefused) {
    // FIO §7.13.22/§7.13.23: sync type and cycle time writable; the master sets them.
    auto fio = write_sync_objects(master_, 0, sync_at(microseconds(2000), false));
    ASSERT_TRUE(fio) << fio.error();
    EXPECT_EQ(fio->mode, 0U);
    EXPECT_EQ(master_.sdo_read<std::uint32_t>(0, 0x1C32, 2).value_or(0), 2'000'000U);
    EXPECT_EQ(master_.sdo_read<std::uint16_t>(0, 0x1C32, 1).value_or(9), 0U);
    EXPECT_EQ(master_.sdo_read<std::uint16_t>(0, 0x1C33, 1).value_or(9), 0U);
    ASSERT_TRUE(write_sync_objects(master_, 0, sync_at(microseconds(1000), true)));
    EXPECT_EQ(master_.sdo_read<std::uint16_t>(0, 0x1C32, 1).value_or(9), 2U); // DC SYNC0
    EXPECT_EQ(master_.sdo_read<std::uint16_t>(0, 0x1C33, 1).value_or(9), 2U);
    // AKD2G §5.2.50: 250 µs minimum in 1C32h:05; sync type and cycle read-only (left alone).
    auto fast = write_sync_objects(master_, 1, sync_at(microseconds(200), false));
    ASSERT_FALSE(fast);
    EXPECT_EQ(fast.error(), "slave 1 (AKD2G): cycle time 200 µs is shorter than the slave's "
                            "minimum cycle time 250 µs (0x1C32:05)");
    auto named = write_sync_objects(master_, 1, sync_at(microseconds(200), false, "spindle"));
    ASSERT_FALSE(named);
    EXPECT_EQ(named.error(), "slave 1 (AKD2G) \"spindle\": cycle time 200 µs is shorter than "
                             "the slave's minimum cycle time 250 µs (0x1C32:05)");
    auto akd = write_sync_objects(master_, 1, sync_at(microseconds(250), false));
    ASSERT_TRUE(akd) << akd.error();
    EXPECT_EQ(akd->min_cycle_ns, 250'000U);
    EXPECT_EQ(master_.sdo_read<std::uint32_t>(1, 0x1C32, 2).value_or(9), 0U); // untouched
    // What was left alone is said (an info line), not silently skipped.
    ASSERT_FALSE(akd->notes.empty());
    EXPECT_EQ(akd->notes[0], "slave 1 (AKD2G): 0x1C32:01 (output sync mode) is read-only, the "
                             "slave sets it itself; not written");
}

TEST_F(DriveLayoutTest, SmSynchronousModeIsCheckedAgainstTheSupportedSyncModes) {
    SyncSettings sm;
    sm.cycle = microseconds(1000);
    sm.mode = SyncMode::SmSynchronous;
    // FIO §7.13.22: 1C32h:01..03 only, no "sync modes supported": mode 1 is written, and the
    // report says it could not be checked.
    auto fio = write_sync_objects(master_, 0, sm);
    ASSERT_TRUE(fio) << fio.error();
    EXPECT_EQ(fio->mode, 1U);
    EXPECT_EQ(master_.sdo_read<std::uint16_t>(0, 0x1C32, 1).value_or(9), 1U);
    EXPECT_EQ(master_.sdo_read<std::uint16_t>(0, 0x1C33, 1).value_or(9), 1U);
    const std::string unchecked = "slave 0 (FIO Drive Control): has no 0x1C32:04 (sync modes "
                                  "supported); sync mode 1 (SM synchronous) not checked";
    EXPECT_NE(std::find(fio->notes.begin(), fio->notes.end(), unchecked), fio->notes.end());
    // AKD2G §5.2.50: 1C32h:04 = 0x0027 offers SM-synchronous operation.
    auto akd = write_sync_objects(master_, 1, sm);
    ASSERT_TRUE(akd) << akd.error();
    EXPECT_EQ(akd->mode, 1U);
    // A slave that offers free run only refuses mode 1 with a sentence naming it and 1C32h:04.
    const std::array<std::uint8_t, 2> free_only{0x01, 0x00};
    ASSERT_TRUE(segment_.slave(1).app().od().write(0x1C32, 4, free_only, true));
    auto refused = write_sync_objects(master_, 1, sm);
    ASSERT_FALSE(refused);
    EXPECT_EQ(refused.error(),
              "slave 1 (AKD2G): sync mode 1 (SM synchronous) is not among the slave's supported "
              "sync modes (0x1C32:04 = 0x0001: bit 0 free run, bit 1 SM-synchronous, bits 4..2 "
              "DC)");
    EXPECT_EQ(sync_mode_from_string("sm"), SyncMode::SmSynchronous);
    EXPECT_EQ(sync_mode_from_string("dc"), SyncMode::DcSync0);
    EXPECT_EQ(sync_mode_from_string("free"), SyncMode::FreeRun);
    EXPECT_FALSE(sync_mode_from_string("sync1"));
}

} // namespace
} // namespace codrive::ethercat
