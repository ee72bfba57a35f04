// SPDX-License-Identifier: Apache-2.0
// The bus file's `esi:` keys: the ESI file is read with the bus file, relative to it, and a file
// that cannot be read is a finding at the key's line.
#include <codrive/controller/ethercat_segment.hpp>

#include <codrive/testing/text.hpp>

#include <gtest/gtest.h>

#include <fstream>
#include <sstream>

using namespace codrive;
using namespace codrive::controller;
using codrive::testing::joined;

namespace {

const std::string kDocs = std::string(CODRIVE_SOURCE_DIR) + "/docs/bus-file.md";

} // namespace

TEST(ControllerBusFileEsi, TheEsiExampleOfTheDocsReadsTheDeviceFileRelativeToTheBusFile) {
    // docs/bus-file.md, the `esi:` example, exactly as printed there, as if the bus file were
    // docs/bus-file.md itself (so `../devices/fio.xml` is the shipped file).
    std::ifstream in(kDocs);
    std::stringstream doc;
    doc << in.rdbuf();
    const std::string text = doc.str();
    const auto at = text.find("esi: ../devices/fio.xml");
    ASSERT_NE(at, std::string::npos) << "docs/bus-file.md lost its ESI example";
    const auto begin = text.rfind("```yaml\n", at);
    const auto end = text.find("```", at);
    ASSERT_TRUE(begin != std::string::npos && end != std::string::npos);
    const auto s = split_bus_file(text.substr(begin + 8, end - begin - 8), kDocs);
    ASSERT_TRUE(s.ethercat) << joined(s.errors);
    ASSERT_EQ(s.ethercat->slaves.size(), 2U);
    for (const auto& slave : s.ethercat->slaves) {
        ASSERT_NE(slave.esi, nullptr);
        EXPECT_EQ(slave.esi->vendor_id, 0x0048554BU);
        ASSERT_EQ(slave.esi->devices.size(), 1U);
        EXPECT_EQ(slave.esi->devices[0].product_code, 0x0002BA67U);
    }
    EXPECT_EQ(s.ethercat->slaves[0].axes.size(), 1U);
    EXPECT_TRUE(s.ethercat->slaves[1].axes.empty());
}

TEST(ControllerBusFileEsi, TheSegmentsEsiIsEverySlavesWithoutItsOwn) {
    const std::string text = "ethercat:\n"
                             "  interface: ecm0\n"
                             "  esi: ../devices/akd2g.xml\n"
                             "  slaves:\n"
                             "    - {position: 0, profile: akd2g}\n"
                             "    - {position: 1, profile: fio, esi: ../devices/fio.xml}\n"
                             "    - {position: 2, profile: generic}\n";
    const auto s = split_bus_file(text, kDocs);
    ASSERT_TRUE(s.ethercat) << joined(s.errors);
    const auto& slaves = s.ethercat->slaves;
    ASSERT_EQ(slaves.size(), 3U);
    EXPECT_EQ(slaves[0].esi->vendor_id, 0x6AU);
    EXPECT_EQ(slaves[1].esi->vendor_id, 0x0048554BU);
    EXPECT_EQ(slaves[2].esi, slaves[0].esi);
}

TEST(ControllerBusFileEsi, AMissingOrMalformedEsiIsAFindingAtItsLine) {
    const std::string text = "ethercat:\n"
                             "  interface: ecm0\n"
                             "  slaves:\n"
                             "    - position: 0\n"
                             "      profile: fio\n"
                             "      esi: no-such.xml\n"
                             "    - position: 1\n"
                             "      profile: fio\n"
                             "      esi: ../docs/bus-file.md\n";
    const auto s = split_bus_file(text, kDocs);
    EXPECT_FALSE(s.ethercat);
    const std::string all = joined(s.errors);
    ASSERT_EQ(s.errors.size(), 2U) << all;
    EXPECT_EQ(s.errors[0].rfind(kDocs + ":6: slave 0: `esi`: ", 0), 0U) << all;
    EXPECT_NE(s.errors[0].find("docs/no-such.xml: cannot read the ESI file: No such file or "
                               "directory"),
              std::string::npos)
        << all;
    // Markdown is not XML: the ESI reader's own `file:line:` sentence follows the bus file's.
    EXPECT_EQ(s.errors[1].rfind(kDocs + ":9: slave 1: `esi`: ", 0), 0U) << all;
    EXPECT_NE(s.errors[1].find("`: " + kDocs + ":"), std::string::npos) << all;
    EXPECT_NE(s.errors[1].find(": not well-formed XML: "), std::string::npos) << all;
}
