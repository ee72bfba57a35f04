// SPDX-License-Identifier: Apache-2.0
// A PDO assignment (1C12h/1C13h) whose sub-index 0 says 255, the most an 8-bit count holds
// (ETG.1000.6 §5.6.7.4): the master reads every entry once and the read ends, and the simulated
// ESC sizes its process data from it and answers the next state request.
#include <codrive/testing/sim_segment.hpp>

#include <gtest/gtest.h>

#include <string>

namespace codrive::ethercat {
namespace {

using sim::ecat::make_drive_slave;

class PdoCountLimit : public codrive::testing::SimSegmentTest {
protected:
    PdoCountLimit() { segment_.add(make_drive_slave("akd2g", 1)); }
};

// Before the loop counter was wider than the count, sub-index 255 was followed by sub-index 0:
// here the read then failed (one byte where a PDO number was expected); a slave that answers any
// sub-index with two bytes kept it going forever, its list growing.
TEST_F(PdoCountLimit, TheMasterReadsAnAssignmentOf255PdosOnceEach) {
    bring_up(AlState::PreOp);
    ObjectDictionary& od = segment_.slave(0).app().od();
    const auto first = od.get<std::uint16_t>(0x1C12, 1);
    ASSERT_TRUE(first);
    for (unsigned s = 2; s <= 255; ++s) {
        od.add_sub(0x1C12,
                   SubObject::make(static_cast<std::uint8_t>(s), "PDO", DataType::Unsigned16,
                                   Access::Rw, Value(DataType::Unsigned16, {0, 0})));
        ASSERT_TRUE(od.set<std::uint16_t>(0x1C12, static_cast<std::uint8_t>(s), *first));
    }
    ASSERT_TRUE(od.set<std::uint8_t>(0x1C12, 0, 255));
    auto assignment = master_.read_pdo_assignment(0);
    ASSERT_TRUE(assignment) << master_.last_error();
    ASSERT_EQ(assignment->first.size(), 255U);
    EXPECT_EQ(assignment->first.back().index, *first);
    EXPECT_EQ(assignment->first.back().entries.size(), assignment->first.front().entries.size());
}

// A master that writes 255 into 1C12h:00 and asks for SAFE-OP gets an answer: before, the ESC
// counted the PDOs with an 8-bit counter and never left the count. The manual gives 1C12h:00 no
// range (AKD2G §5.2.48), so the download is taken; sub-indices past the assigned PDOs hold none
// (11 to 255 do not exist), so the outputs keep their size and SAFE-OP is reached.
TEST_F(PdoCountLimit, AnAssignmentCountOf255IsAnsweredByTheEsc) {
    bring_up(AlState::PreOp);
    ASSERT_TRUE(master_.map_process_data()) << master_.last_error();
    const std::uint8_t count = 255;
    ASSERT_TRUE(master_.sdo_download(0, 0x1C12, 0, std::span<const std::uint8_t>(&count, 1)))
        << master_.last_error();
    EXPECT_TRUE(master_.request_state(0, AlState::SafeOp)) << master_.last_error();
    EXPECT_EQ(segment_.slave(0).state(), AlState::SafeOp);
}

} // namespace
} // namespace codrive::ethercat
