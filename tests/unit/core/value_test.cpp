// SPDX-License-Identifier: Apache-2.0
// Value parsing, range checks and text.
#include <codrive/core/value.hpp>

#include <gtest/gtest.h>

using namespace codrive;

TEST(Value, ParsesDecimalHexAndNegative) {
    auto v = Value::parse(DataType::Unsigned8, "0x1A");
    ASSERT_TRUE(v);
    EXPECT_EQ(v->as_uint(), 0x1AU);
    auto s = Value::parse(DataType::Integer32, "-5");
    ASSERT_TRUE(s);
    EXPECT_EQ(s->as_int(), -5);
    EXPECT_EQ(s->to_string(), "-5");
    auto hex_signed = Value::parse(DataType::Integer16, "0xFFFF");
    ASSERT_TRUE(hex_signed);
    EXPECT_EQ(hex_signed->as_int(), -1) << "hex text is a bit pattern for signed types";
}

TEST(Value, RejectsOutOfRangeWithClearError) {
    auto v = Value::parse(DataType::Unsigned8, "256");
    ASSERT_FALSE(v);
    EXPECT_EQ(v.error(), CoreErrc::OutOfRange);
    EXPECT_EQ(Value::parse(DataType::Integer8, "-129").error(), CoreErrc::OutOfRange);
    EXPECT_EQ(Value::parse(DataType::Unsigned16, "-1").error(), CoreErrc::OutOfRange);
    EXPECT_EQ(Value::parse(DataType::Unsigned32, "12abc").error(), CoreErrc::ParseError);
    EXPECT_EQ(Value::parse(DataType::Boolean, "2").error(), CoreErrc::OutOfRange);
    EXPECT_EQ(Value::parse(DataType::Unsigned64, "0x1FFFFFFFFFFFFFFFF").error(),
              CoreErrc::ParseError);
}

TEST(Value, RealsAndBooleans) {
    auto f = Value::parse(DataType::Real32, "1.5");
    ASSERT_TRUE(f);
    EXPECT_EQ(f->to_string(), "1.5");
    EXPECT_EQ(f->size(), 4U);
    auto d = Value::parse(DataType::Real64, "-2.25");
    ASSERT_TRUE(d);
    EXPECT_DOUBLE_EQ(*d->as_double(), -2.25);
    EXPECT_EQ(Value::parse(DataType::Real32, "abc").error(), CoreErrc::ParseError);
    EXPECT_EQ(Value::parse(DataType::Boolean, "true")->as_uint(), 1U);
}

TEST(Value, StringsAndOctets) {
    auto s = Value::parse(DataType::VisibleString, "AKD2G-S-DUAL");
    ASSERT_TRUE(s);
    EXPECT_EQ(s->size(), 12U);
    EXPECT_EQ(s->to_string(), "AKD2G-S-DUAL");
    auto o = Value::parse(DataType::OctetString, "01 02 ab");
    ASSERT_TRUE(o);
    EXPECT_EQ(o->to_string(), "01 02 AB");
    EXPECT_EQ(Value::parse(DataType::Domain, "0102AB")->size(), 3U);
    EXPECT_FALSE(Value::parse(DataType::OctetString, "0 1"));
}

TEST(Value, OddWidthIntegers) {
    auto v = Value::parse(DataType::Integer24, "-1");
    ASSERT_TRUE(v);
    EXPECT_EQ(v->size(), 3U);
    EXPECT_EQ(v->as_int(), -1);
    EXPECT_FALSE(Value::parse(DataType::Unsigned24, "0x1000000"));
    EXPECT_EQ(Value::parse(DataType::Unsigned48, "0xFFFFFFFFFFFF")->as_uint(), 0xFFFFFFFFFFFFULL);
}

TEST(Value, TypeNames) {
    EXPECT_EQ(data_type_from_name("u32"), DataType::Unsigned32);
    EXPECT_EQ(data_type_from_name("UNSIGNED32"), DataType::Unsigned32);
    EXPECT_EQ(data_type_from_name("str"), DataType::VisibleString);
    EXPECT_EQ(data_type_from_name("f64"), DataType::Real64);
    EXPECT_FALSE(data_type_from_name("u33"));
    EXPECT_EQ(to_string(DataType::Integer16), "INTEGER16");
    EXPECT_EQ(data_type_from_index(0x0007), DataType::Unsigned32);
    EXPECT_FALSE(data_type_from_index(0x0017));
    EXPECT_EQ(access_from_string(" RW "), Access::Rw);
    EXPECT_EQ(access_from_string("Const"), Access::Const);
}
