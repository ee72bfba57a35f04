// SPDX-License-Identifier: Apache-2.0
// Value text of EDS/DCF files: $NODEID arithmetic, number bases, reals, strings, times.
#include "eds_test_support.hpp"

#include <gtest/gtest.h>

namespace codrive {
namespace {

using eds_test::dump;

// Parses one VAR 0x2000 of `type` with DefaultValue `text`.
DeviceDescription var(const std::string& type, const std::string& text,
                      std::optional<NodeId> node = {}) {
    const std::string eds = eds_test::eds_head({0x2000}) +
                            "[2000]\nParameterName=v\nDataType=" + type +
                            "\nAccessType=rw\nDefaultValue=" + text + "\n";
    return parse_eds(eds, "v.eds", node);
}

// Line of DefaultValue in var(): head (8 lines) + 4.
constexpr std::size_t kDefaultLine = 13;

std::optional<std::uint64_t> u32(const std::string& text, std::optional<NodeId> node = {}) {
    DeviceDescription d = var("0x0007", text, node);
    if (d.has_errors()) {
        return std::nullopt;
    }
    return d.od.find(0x2000, 0)->value.as_uint();
}

TEST(EdsValues, NodeIdArithmetic) {
    EXPECT_EQ(u32("$NODEID+0x180", 5), 0x185U);
    EXPECT_EQ(u32("0x180+$NODEID", 5), 0x185U);
    EXPECT_EQ(u32("$NODEID + 0x180", 5), 0x185U);
    EXPECT_EQ(u32("$nodeid+0x180", 5), 0x185U);
    EXPECT_EQ(u32("$NODEID", 0x7F), 0x7FU);
    EXPECT_EQ(u32("0x600+$NODEID-1", 2), 0x601U);
    EXPECT_EQ(u32("$NODEID+0x80000200", 1), 0x80000201U);
    EXPECT_EQ(u32("$NODEID+384", 1), 385U);
    EXPECT_EQ(u32("$NODEID+0x180"), 0x180U); // no node-ID known: $NODEID counts as 0
}

TEST(EdsValues, NodeIdOverflowOfTheTypeIsAnError) {
    DeviceDescription d = var("0x0005", "$NODEID+0xF0", 0x20);
    EXPECT_NE(eds_test::find(d, EdsSeverity::Error, kDefaultLine,
                             "'$NODEID+0xF0' is out of range for UNSIGNED8"),
              nullptr)
        << dump(d);
}

TEST(EdsValues, NumberBasesFollowCiA306) {
    EXPECT_EQ(u32("42"), 42U);
    EXPECT_EQ(u32("0x2A"), 42U);
    EXPECT_EQ(u32("0X2a"), 42U);
    EXPECT_EQ(u32("0"), 0U);
    EXPECT_EQ(u32("  7  "), 7U);
    DeviceDescription octal = var("0x0007", "010");
    EXPECT_EQ(octal.od.find(0x2000, 0)->value.as_uint(), 8U);
    EXPECT_NE(eds_test::find(octal, EdsSeverity::Warning, kDefaultLine, "read as octal"), nullptr)
        << dump(octal);
    DeviceDescription not_octal = var("0x0007", "0129");
    EXPECT_EQ(not_octal.od.find(0x2000, 0)->value.as_uint(), 129U);
    EXPECT_NE(eds_test::find(not_octal, EdsSeverity::Warning, kDefaultLine, "read as decimal"),
              nullptr);
}

TEST(EdsValues, SignedValues) {
    auto i16 = [](const std::string& t) {
        DeviceDescription d = var("0x0003", t);
        EXPECT_FALSE(d.has_errors()) << t << "\n" << dump(d);
        return d.od.find(0x2000, 0)->value.as_int();
    };
    EXPECT_EQ(i16("-5"), -5);
    EXPECT_EQ(i16("-0x7FFF"), -0x7FFF);
    EXPECT_EQ(i16("0xFFFF"), -1); // hex for a signed type is the bit pattern
    EXPECT_EQ(i16("32767"), 32767);
    EXPECT_TRUE(var("0x0003", "32768").has_errors());
    EXPECT_TRUE(var("0x0003", "-32769").has_errors());
    DeviceDescription i64 = var("0x0015", "-9223372036854775808");
    EXPECT_FALSE(i64.has_errors()) << dump(i64);
    EXPECT_EQ(i64.od.find(0x2000, 0)->value.as_int(), INT64_MIN);
}

TEST(EdsValues, Unsigned64UsesAllBits) {
    DeviceDescription d = var("0x001B", "0xFFFFFFFFFFFFFFFF");
    EXPECT_FALSE(d.has_errors()) << dump(d);
    EXPECT_EQ(d.od.find(0x2000, 0)->value.as_uint(), UINT64_MAX);
    EXPECT_TRUE(var("0x001B", "0x1FFFFFFFFFFFFFFFF").has_errors());
    EXPECT_TRUE(var("0x0007", "-1").has_errors());
}

TEST(EdsValues, Booleans) {
    EXPECT_EQ(var("0x0001", "1").od.find(0x2000, 0)->value.as_uint(), 1U);
    EXPECT_EQ(var("0x0001", "false").od.find(0x2000, 0)->value.as_uint(), 0U);
    EXPECT_EQ(var("0x0001", "TRUE").od.find(0x2000, 0)->value.as_uint(), 1U);
    EXPECT_TRUE(var("0x0001", "2").has_errors());
}

TEST(EdsValues, RealsAsDecimalOrBitPattern) {
    EXPECT_DOUBLE_EQ(*var("0x0008", "-2.5e3").od.find(0x2000, 0)->value.as_double(), -2500.0);
    EXPECT_DOUBLE_EQ(*var("0x0008", "0x3F800000").od.find(0x2000, 0)->value.as_double(), 1.0);
    // Fewer hex digits than the type's size is a number, as strtod reads it.
    EXPECT_DOUBLE_EQ(*var("0x0011", "0x10").od.find(0x2000, 0)->value.as_double(), 16.0);
    EXPECT_DOUBLE_EQ(*var("0x0011", "0x3FF0000000000000").od.find(0x2000, 0)->value.as_double(),
                     1.0);
    EXPECT_TRUE(var("0x0008", "fast").has_errors());
}

TEST(EdsValues, StringsVerbatimOrQuotedWithEscapes) {
    EXPECT_EQ(var("0x0009", "a ; b = c").od.find(0x2000, 0)->value.to_string(), "a ; b = c");
    EXPECT_EQ(var("0x0009", "\"  padded  \"").od.find(0x2000, 0)->value.to_string(), "  padded  ");
    EXPECT_EQ(var("0x0009", R"("line\nbreak \"q\" \\")").od.find(0x2000, 0)->value.to_string(),
              "line\nbreak \"q\" \\");
    DeviceDescription empty = var("0x0009", "");
    EXPECT_TRUE(empty.od.find(0x2000, 0)->default_value.has_value());
    EXPECT_EQ(empty.od.find(0x2000, 0)->value.size(), 0U);
}

TEST(EdsValues, OctetStringsAndDomainsAreHex) {
    EXPECT_EQ(var("0x000A", "0102ab").od.find(0x2000, 0)->value.to_string(), "01 02 AB");
    EXPECT_EQ(var("0x000F", "DE AD").od.find(0x2000, 0)->value.to_string(), "DE AD");
    EXPECT_TRUE(var("0x000A", "012").has_errors());
}

TEST(EdsValues, TimeOfDayAsDaysAndMilliseconds) {
    DeviceDescription d = var("0x000C", "1 1000");
    EXPECT_FALSE(d.has_errors()) << dump(d);
    const Value& v = d.od.find(0x2000, 0)->value;
    EXPECT_EQ(get_le_n(v.bytes().data(), 4), 1000U);
    EXPECT_EQ(get_le_n(v.bytes().data() + 4, 2), 1U);
    EXPECT_TRUE(var("0x000C", "1 300000000").has_errors()); // ms beyond 28 bits
    EXPECT_EQ(eds_value_text(v), "1 1000");
}

TEST(EdsValues, EmptyNumericDefaultMeansNoDefault) {
    DeviceDescription d = var("0x0007", "");
    EXPECT_TRUE(d.findings.size() <= 1U) << dump(d); // only "no [MandatoryObjects]"
    EXPECT_FALSE(d.od.find(0x2000, 0)->default_value.has_value());
    EXPECT_EQ(d.od.find(0x2000, 0)->value.as_uint(), 0U);
}

TEST(EdsValues, DefaultOutsideLimitsIsAWarning) {
    const std::string eds = eds_test::eds_head({0x2000}) +
                            "[2000]\nParameterName=v\nDataType=0x0006\nAccessType=rw\n"
                            "LowLimit=10\nHighLimit=20\nDefaultValue=30\n";
    DeviceDescription d = parse_eds(eds, "v.eds");
    EXPECT_NE(eds_test::find(d, EdsSeverity::Warning, 15, "DefaultValue 30 is above HighLimit 20"),
              nullptr)
        << dump(d);
    EXPECT_FALSE(d.has_errors());
}

TEST(EdsValues, NodeIdValueIsCheckedForEveryNodeIdWhenNoneIsGiven) {
    // Evaluating $NODEID as 0 would put $NODEID+0x80 below LowLimit=0x81: no finding for that.
    const std::string ok = eds_test::eds_head({0x2000}) +
                           "[2000]\nParameterName=v\nDataType=0x0007\nAccessType=rw\n"
                           "LowLimit=0x81\nHighLimit=0xFF\nDefaultValue=$NODEID+0x80\n";
    DeviceDescription d = parse_eds(ok, "v.eds");
    EXPECT_EQ(d.count(EdsSeverity::Warning), 1U) << eds_test::dump(d); // no mandatory objects
    EXPECT_FALSE(d.has_errors());
    // A limit that only some node-IDs break: the finding names them and says how it checked.
    const std::string bad = eds_test::eds_head({0x2000}) +
                            "[2000]\nParameterName=v\nDataType=0x0007\nAccessType=rw\n"
                            "LowLimit=0x181\nHighLimit=0x1F0\nDefaultValue=$NODEID+0x180\n";
    d = parse_eds(bad, "v.eds");
    EXPECT_NE(eds_test::find(d, EdsSeverity::Warning, 15,
                             "DefaultValue $NODEID+0x180 is above HighLimit 0x1F0 for node-ID "
                             "113..127 (checked for every node-ID 1..127)"),
              nullptr)
        << eds_test::dump(d);
    EXPECT_EQ(d.count(EdsSeverity::Warning), 2U) << eds_test::dump(d);
    // With a node-ID the value is checked for that node only.
    d = parse_eds(bad, "v.eds", NodeId{5});
    EXPECT_EQ(d.count(EdsSeverity::Warning), 1U) << eds_test::dump(d);
}

TEST(EdsValues, ValueTextIsWhatFilesWrite) {
    EXPECT_EQ(eds_value_text(Value::from_uint(DataType::Unsigned16, 0x1A).value()), "0x001A");
    EXPECT_EQ(eds_value_text(Value::from_int(DataType::Integer8, -3).value()), "-3");
    EXPECT_EQ(eds_value_text(Value::from_double(DataType::Real32, 0.1).value()), "0.1");
    EXPECT_EQ(eds_value_text(Value::from_uint(DataType::Boolean, 1).value()), "1");
    EXPECT_EQ(eds_value_text(Value::from_string("x")), "x");
    EXPECT_EQ(eds_value_text(Value::from_string(" x")), "\" x\"");
    EXPECT_EQ(eds_value_text(Value(DataType::OctetString, {0x01, 0xAB})), "01AB");
}

} // namespace
} // namespace codrive

namespace codrive {
namespace {

TEST(EdsQuirks, TrailingCommentsAfterNumbersAreIgnoredWithAWarning) {
    const std::string eds = eds_test::eds_head({0x2000}) +
                            "[2000]\nParameterName=v ; keeps its ';'\nDataType=0x0006 ; u16\n"
                            "AccessType=rw ; writable\nDefaultValue=0x10 ; sixteen\n"
                            "PDOMapping=1;yes\n";
    DeviceDescription d = parse_eds(eds, "v.eds");
    EXPECT_FALSE(d.has_errors()) << eds_test::dump(d);
    const SubObject* s = d.od.find(0x2000, 0);
    ASSERT_NE(s, nullptr);
    EXPECT_EQ(d.od.find(0x2000)->name, "v ; keeps its ';'");
    EXPECT_EQ(s->type, DataType::Unsigned16);
    EXPECT_EQ(s->access, Access::Rw);
    EXPECT_EQ(s->value.as_uint(), 0x10U);
    // The text `eds show` prints and $NODEID re-evaluation reads has no comment either.
    EXPECT_EQ(s->default_text, "0x10");
    EXPECT_TRUE(s->pdo_mappable);
    EXPECT_NE(eds_test::find(d, EdsSeverity::Warning, 12,
                             "[2000] AccessType: trailing comment '; writable' ignored"),
              nullptr)
        << eds_test::dump(d);
    EXPECT_EQ(d.count(EdsSeverity::Warning), 5U) << eds_test::dump(d); // 4 comments + no mandatory
}

TEST(EdsQuirks, StringValuesKeepSemicolons) {
    const std::string eds = eds_test::eds_head({0x2000}) +
                            "[2000]\nParameterName=v\nDataType=0x0009\nAccessType=rw\n"
                            "DefaultValue=a;b\n";
    DeviceDescription d = parse_eds(eds, "v.eds");
    EXPECT_EQ(d.od.find(0x2000, 0)->value.to_string(), "a;b");
    EXPECT_EQ(d.od.find(0x2000, 0)->default_text, "a;b");
}

TEST(EdsQuirks, NodeIdValueWithATrailingCommentIsShownWithoutIt) {
    const std::string eds =
        eds_test::eds_head({0x2000}) +
        "[2000]\nParameterName=v\nDataType=0x0007\nAccessType=rw\n"
        "DefaultValue=$NODEID+0x180 ; TPDO1 COB-ID\nParameterValue=0x185 ; set\n";
    DeviceDescription d = parse_eds(eds, "v.eds");
    const SubObject* s = d.od.find(0x2000, 0);
    ASSERT_NE(s, nullptr);
    EXPECT_EQ(s->default_text, "$NODEID+0x180");
    EXPECT_EQ(s->parameter_text, "0x185");
}

TEST(EdsQuirks, DataTypeByNameIsAcceptedWithAWarning) {
    const std::string eds = eds_test::eds_head({0x2000}) +
                            "[2000]\nParameterName=v\nDataType=UNSIGNED32\nAccessType=rw\n";
    DeviceDescription d = parse_eds(eds, "v.eds");
    EXPECT_EQ(d.od.find(0x2000, 0)->type, DataType::Unsigned32);
    EXPECT_NE(eds_test::find(d, EdsSeverity::Warning, 11,
                             "DataType=UNSIGNED32 should be the index 0x0007"),
              nullptr)
        << eds_test::dump(d);
}

TEST(EdsQuirks, MissingCommentLinesAreReportedOnce) {
    const std::string eds = eds_test::eds_head({}) + "[Comments]\nLines=60000\nLine1=a\nLine3=c\n";
    DeviceDescription d = parse_eds(eds, "c.eds");
    EXPECT_EQ(d.comments, (std::vector<std::string>{"a", "c"}));
    EXPECT_NE(eds_test::find(d, EdsSeverity::Warning, 8,
                             "Lines=60000 but 59998 of the lines are missing (first: Line2)"),
              nullptr)
        << eds_test::dump(d);
}

TEST(EdsQuirks, ByteOrderMarkAndOldMacLineEndings) {
    const std::string eds = "\xEF\xBB\xBF[FileInfo]\rFileName=m.eds\r[DeviceInfo]\rVendorName=m\r"
                            "[OptionalObjects]\rSupportedObjects=1\r1=0x2000\r[2000]\r"
                            "ParameterName=v\rDataType=0x0005\rAccessType=ro\rDefaultValue=7\r";
    DeviceDescription d = parse_eds(eds, "m.eds");
    EXPECT_EQ(d.file_info.file_name, "m.eds");
    EXPECT_EQ(d.od.find(0x2000, 0)->value.as_uint(), 7U);
    EXPECT_FALSE(d.has_errors()) << eds_test::dump(d);
}

} // namespace
} // namespace codrive
