// SPDX-License-Identifier: Apache-2.0
// What an independent master (SOEM, docs/ethercat.md "Interop") reads from codrive-ecat-sim,
// asserted through codrive's own master on veth: DL status topology, complete access layout,
// SDO information of the AKD2G's manufacturer objects, the DS-BVS's object names.
#include "veth_segment.hpp"

#include <codrive/core/endian.hpp>
#include <codrive/core/sdo_abort.hpp>
#include <codrive/ethercat/registers.hpp>

#include <fmt/format.h>

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

} // namespace
} // namespace codrive::testing
