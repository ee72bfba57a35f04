// SPDX-License-Identifier: Apache-2.0
// What an independent master (SOEM, docs/ethercat.md "Interop") reads from codrive-ecat-sim,
// asserted through codrive's own master on veth: DL status topology, complete access layout,
// SDO information of the AKD2G's manufacturer objects, the DS-BVS's object names.
#include "veth_segment.hpp"

#include <codrive/core/endian.hpp>
#include <codrive/core/sdo_abort.hpp>
#include <codrive/ethercat/registers.hpp>

#include <fmt/format.h>
#include <fmt/ranges.h>

namespace codrive::testing {
namespace {

using namespace codrive::ethercat;

TEST_F(EcatVethTest, DlStatusShowsTheLineTopology) {
    // ETG.1000.4 §6.1.4: 0x0110 has link/loop/communication per port. A master reads the
    // topology there (SOEM: ports with communication and an open loop are "active"); the
    // simulator once left it 0, so SOEM saw no open port and computed no DC delays.
    start({"--slave", "akd2g", "--slave", "ds-bvs", "--slave", "fio"});
    if (IsSkipped() || HasFatalFailure()) {
        return;
    }
    ASSERT_TRUE(master_->scan()) << master_->last_error();
    ASSERT_EQ(master_->slaves().size(), 3U);
    for (std::size_t i = 0; i < 3; ++i) {
        auto v = master_->read_register<std::uint16_t>(i, reg::kDlStatus);
        ASSERT_TRUE(v) << master_->last_error();
        SCOPED_TRACE(fmt::format("slave {} DL status 0x{:04X}", i, *v));
        EXPECT_NE(*v & dl_status::kPdiOperational, 0);
        EXPECT_NE(*v & dl_status::link(0), 0) << "port 0 faces the master";
        EXPECT_NE(*v & dl_status::communication(0), 0);
        EXPECT_EQ(*v & dl_status::loop_closed(0), 0);
        const bool last = i == 2;
        EXPECT_EQ((*v & dl_status::communication(1)) != 0, !last) << "port 1 to the next slave";
        EXPECT_EQ((*v & dl_status::loop_closed(1)) != 0, last) << "the last slave closes port 1";
        EXPECT_NE(*v & dl_status::loop_closed(2), 0);
        EXPECT_NE(*v & dl_status::loop_closed(3), 0);
    }
}

TEST_F(EcatVethTest, CompleteAccessPadsSubindexZeroTo16Bits) {
    // ETG.1000.6 §5.6.2.1 complete access: the object as its ESI data type lays it out, sub 0
    // (UINT8) at bit 0 and sub 1 at bit 16 (devices/akd2g.xml DT1C12). SOEM reads 1C12h/1C13h
    // this way; with sub 0 as one byte it read PDO 0x0116 and fell back to the SII.
    start({"--slave", "akd2g"});
    if (IsSkipped() || HasFatalFailure()) {
        return;
    }
    ASSERT_TRUE(master_->scan()) << master_->last_error();
    ASSERT_TRUE(master_->set_state_all(AlState::PreOp)) << master_->last_error();
    auto r = master_->sdo_upload(0, 0x1C12, 0, true);
    ASSERT_TRUE(r) << master_->last_error();
    ASSERT_EQ(r->size(), 2U + 2 * 2);
    EXPECT_EQ((*r)[0], 2);
    EXPECT_EQ((*r)[1], 0) << "padding";
    EXPECT_EQ(get_le<std::uint16_t>(r->data() + 2), 0x1600);
    EXPECT_EQ(get_le<std::uint16_t>(r->data() + 4), 0x1601);

    // Download in the same layout: one PDO assigned, read back entry by entry.
    const std::vector<std::uint8_t> one{1, 0, 0x01, 0x16};
    ASSERT_TRUE(master_->sdo_download(0, 0x1C12, 0, one, true)) << master_->last_error();
    EXPECT_EQ(master_->sdo_read<std::uint8_t>(0, 0x1C12, 0).value_or(0), 1);
    EXPECT_EQ(master_->sdo_read<std::uint16_t>(0, 0x1C12, 1).value_or(0), 0x1601);
    // Sub 0 alone, unpadded, is too short.
    const std::vector<std::uint8_t> short_one{0};
    auto w = master_->sdo_download(0, 0x1C12, 0, short_one, true);
    ASSERT_FALSE(w);
    EXPECT_EQ(w.error(), SdoAbort::LengthTooLow);
}

TEST_F(EcatVethTest, Akd2gControlledStopObjectHasEverySubIndexTheManualLists) {
    // AKD2G manual §5.3.82: 5002h/5102h subs 1..5 (CS.STATE, CS.DEC, ZEROT, ZEROV, ZEROACC).
    // A master lists the entry descriptions 1..highest sub-index; a gap was an SDO info error.
    start({"--slave", "akd2g"});
    if (IsSkipped() || HasFatalFailure()) {
        return;
    }
    ASSERT_TRUE(master_->scan()) << master_->last_error();
    ASSERT_TRUE(master_->set_state_all(AlState::PreOp)) << master_->last_error();
    auto o = master_->sdo_info_object(0, 0x5002);
    ASSERT_TRUE(o) << master_->last_error();
    EXPECT_EQ(o->max_subindex, 5);
    EXPECT_EQ(master_->sdo_read<std::uint8_t>(0, 0x5002, 0).value_or(0), 5);
    const char* names[] = {"AXIS1.CS.STATE", "AXIS1.CS.DEC", "AXIS1.ZEROT", "AXIS1.ZEROV",
                           "AXIS1.ZEROACC"};
    const std::uint16_t bits[] = {8, 32, 32, 32, 32};
    for (std::uint8_t s = 1; s <= 5; ++s) {
        auto e = master_->sdo_info_entry(0, 0x5002, s);
        ASSERT_TRUE(e) << master_->last_error();
        EXPECT_EQ(e->name, names[s - 1]);
        EXPECT_EQ(e->bit_length, bits[s - 1]);
    }
    auto axis2 = master_->sdo_info_entry(0, 0x5102, 2);
    ASSERT_TRUE(axis2) << master_->last_error();
    EXPECT_EQ(axis2->name, "AXIS2.CS.DEC");
}

// Every record and array of the simulated drives, as a master that lists the dictionary sees it
// (SOEM's slaveinfo -sdo: object list, object description, entry descriptions, values): sub 0
// (the entries in use) is at most the highest sub-index the object description states, and on
// the AKD2G and the FIO, whose manuals list every entry, each entry up to that has a description
// and a name (FIO 3210h once said 0Ch with entries up to 0Ah only). The DS-BVS manual leaves some
// entries out (docs/conformance.md), so its records may have gaps, as ETG.1000.6 allows.
TEST_F(EcatVethTest, EveryObjectDescribesEachEntryUpToItsHighestSubIndex) {
    start({"--slave", "akd2g", "--slave", "ds-bvs", "--slave", "fio"});
    if (IsSkipped() || HasFatalFailure()) {
        return;
    }
    ASSERT_TRUE(master_->scan()) << master_->last_error();
    ASSERT_TRUE(master_->set_state_all(AlState::PreOp)) << master_->last_error();
    std::vector<std::string> problems;
    for (std::size_t slave = 0; slave < 3; ++slave) {
        auto list = master_->sdo_info_object_list(slave);
        ASSERT_TRUE(list) << master_->last_error();
        const std::string who = master_->slaves()[slave].display_name();
        const bool complete_manual = who != "DS-BVS";
        for (const std::uint16_t index : *list) {
            auto o = master_->sdo_info_object(slave, index);
            if (!o) {
                problems.push_back(
                    fmt::format("{} {:04X}h: {}", who, index, master_->last_error()));
                continue;
            }
            constexpr std::uint8_t kVar = 7; // ETG.1000.6 Table 46 object code VAR
            // FIO 1C32h: §7.13.22 gives sub 0 = 05h with entries 01h..03h (docs/conformance.md).
            if (o->object_code == kVar || (who == "FIO Drive Control" && index == 0x1C32)) {
                continue;
            }
            auto highest = master_->sdo_read<std::uint8_t>(slave, index, 0);
            if (!highest || *highest > o->max_subindex) {
                problems.push_back(fmt::format("{} {:04X}h: sub 0 = {}, object description {}", who,
                                               index, highest ? int{*highest} : -1,
                                               int{o->max_subindex}));
            }
            for (unsigned s = 0; complete_manual && s <= o->max_subindex; ++s) {
                auto e = master_->sdo_info_entry(slave, index, static_cast<std::uint8_t>(s));
                if (!e || e->name.empty() || e->bit_length == 0) {
                    problems.push_back(
                        fmt::format("{} {:04X}:{:02X}: no entry description", who, index, s));
                }
            }
        }
    }
    EXPECT_TRUE(problems.empty()) << fmt::format("{}", fmt::join(problems, "\n"));
}

TEST_F(EcatVethTest, DsBvsNamesAreTheManualsWholeNames) {
    // The DS-BVS manual's table cells wrap ("External Load Torque Feed-" / "Forward Gain"); the
    // names a master lists are the whole names of the section headings (§6.2.52, §6.2.57,
    // §6.2.86.1, §6.2.88.1).
    start({"--slave", "ds-bvs"});
    if (IsSkipped() || HasFatalFailure()) {
        return;
    }
    ASSERT_TRUE(master_->scan()) << master_->last_error();
    ASSERT_TRUE(master_->set_state_all(AlState::PreOp)) << master_->last_error();
    const struct {
        std::uint16_t index;
        std::uint8_t sub;
        const char* name;
    } expected[] = {{0x4209, 0, "Averaged Current (Moving Averaged 10step)"},
                    {0x4311, 0, "External Load Torque Feed-Forward Gain"},
                    {0x6048, 1, "VL Mode Acceleration Delta Speed"},
                    {0x604A, 2, "VL Mode Quick Stop Deceleration Delta Time"}};
    for (const auto& x : expected) {
        auto e = master_->sdo_info_entry(0, x.index, x.sub);
        ASSERT_TRUE(e) << master_->last_error();
        EXPECT_EQ(e->name, x.name);
    }
}

TEST_F(EcatVethTest, InitWithoutAcknowledgeLeavesAnErrorState) {
    // ETG.1000.6 §6.4.1.3: with the error flag set, a request without the acknowledge bit is
    // ignored, except one for INIT. SOEM's ecx_reconfig_slave() writes a plain 0x0001; a slave
    // that ignored it stayed in SAFE-OP + error and SOEM's simple_ng reconfigured it forever.
    start({"--slave", "akd2g", "--refuse", "0:op:0x001A"});
    if (IsSkipped() || HasFatalFailure()) {
        return;
    }
    ASSERT_TRUE(master_->scan()) << master_->last_error();
    ASSERT_FALSE(master_->set_state_all(AlState::Op)); // refused and acknowledged: SAFE-OP
    const auto al_status = [&] {
        auto v = master_->read_register<std::uint16_t>(0, reg::kAlStatus);
        return v ? *v : std::uint16_t{0xFFFF};
    };
    constexpr std::uint16_t kErrorFlag = 0x10;
    ASSERT_TRUE(master_->write_register<std::uint16_t>(0, reg::kAlControl, 0x08)); // OP again
    EXPECT_EQ(al_status(), 0x04 | kErrorFlag) << "refused: SAFE-OP with the error flag";
    ASSERT_TRUE(master_->write_register<std::uint16_t>(0, reg::kAlControl, 0x02)); // PRE-OP
    EXPECT_EQ(al_status(), 0x04 | kErrorFlag) << "PRE-OP without acknowledge is ignored";
    ASSERT_TRUE(master_->write_register<std::uint16_t>(0, reg::kAlControl, 0x01)); // INIT
    EXPECT_EQ(al_status(), 0x01) << "INIT is carried out without acknowledge";
}

} // namespace
} // namespace codrive::testing
