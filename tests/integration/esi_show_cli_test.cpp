// SPDX-License-Identifier: Apache-2.0
// `codrive esi show FILE [INDEX]` on the shipped devices/*.xml and on a malformed file: what
// docs/cli/codrive-esi.md promises, run as the user runs it.
#include <codrive/testing/process.hpp>
#include <codrive/testing/text.hpp>

#include <gtest/gtest.h>

#include <fstream>
#include <string>
#include <unistd.h>

using namespace std::chrono_literals;
namespace ct = codrive::testing;
using codrive::testing::has;

namespace {

const std::string kDeviceDir = std::string(CODRIVE_SOURCE_DIR) + "/devices/";

} // namespace

TEST(EsiShowCli, ListsIdentityCountsSyncManagersAndDefaultPdos) {
    const auto r = ct::run({ct::tool_path("codrive"), "esi", "show", kDeviceDir + "fio.xml"}, 20s);
    ASSERT_EQ(r.status, 0) << r.output;
    EXPECT_TRUE(has(r.output, "fio.xml: vendor 0x0048554B (Kuhnke), 1 device(s)")) << r.output;
    EXPECT_TRUE(has(r.output, "device product 0x0002BA67 revision 0x00000000 (Kuhnke FIO Drive "
                              "Control): 130 objects, 4 RxPDO, 4 TxPDO"))
        << r.output;
    EXPECT_TRUE(has(r.output, "  MBoxOut start 0x1000 size 128")) << r.output;
    EXPECT_TRUE(has(r.output, "mailbox: CoE (SDO info yes, PDO assign yes, PDO config yes)"))
        << r.output;
    EXPECT_TRUE(has(r.output, "  RxPDO 1600h RxPDO 1600h, SM2 by default\n"
                              "    6040:00 16 bit  Controlword\n"))
        << r.output;
    const auto akd =
        ct::run({ct::tool_path("codrive"), "esi", "show", kDeviceDir + "akd2g.xml"}, 20s);
    ASSERT_EQ(akd.status, 0) << akd.output;
    EXPECT_TRUE(has(akd.output, "(Kollmorgen AKD2G): 166 objects, 13 RxPDO, 19 TxPDO"))
        << akd.output;
}

TEST(EsiShowCli, OneObjectIsPrintedTypedAndAMissingOneIsAnError) {
    auto r =
        ct::run({ct::tool_path("codrive"), "esi", "show", kDeviceDir + "fio.xml", "607A"}, 20s);
    ASSERT_EQ(r.status, 0) << r.output;
    EXPECT_TRUE(has(r.output, "607A:00  Target position  DINT (INTEGER32)  rw  R  A00F0000"))
        << r.output;
    r = ct::run({ct::tool_path("codrive"), "esi", "show", kDeviceDir + "fio.xml", "2345"}, 20s);
    EXPECT_EQ(r.status, 1) << r.output;
    EXPECT_TRUE(has(r.output, "fio.xml has no object 2345h")) << r.output;
    r = ct::run({ct::tool_path("codrive"), "esi", "show", kDeviceDir + "fio.xml", "x9"}, 20s);
    EXPECT_EQ(r.status, 2) << r.output;
}

TEST(EsiShowCli, AMalformedFileIsOneSentenceWithItsLine) {
    const std::string path = "/tmp/codrive-esi-show-" + std::to_string(::getpid()) + ".xml";
    std::ofstream(path) << "<EtherCATInfo>\n  <Vendor>\n    <Id>#xZZ</Id>\n  </Vendor>\n"
                           "</EtherCATInfo>\n";
    const auto r = ct::run({ct::tool_path("codrive"), "esi", "show", path}, 20s);
    EXPECT_EQ(r.status, 1) << r.output;
    EXPECT_TRUE(has(r.output, "codrive esi show: " + path +
                                  ":3: Vendor/Id is `#xZZ`, not a number 0..4294967295"))
        << r.output;
    std::remove(path.c_str());
}
