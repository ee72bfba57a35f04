// SPDX-License-Identifier: Apache-2.0
// Complete access (ETG.1000.6 §5.6.2.1.1) over an ARRAY whose sub-index 0 says 255, the most an
// 8-bit count can hold: every entry is read and written once, and the walk ends.
#include <codrive/sdo/complete_access.hpp>

#include <gtest/gtest.h>

#include <vector>

namespace codrive::sdo {
namespace {

constexpr std::uint16_t kIndex = 0x2200;

ObjectDictionary array_of_255() {
    ObjectDictionary od;
    od.add_sub(kIndex,
               SubObject::make(0, "Highest sub-index supported", DataType::Unsigned8, Access::Rw,
                               Value(DataType::Unsigned8, {255})),
               "Array of 255");
    od.find(kIndex)->code = ObjectCode::Array;
    for (unsigned s = 1; s <= 255; ++s) {
        const auto sub = static_cast<std::uint8_t>(s);
        od.add_sub(kIndex, SubObject::make(sub, "Entry", DataType::Unsigned8, Access::Rw,
                                           Value(DataType::Unsigned8, {sub})));
    }
    return od;
}

TEST(CompleteAccess, AnArrayOf255EntriesIsReadOnceEach) {
    ObjectDictionary od = array_of_255();
    auto r = read_complete(od, kIndex, 0);
    ASSERT_TRUE(r);
    ASSERT_EQ(r->size(), 2U + 255U) << "sub 0 padded to 16 bits, then 255 one-byte entries";
    EXPECT_EQ((*r)[0], 255);
    EXPECT_EQ((*r)[2], 1);
    EXPECT_EQ(r->back(), 255);
}

TEST(CompleteAccess, AnArrayOf255EntriesIsWrittenWholeFromSubIndexZero) {
    ObjectDictionary od = array_of_255();
    std::vector<std::uint8_t> data = {255, 0};
    for (unsigned s = 1; s <= 255; ++s) {
        data.push_back(static_cast<std::uint8_t>(256 - s));
    }
    auto w = write_complete(od, kIndex, 0, data);
    ASSERT_TRUE(w) << "abort 0x" << std::hex << static_cast<std::uint32_t>(w.error());
    EXPECT_EQ(od.get<std::uint8_t>(kIndex, 0), 255);
    EXPECT_EQ(od.get<std::uint8_t>(kIndex, 1), 255);
    EXPECT_EQ(od.get<std::uint8_t>(kIndex, 255), 1);
}

} // namespace
} // namespace codrive::sdo
