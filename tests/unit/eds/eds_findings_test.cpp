// SPDX-License-Identifier: Apache-2.0
// Findings: sloppy files are accepted with warnings, malformed ones get errors with line and
// reason, and no input makes the parser crash or throw.
#include "eds_test_support.hpp"

#include <gtest/gtest.h>

#include <fstream>
#include <random>
#include <sstream>

namespace codrive {
namespace {

using eds_test::dump;
using eds_test::find;
using eds_test::load;

TEST(EdsSloppy, AcceptedWithWarningsAndNoErrors) {
    DeviceDescription d = load("sloppy.eds");
    EXPECT_EQ(d.count(EdsSeverity::Error), 0U) << dump(d);
    const struct {
        std::size_t line;
        const char* text;
    } expected[] = {
        {10, "[DEVICEINFO] LSS_Supported=true should be 1 or 0"},
        {14, "[MandatoryObjects] 1 '1000' has no 0x prefix; read as hex 0x1000"},
        {18, "[OptionalObjects] SupportedObjects=2 but 1 objects are listed"},
        {26, "[1000] AccessType 'RO' should be written 'ro'"},
        {32, "[1001] duplicate key 'AccessType' (first at line 31); keeping the first value 'ro'"},
        {35, "[1017] ObjectType=VAR should be the number 0x7"},
        {38, "[1017] DefaultValue: '010' has a leading zero and is read as octal"},
        {39, "[1017] PDOMapping=true should be 1 or 0"},
        {40, "[1018] has no sub-index 0 (highest sub-index supported)"},
        {43, "[1018] SubNumber=3 but 1 sub-object sections are given"},
        {47, "[1018SUB1] AccessType 'Const' should be written 'const'"},
        {53, "[2000] DefaultValue: '09' has a leading zero but is not octal; read as decimal"},
        {54, "object [2001] is not listed in [MandatoryObjects], [OptionalObjects] or "
             "[ManufacturerObjects]; loaded anyway"},
        {58, "duplicate section [1001] (first at line 28); its keys are merged into the first"},
    };
    for (const auto& e : expected) {
        EXPECT_NE(find(d, EdsSeverity::Warning, e.line, e.text), nullptr)
            << "line " << e.line << ": " << e.text << "\n"
            << dump(d);
    }
    EXPECT_EQ(d.findings.size(), std::size(expected)) << dump(d);
}

TEST(EdsSloppy, QuirksAreReadTheWayToolsReadThem) {
    DeviceDescription d = load("sloppy.eds");
    EXPECT_EQ(d.device_info.vendor_name, "Sloppy Motors"); // case-insensitive keys
    EXPECT_EQ(d.device_info.nr_of_rx_pdo, 1);
    EXPECT_TRUE(d.device_info.lss_supported);
    EXPECT_EQ(d.file_info.file_name, "sloppy.eds"); // spaces around '='
    EXPECT_EQ(d.od.find(0x1000, 0)->access, Access::Ro);
    EXPECT_EQ(d.od.find(0x1001, 0)->access, Access::Ro);           // first duplicate wins
    EXPECT_EQ(d.od.find(0x1001, 0)->default_value->as_uint(), 0U); // merged section
    EXPECT_EQ(d.od.find(0x1017, 0)->access, Access::Rw);           // "rw   "
    EXPECT_EQ(d.od.find(0x1017, 0)->value.as_uint(), 8U);          // octal 010
    EXPECT_TRUE(d.od.find(0x1017, 0)->pdo_mappable);
    EXPECT_EQ(d.od.find(0x1018, 1)->access, Access::Const);
    EXPECT_EQ(d.od.find(0x2000, 0)->value.as_uint(), 9U);
    EXPECT_NE(d.od.find(0x2001), nullptr); // unlisted object loaded
}

struct Malformed {
    const char* file;
    std::size_t line;
    const char* message;
};

// Each fixture in tests/data/eds/malformed/ breaks one rule; its first line says which.
const Malformed kMalformed[] = {
    {"bad_section_header.eds", 19, "malformed section header '[2000' (no closing ']')"},
    {"empty_section_name.eds", 19, "empty section name"},
    {"no_equals.eds", 18,
     "line 'ThisIsGarbage' is neither a [section], a key=value nor a ;comment"},
    {"no_key.eds", 18, "has no key before '='"},
    {"unknown_access.eds", 16, "AccessType 'readwrite' is not one of ro, wo, rw, rwr, rww, const"},
    {"missing_access.eds", 13, "[1000] has no AccessType; assuming ro"},
    {"missing_datatype.eds", 13, "[1000] has no DataType; skipped"},
    {"bad_datatype.eds", 15, "DataType 0x0020 is not a basic CiA 301 data type"},
    {"default_out_of_range.eds", 17, "[1000] DefaultValue '0x1FF' is out of range for UNSIGNED8"},
    {"default_not_number.eds", 17, "[1000] DefaultValue '12abc' has unexpected 'a'"},
    {"unknown_variable.eds", 17, "'$NODE+1' uses an unknown variable (only $NODEID is defined)"},
    {"bad_octet_string.eds", 17, "DefaultValue 'XYZ' is not hex bytes"},
    {"bad_object_type.eds", 15, "[1000] ObjectType 0x4 is not a CiA 301 object code"},
    {"listed_without_section.eds", 15, "object 0x2000 is listed but has no [2000] section"},
    {"sub_without_object.eds", 19, "[2000sub1] has no object section [2000]; ignored"},
    {"bad_compact_value.eds", 28, "[1003Value] 2 'later' is not a number"},
    {"bad_list_entry.eds", 11, "[MandatoryObjects] 1 'device' is not an object index"},
    {"key_outside_section.eds", 2, "key 'VendorName' is outside any section"},
    {"bad_node_id.dcf", 20, "[DeviceComissioning] NodeID 200 is not a node-ID (1..127)"},
    {"nodeid_in_real.eds", 17, "uses $NODEID, which is not allowed for REAL32"},
    {"limit_not_number.eds", 18, "[1000] HighLimit 'max' is not a number"},
};

class EdsMalformed : public ::testing::TestWithParam<Malformed> {};

TEST_P(EdsMalformed, ReportsExactlyOneErrorWithLineAndReason) {
    const Malformed& m = GetParam();
    DeviceDescription d = load(std::string("malformed/") + m.file);
    const EdsFinding* f = find(d, EdsSeverity::Error, m.line, m.message);
    ASSERT_NE(f, nullptr) << "expected line " << m.line << ": " << m.message << "\n" << dump(d);
    EXPECT_EQ(d.count(EdsSeverity::Error), 1U) << dump(d);
    EXPECT_NE(f->file.find(m.file), std::string::npos);
    EXPECT_EQ(format_finding(*f).substr(f->file.size()),
              ":" + std::to_string(m.line) + ": error: " + f->message);
}

INSTANTIATE_TEST_SUITE_P(AllFixtures, EdsMalformed, ::testing::ValuesIn(kMalformed),
                         [](const auto& p) {
                             std::string n = p.param.file;
                             return n.substr(0, n.find('.'));
                         });

TEST(EdsMalformed, TheRestOfABrokenFileIsStillLoaded) {
    DeviceDescription d = load("malformed/bad_datatype.eds");
    EXPECT_EQ(d.od.find(0x1000), nullptr); // the broken object is skipped...
    DeviceDescription d2 = load("malformed/unknown_access.eds");
    ASSERT_NE(d2.od.find(0x1000, 0), nullptr); // ...a broken key only falls back
    EXPECT_EQ(d2.od.find(0x1000, 0)->access, Access::Ro);
}

TEST(EdsLoad, MissingFileIsAnError) {
    auto d = load_eds(eds_test::data_path("does-not-exist.eds"));
    ASSERT_FALSE(d.has_value());
    EXPECT_EQ(d.error(), std::errc::no_such_file_or_directory);
}

TEST(EdsRobustness, EmptyAndBinaryInputNeverCrash) {
    DeviceDescription empty = parse_eds("", "empty.eds");
    EXPECT_EQ(empty.od.size(), 0U);
    EXPECT_FALSE(empty.has_errors()); // only warnings: no sections at all
    static const char kBinary[] = "\0\xff[\x01=\n[]]\r\r=\n[1000sub]\n[ffffsubff]\nDataType=\0";
    const std::string binary(kBinary, sizeof(kBinary) - 1);
    DeviceDescription b = parse_eds(binary, "binary.eds");
    EXPECT_TRUE(b.has_errors());
}

TEST(EdsRobustness, RandomMutationsOfARealFileNeverCrash) {
    std::ifstream in(eds_test::data_path("full.eds"));
    std::stringstream ss;
    ss << in.rdbuf();
    const std::string base = ss.str();
    std::mt19937 rng(12345);
    const std::string alphabet = "[]=;$+-0x19AFsubNODEIDValueName\n\r \t\"\\";
    for (int round = 0; round < 300; ++round) {
        std::string text = base;
        const int edits = 1 + static_cast<int>(rng() % 20);
        for (int e = 0; e < edits && !text.empty(); ++e) {
            const std::size_t pos = rng() % text.size();
            switch (rng() % 3) {
            case 0:
                text[pos] = alphabet[rng() % alphabet.size()];
                break;
            case 1:
                text.erase(pos, rng() % 8);
                break;
            default:
                text.insert(pos, 1, static_cast<char>(rng() % 256));
                break;
            }
        }
        DeviceDescription d = parse_eds(text, "mutated.eds", static_cast<NodeId>(1 + round % 127));
        // Whatever was loaded can be written and read again.
        DeviceDescription again = parse_eds(write_eds(d), "again.eds", d.node_id);
        EXPECT_EQ(again.od.size(), d.od.size()) << "round " << round;
    }
}

} // namespace
} // namespace codrive

namespace codrive {
namespace {

TEST(EdsStructure, SubSectionsOfAVarAreIgnoredWithAWarning) {
    const std::string eds = eds_test::eds_head({0x2000}) +
                            "[2000]\nParameterName=v\nDataType=0x0005\nAccessType=rw\n"
                            "[2000sub1]\nParameterName=s\nDataType=0x0005\nAccessType=rw\n";
    DeviceDescription d = parse_eds(eds, "v.eds");
    EXPECT_EQ(d.od.find(0x2000)->subs.size(), 1U);
    EXPECT_NE(eds_test::find(d, EdsSeverity::Warning, 13,
                             "[2000sub1] is a sub-object of 0x2000, which is a VAR"),
              nullptr)
        << eds_test::dump(d);
}

TEST(EdsStructure, ValueSectionWithoutCompactSubObjIsIgnored) {
    const std::string eds = eds_test::eds_head({0x2000}) +
                            "[2000]\nParameterName=a\nObjectType=0x8\nSubNumber=2\n"
                            "[2000sub0]\nParameterName=n\nDataType=0x0005\nAccessType=ro\n"
                            "[2000sub1]\nParameterName=x\nDataType=0x0005\nAccessType=rw\n"
                            "[2000Value]\nNrOfEntries=1\n1=5\n";
    DeviceDescription d = parse_eds(eds, "v.eds");
    EXPECT_EQ(d.od.find(0x2000, 1)->value.as_uint(), 0U);
    EXPECT_NE(eds_test::find(d, EdsSeverity::Warning, 21,
                             "[2000Value] is only used with CompactSubObj; ignored"),
              nullptr)
        << eds_test::dump(d);
}

TEST(EdsStructure, SubSectionsReplaceGeneratedCompactSubObjects) {
    const std::string eds = eds_test::eds_head({0x2000}) +
                            "[2000]\nParameterName=a\nObjectType=0x8\nDataType=0x0006\n"
                            "AccessType=rw\nCompactSubObj=2\n"
                            "[2000sub2]\nParameterName=special\nDataType=0x0006\nAccessType=ro\n";
    DeviceDescription d = parse_eds(eds, "v.eds");
    ASSERT_EQ(d.od.find(0x2000)->subs.size(), 3U);
    EXPECT_EQ(d.od.find(0x2000, 1)->name, "a1");
    EXPECT_EQ(d.od.find(0x2000, 2)->name, "special");
    EXPECT_EQ(d.od.find(0x2000, 2)->access, Access::Ro);
    EXPECT_NE(eds_test::find(d, EdsSeverity::Warning, 15,
                             "has both CompactSubObj and sub-object sections"),
              nullptr)
        << eds_test::dump(d);
}

TEST(EdsStructure, UnknownSectionsAndKeysAreInfos) {
    const std::string eds = eds_test::eds_head({0x2000}) +
                            "[2000]\nParameterName=v\nDataType=0x0005\nAccessType=rw\n"
                            "Colour=blue\n[Tools]\nEditor=vi\n";
    DeviceDescription d = parse_eds(eds, "v.eds");
    EXPECT_NE(eds_test::find(d, EdsSeverity::Info, 13, "[2000] key 'Colour' is not used"), nullptr)
        << eds_test::dump(d);
    EXPECT_NE(eds_test::find(d, EdsSeverity::Info, 14, "section [Tools] is not used by codrive"),
              nullptr)
        << eds_test::dump(d);
    EXPECT_FALSE(d.has_errors());
}

} // namespace
} // namespace codrive
