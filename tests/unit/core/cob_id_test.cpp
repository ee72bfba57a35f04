// SPDX-License-Identifier: Apache-2.0
// Predefined connection set classification.
#include <codrive/core/cob_id.hpp>

#include <gtest/gtest.h>

using namespace codrive;

TEST(CobId, ClassifiesEveryFunctionCode) {
    EXPECT_EQ(classify_cob_id(0x000).type, CobType::Nmt);
    EXPECT_EQ(classify_cob_id(0x080).type, CobType::Sync);
    EXPECT_EQ(classify_cob_id(0x084).type, CobType::Emcy);
    EXPECT_EQ(classify_cob_id(0x084).node, 4);
    EXPECT_EQ(classify_cob_id(0x100).type, CobType::Time);
    EXPECT_EQ(classify_cob_id(0x181).type, CobType::Tpdo1);
    EXPECT_EQ(classify_cob_id(0x27F).type, CobType::Rpdo1);
    EXPECT_EQ(classify_cob_id(0x27F).node, 127);
    EXPECT_EQ(classify_cob_id(0x482).type, CobType::Tpdo4);
    EXPECT_EQ(classify_cob_id(0x482).pdo_number(), 4U);
    EXPECT_EQ(classify_cob_id(0x585).type, CobType::SdoTx);
    EXPECT_EQ(classify_cob_id(0x605).type, CobType::SdoRx);
    EXPECT_EQ(classify_cob_id(0x77F).type, CobType::Heartbeat);
    EXPECT_EQ(classify_cob_id(0x7E5).type, CobType::LssMaster);
    EXPECT_EQ(classify_cob_id(0x7E4).type, CobType::LssSlave);
}

TEST(CobId, NodeZeroAndReservedAreUnknown) {
    EXPECT_EQ(classify_cob_id(0x180).type, CobType::Unknown);
    EXPECT_EQ(classify_cob_id(0x680).type, CobType::Unknown);
    EXPECT_EQ(classify_cob_id(0x800).type, CobType::Unknown);
}

TEST(CobId, BuildersMatchTheConnectionSet) {
    EXPECT_EQ(cob::tpdo(2, 5), 0x285U);
    EXPECT_EQ(cob::rpdo(3, 5), 0x405U);
    EXPECT_EQ(cob::sdo_rx(127), 0x67FU);
    EXPECT_EQ(cob::heartbeat(1), 0x701U);
    EXPECT_TRUE(classify_cob_id(cob::tpdo(1, 9)).is_tpdo());
    EXPECT_TRUE(classify_cob_id(cob::rpdo(4, 9)).is_rpdo());
    EXPECT_EQ(to_string(CobType::SdoTx), "SDO-tx");
}
