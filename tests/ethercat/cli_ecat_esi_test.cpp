// SPDX-License-Identifier: Apache-2.0
// `codrive ecat sdo read|write --esi FILE` on veth: values named and typed from the ESI file of
// the slave's identity, and a slave the file does not describe refused with a sentence.
#include "veth_segment.hpp"

#include <codrive/testing/text.hpp>

#include <fmt/format.h>

namespace codrive::testing {
namespace {

const std::string kFioEsi = std::string(CODRIVE_SOURCE_DIR) + "/devices/fio.xml";

class EcatSdoEsi : public EcatVethTest {
protected:
    void SetUp() override {
        start({"--slave", "fio", "--slave", "akd2g"});
        link_.reset(); // the CLI opens its own socket
        master_.reset();
    }
    RunResult codrive(std::vector<std::string> args) {
        args.insert(args.begin(), tool_path("codrive"));
        return run(args);
    }
};

TEST_F(EcatSdoEsi, ReadAndWriteAreNamedAndTypedFromTheEsi) {
    const std::string iface = veth_->master_if();
    // 607Ah is INTEGER32 (DINT) in devices/fio.xml: a negative value needs no --type.
    auto w = codrive({"ecat", "sdo", "write", "--ethercat", iface, "-n", "0", "0x607A", "0",
                      "-1000", "--esi", kFioEsi});
    ASSERT_EQ(w.status, 0) << w.output;
    auto r = codrive(
        {"ecat", "sdo", "read", "--ethercat", iface, "-n", "0", "0x607A", "0", "--esi", kFioEsi});
    ASSERT_EQ(r.status, 0) << r.output;
    EXPECT_TRUE(has(r.output, "Target position: -1000")) << r.output;
    // A record's sub-index: its name from the DataType's SubItem (0x0048554B, unsigned).
    r = codrive(
        {"ecat", "sdo", "read", "--ethercat", iface, "-n", "0", "0x1018", "1", "--esi", kFioEsi});
    ASSERT_EQ(r.status, 0) << r.output;
    EXPECT_TRUE(has(r.output, "Vendor-ID: 4740427")) << r.output;
}

TEST_F(EcatSdoEsi, ASlaveTheEsiDoesNotDescribeIsRefused) {
    // Slave 1 is the AKD2G: Kollmorgen's identity, not the FIO file's.
    auto r = codrive({"ecat", "sdo", "read", "--ethercat", veth_->master_if(), "-n", "1", "0x6041",
                      "0", "--esi", kFioEsi});
    EXPECT_EQ(r.status, 1) << r.output;
    EXPECT_TRUE(has(r.output, "slave 1")) << r.output;
    EXPECT_TRUE(has(r.output, "the slave is vendor 0x0000006A product 0x11210100")) << r.output;
    EXPECT_TRUE(has(r.output, "fio.xml describes vendor 0x0048554B")) << r.output;
}

} // namespace
} // namespace codrive::testing
