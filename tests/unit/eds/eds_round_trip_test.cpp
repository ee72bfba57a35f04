// SPDX-License-Identifier: Apache-2.0
// parse → write → parse is lossless for fixtures, real files and descriptions built in code.
#include "eds_test_support.hpp"

#include <gtest/gtest.h>

#include <cstdio>
#include <unistd.h>

namespace codrive {
namespace {

using eds_test::dump;
using eds_test::expect_same_dictionary;
using eds_test::load;

void expect_same_description(const DeviceDescription& a, const DeviceDescription& b,
                             bool texts = true) {
    EXPECT_EQ(a.file_info, b.file_info);
    EXPECT_EQ(a.device_info, b.device_info);
    EXPECT_EQ(a.dummy_usage, b.dummy_usage);
    EXPECT_EQ(a.commissioning, b.commissioning);
    EXPECT_EQ(a.comments, b.comments);
    expect_same_dictionary(a.od, b.od, texts);
}

class EdsRoundTrip : public ::testing::TestWithParam<const char*> {};

TEST_P(EdsRoundTrip, ParseWriteParseIsLossless) {
    const DeviceDescription first = load(GetParam(), 0x11);
    const std::string text = write_eds(first);
    const DeviceDescription second = parse_eds(text, "written.eds", 0x11);
    // A written file has nothing to complain about, unless the model itself is odd (sloppy.eds
    // has a RECORD without sub-index 0).
    EXPECT_EQ(second.count(EdsSeverity::Error), 0U) << dump(second);
    if (first.count(EdsSeverity::Error) == 0 && first.count(EdsSeverity::Warning) == 0) {
        EXPECT_TRUE(second.findings.empty()) << dump(second);
    }
    expect_same_description(first, second);
    // Writing is a fixed point after one round.
    EXPECT_EQ(write_eds(second), text);
}

const char* const kFiles[] = {
    "full.eds",
    "device.dcf",
    "sloppy.eds",
    "real/canopennode-ds301-profile.eds",
    "real/canopendemo-demodevice.eds",
    "real/lely-co-nmt-master.dcf",
    "real/lely-co-pdo-transmit.dcf",
    "real/lely-co-sdev.dcf",
    "real/lely-coapp-fiber-master.dcf",
};

INSTANTIATE_TEST_SUITE_P(Files, EdsRoundTrip, ::testing::ValuesIn(kFiles), [](const auto& p) {
    std::string n = p.param;
    for (char& c : n) {
        c = std::isalnum(static_cast<unsigned char>(c)) != 0 ? c : '_';
    }
    return n;
});

TEST(EdsWrite, DescriptionBuiltInCodeRoundTrips) {
    DeviceDescription d;
    d.file_info.file_name = "sim.eds";
    d.file_info.eds_version = "4.0";
    d.device_info.vendor_name = "codrive";
    d.device_info.vendor_number = 0xAB;
    d.device_info.baud_rates = {250, 500, 1000, 2000};
    d.device_info.nr_of_rx_pdo = 4;
    d.device_info.lss_supported = true;
    d.dummy_usage.entries[0x0005] = true;
    d.od.add_var(0x1000, "Device type", DataType::Unsigned32, Access::Ro,
                 Value::from_uint(DataType::Unsigned32, 0x00020192).value());
    d.od.find(0x1000, 0)->default_value = d.od.find(0x1000, 0)->value;
    d.od.add_var(0x6041, "Statusword", DataType::Unsigned16, Access::Ro,
                 Value::from_uint(DataType::Unsigned16, 0).value(), true);
    d.od.add_var(0x2000, "Label", DataType::VisibleString, Access::Rw,
                 Value::from_string("  two\nlines \"q\""));
    d.od.find(0x2000, 0)->default_value = d.od.find(0x2000, 0)->value;
    d.od.add_var(0x6064, "Position actual value", DataType::Integer32, Access::Ro,
                 Value::from_int(DataType::Integer32, -7).value(), true);
    SubObject* pos = d.od.find(0x6064, 0);
    pos->default_value = pos->value;
    pos->low_limit = Value::from_int(DataType::Integer32, -1000).value();
    pos->high_limit = Value::from_int(DataType::Integer32, 1000).value();
    SubObject count;
    count.subindex = 0;
    count.name = "Highest sub-index supported";
    count.type = DataType::Unsigned8;
    count.access = Access::Const;
    count.value = Value::from_uint(DataType::Unsigned8, 1).value();
    count.default_value = count.value;
    d.od.add_sub(0x1018, count, "Identity object");
    SubObject vendor;
    vendor.subindex = 1;
    vendor.name = "Vendor-ID";
    vendor.type = DataType::Unsigned32;
    vendor.value = Value::from_uint(DataType::Unsigned32, 0xAB).value();
    vendor.default_value = vendor.value;
    d.od.add_sub(0x1018, vendor);
    SubObject gain;
    gain.subindex = 0;
    gain.name = "Gain";
    gain.type = DataType::Real64;
    gain.access = Access::Rw;
    gain.value = Value::from_double(DataType::Real64, 0.1 + 0.2).value();
    gain.default_value = gain.value;
    Object g;
    g.index = 0x2001;
    g.name = "Gain";
    g.subs[0] = gain;
    d.od.insert(g);

    const std::string text = write_eds(d);
    const DeviceDescription back = parse_eds(text, "sim.eds");
    EXPECT_EQ(back.count(EdsSeverity::Error), 0U) << dump(back) << text;
    expect_same_description(d, back, false);
    EXPECT_EQ(back.od.find(0x2000, 0)->value.to_string(), "  two\nlines \"q\"");
    EXPECT_EQ(back.device_info.baud_rates, (std::vector<unsigned>{250, 500, 1000, 2000}));
}

TEST(EdsWrite, DcfKeepsCommissioningAndParameterValues) {
    const DeviceDescription dcf = load("device.dcf");
    const std::string text = write_eds(dcf);
    EXPECT_NE(text.find("[DeviceComissioning]\nNodeID=0x05\n"), std::string::npos) << text;
    EXPECT_NE(text.find("ParameterValue=$NODEID+0x80000180\n"), std::string::npos) << text;
    const DeviceDescription back = parse_eds(text, "back.dcf");
    EXPECT_EQ(back.od.find(0x1800, 1)->value.as_uint(), 0x80000185U);
}

TEST(EdsWrite, CompactArraysAreWrittenExpanded) {
    const DeviceDescription d = load("full.eds");
    const std::string text = write_eds(d);
    EXPECT_EQ(text.find("CompactSubObj"), std::string::npos);
    EXPECT_NE(text.find("[1003sub4]\nParameterName=Oldest error\n"), std::string::npos) << text;
    EXPECT_NE(text.find("[1003sub0]\nParameterName=NrOfObjects\n"), std::string::npos) << text;
}

// fuzz_eds (bench/fuzz_long.sh, 44,346 executions): a compact sub-object's default value in
// [xxxxValue] kept its trailing `; comment` in the text that is written, so the written file
// read back differently and the second write was not the first.
TEST(EdsWrite, ACompactValueWithATrailingCommentIsWrittenWithoutIt) {
    const DeviceDescription first = parse_eds("[OptionalObjects]\nSupportedObjects=1\n1=0x1016\n"
                                              "[1016]\nParameterName=HB\nObjectType=0x8\n"
                                              "DataType=0x0007\nAccessType=rw\nCompactSubObj=3\n"
                                              "[1016Value]\nNrOfEntries=1\n2=0x00050064; 100 ms\n",
                                              "hb.eds", std::nullopt);
    const Object* hb = first.od.find(0x1016);
    ASSERT_NE(hb, nullptr);
    ASSERT_GT(hb->subs.size(), 2U);
    EXPECT_EQ(hb->subs.at(2).default_text, "0x00050064");
    const std::string written = write_eds(first);
    EXPECT_EQ(write_eds(parse_eds(written, "written.eds", std::nullopt)), written);
}

TEST(EdsWrite, SaveThenLoad) {
    const DeviceDescription d = load("full.eds", 4);
    char path[] = "/tmp/codrive-eds-XXXXXX";
    const int fd = mkstemp(path);
    ASSERT_GE(fd, 0);
    close(fd);
    ASSERT_TRUE(save_eds(d, path).has_value());
    auto back = load_eds(path, 4);
    std::remove(path);
    ASSERT_TRUE(back.has_value());
    EXPECT_TRUE(back->findings.empty()) << dump(*back);
    expect_same_description(d, *back);
    EXPECT_FALSE(save_eds(d, "/nonexistent-dir/x.eds").has_value());
}

} // namespace
} // namespace codrive
