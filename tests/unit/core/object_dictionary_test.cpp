// SPDX-License-Identifier: Apache-2.0
// Object dictionary access, length and range checks, hooks and names.
#include <codrive/core/object_dictionary.hpp>

#include <gtest/gtest.h>

using namespace codrive;

namespace {
ObjectDictionary make_od() {
    ObjectDictionary od;
    od.add_var(0x1000, "Device type", DataType::Unsigned32, Access::Ro,
               *Value::from_uint(DataType::Unsigned32, 0x00020192));
    od.add_var(0x6040, "Controlword", DataType::Unsigned16, Access::Rww,
               Value::zero(DataType::Unsigned16), true);
    od.add_var(0x2000, "Secret", DataType::Unsigned8, Access::Wo, Value::zero(DataType::Unsigned8));
    auto count = SubObject::make(0, "Highest sub-index supported", DataType::Unsigned8, Access::Ro,
                                 *Value::from_uint(DataType::Unsigned8, 1));
    od.add_sub(0x1018, count, "Identity object");
    auto vendor = SubObject::make(1, "Vendor-ID", DataType::Unsigned32, Access::Ro,
                                  *Value::from_uint(DataType::Unsigned32, 0x6A));
    od.add_sub(0x1018, vendor);
    auto limited = SubObject::make(0, "Limited", DataType::Integer16, Access::Rw,
                                   Value::zero(DataType::Integer16));
    limited.low_limit = *Value::from_int(DataType::Integer16, -10);
    limited.high_limit = *Value::from_int(DataType::Integer16, 10);
    od.add_sub(0x2001, limited, "Limited");
    return od;
}
} // namespace

TEST(ObjectDictionary, ReadReturnsBytesOrTheRightAbort) {
    auto od = make_od();
    auto v = od.read(0x1018, 1);
    ASSERT_TRUE(v);
    EXPECT_EQ(v->size(), 4U);
    EXPECT_EQ((*v)[0], 0x6A);
    EXPECT_EQ(od.read(0x1234, 0).error(), SdoAbort::NoObject);
    EXPECT_EQ(od.read(0x1018, 9).error(), SdoAbort::NoSubindex);
    EXPECT_EQ(od.read(0x2000, 0).error(), SdoAbort::WriteOnly);
}

TEST(ObjectDictionary, WriteEnforcesAccessLengthAndRange) {
    auto od = make_od();
    const std::uint8_t two[2] = {0x0F, 0x00};
    EXPECT_TRUE(od.write(0x6040, 0, two));
    EXPECT_EQ(od.get<std::uint16_t>(0x6040, 0), 0x000F);
    const std::uint8_t four[4] = {1, 2, 3, 4};
    EXPECT_EQ(od.write(0x1000, 0, four).error(), SdoAbort::ReadOnly);
    EXPECT_EQ(od.write(0x6040, 0, four).error(), SdoAbort::LengthTooHigh);
    const std::uint8_t one[1] = {1};
    EXPECT_EQ(od.write(0x6040, 0, one).error(), SdoAbort::LengthTooLow);
    const std::uint8_t eleven[2] = {11, 0};
    EXPECT_EQ(od.write(0x2001, 0, eleven).error(), SdoAbort::ValueTooHigh);
    const std::uint8_t minus_eleven[2] = {0xF5, 0xFF};
    EXPECT_EQ(od.write(0x2001, 0, minus_eleven).error(), SdoAbort::ValueTooLow);
    EXPECT_TRUE(od.write(0x1000, 0, four, /*force=*/true)) << "local writes bypass access";
}

TEST(ObjectDictionary, WriteHookCanVetoAndSeesData) {
    auto od = make_od();
    int calls = 0;
    od.on_write(0x6040,
                [&](std::uint16_t, std::uint8_t,
                    std::span<const std::uint8_t> d) -> tl::expected<void, SdoAbort> {
                    ++calls;
                    if (d[0] == 0xFF) {
                        return tl::unexpected(SdoAbort::DataTransferState);
                    }
                    return {};
                });
    const std::uint8_t ok[2] = {6, 0};
    const std::uint8_t bad[2] = {0xFF, 0};
    EXPECT_TRUE(od.write(0x6040, 0, ok));
    EXPECT_EQ(od.write(0x6040, 0, bad).error(), SdoAbort::DataTransferState);
    EXPECT_EQ(od.get<std::uint16_t>(0x6040, 0), 6) << "a vetoed write leaves the value";
    EXPECT_EQ(calls, 2);
}

TEST(ObjectDictionary, ReadHookRefreshesValue) {
    auto od = make_od();
    od.on_read(0x1000, [](std::uint16_t, std::uint8_t, SubObject& s) {
        put_le<std::uint32_t>(s.value.mutable_bytes().data(), 42);
    });
    EXPECT_EQ(get_le<std::uint32_t>(od.read(0x1000, 0)->data()), 42U);
}

TEST(ObjectDictionary, PdoDirectionFollowsAccess) {
    auto od = make_od();
    EXPECT_TRUE(od.find(0x6040, 0)->mappable(PdoDir::Rpdo));
    EXPECT_FALSE(od.find(0x6040, 0)->mappable(PdoDir::Tpdo));
    EXPECT_FALSE(od.find(0x1000, 0)->mappable(PdoDir::Tpdo)) << "not flagged mappable";
}

TEST(ObjectDictionary, NamesForMessages) {
    auto od = make_od();
    EXPECT_EQ(od.name_of(0x6040, 0), "Controlword");
    EXPECT_EQ(od.name_of(0x1018, 1), "Identity object.Vendor-ID");
    EXPECT_EQ(od.name_of(0x9999, 0), "");
}
