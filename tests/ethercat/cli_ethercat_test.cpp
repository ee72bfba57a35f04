// SPDX-License-Identifier: Apache-2.0
// `codrive scan|sdo|drive --ethercat IFACE`: the CAN commands over EtherCAT CoE on veth, with
// `-n` naming the slave by its position from 1 (issue 9, "Command line").
#include "veth_segment.hpp"

#include <codrive/testing/text.hpp>

#include <codrive/sim/sim_device.hpp>

#include <fmt/format.h>

namespace codrive::testing {
namespace {

/// "0x2FF0:2"
std::string fmt_control(std::uint16_t index, std::uint8_t sub) {
    return fmt::format("0x{:04X}:{}", index, sub);
}

class EcatCli : public EcatVethTest {
protected:
    void SetUp() override {
        // Started as the issue writes it: `codrive-sim --ethercat IFACE --slave fio --slave akd2g`.
        start({"--slave", "fio", "--slave", "akd2g"}, tool_path("codrive-sim"));
        if (IsSkipped() || HasFatalFailure()) {
            return;
        }
        link_.reset(); // the CLI opens its own socket
        iface_ = veth_->master_if();
    }
    RunResult codrive(std::vector<std::string> args) {
        args.insert(args.begin(), tool_path("codrive"));
        return run(args);
    }
    std::string iface_;
};

TEST_F(EcatCli, ScanListsTheSlavesByPositionFromOne) {
    if (IsSkipped() || HasFatalFailure()) {
        return;
    }
    auto r = codrive({"scan", "--ethercat", iface_});
    ASSERT_EQ(r.status, 0) << r.output;
    EXPECT_TRUE(has(r.output, "pos  station vendor     product    revision   name")) << r.output;
    EXPECT_TRUE(has(r.output, "  1  0x1001  0x0048554B 0x0002BA67 0x00000000 FIO Drive Control"))
        << r.output;
    EXPECT_TRUE(has(r.output, "  2  0x1002  0x0000006A 0x11210100 0x03010000 AKD2G")) << r.output;
    EXPECT_TRUE(has(r.output, "INIT")) << r.output;
    EXPECT_TRUE(has(r.output, "scanned 2 slave(s) on " + iface_)) << r.output;
    auto neither = codrive({"scan"});
    EXPECT_EQ(neither.status, 2) << neither.output;
    EXPECT_TRUE(has(neither.output, "scan needs -i IFACE (CAN) or --ethercat IFACE"));
}

TEST_F(EcatCli, SdoReadsAndWritesOverCoe) {
    if (IsSkipped() || HasFatalFailure()) {
        return;
    }
    auto vendor = codrive({"sdo", "read", "--ethercat", iface_, "-n", "2", "0x1018:1"});
    ASSERT_EQ(vendor.status, 0) << vendor.output;
    EXPECT_TRUE(has(vendor.output, "6A 00 00 00 (0x0000006A = 106)")) << vendor.output;
    auto typed =
        codrive({"sdo", "read", "--ethercat", iface_, "-n", "1", "0x1018:2", "--type", "u32"});
    ASSERT_EQ(typed.status, 0) << typed.output;
    EXPECT_EQ(typed.output, "178791\n");
    // A string longer than the mailbox: segmented both ways.
    std::string text;
    for (int i = 0; i < 12; ++i) {
        text += "segmented over CoE " + std::to_string(i) + "|";
    }
    auto w = codrive(
        {"sdo", "write", "--ethercat", iface_, "-n", "1", "0x5FFF:0", text, "--type", "str"});
    ASSERT_EQ(w.status, 0) << w.output;
    auto back =
        codrive({"sdo", "read", "--ethercat", iface_, "-n", "1", "0x5FFF:0", "--type", "str"});
    ASSERT_EQ(back.status, 0) << back.output;
    EXPECT_EQ(back.output, text + "\n");
    auto abort = codrive({"sdo", "read", "--ethercat", iface_, "-n", "1", "0x2345:0"});
    EXPECT_EQ(abort.status, 1);
    EXPECT_TRUE(has(abort.output, "codrive: slave 1 (FIO Drive Control): SDO upload 0x2345:00 "
                                  "aborted 0x06020000 (object does not exist"))
        << abort.output;
    auto missing = codrive({"sdo", "read", "--ethercat", iface_, "-n", "3", "0x1000:0"});
    EXPECT_EQ(missing.status, 1);
    EXPECT_TRUE(has(missing.output, "there is no slave at position 3 (2 found, numbered from 1)"))
        << missing.output;
    auto both = codrive({"sdo", "read", "-i", "vcan0", "--ethercat", iface_, "-n", "1", "0x1000"});
    EXPECT_EQ(both.status, 2) << both.output;
}

TEST_F(EcatCli, DriveEnablesMovesFaultsAndResetsAnAxisOverCoe) {
    if (IsSkipped() || HasFatalFailure()) {
        return;
    }
    auto enable = codrive({"drive", "--ethercat", iface_, "-n", "2", "enable"});
    ASSERT_EQ(enable.status, 0) << enable.output;
    EXPECT_TRUE(has(enable.output, "slave 2 axis 1 (Kollmorgen AKD2G): OPERATION ENABLED"))
        << enable.output;
    auto move = codrive({"drive", "--ethercat", iface_, "-n", "2", "move", "--pp", "65536"});
    ASSERT_EQ(move.status, 0) << move.output;
    EXPECT_TRUE(has(move.output, "mode profile position (PP), position 65536")) << move.output;
    auto fio = codrive({"drive", "--ethercat", iface_, "-n", "1", "status"});
    ASSERT_EQ(fio.status, 0) << fio.output;
    EXPECT_TRUE(has(fio.output, "slave 1 axis 1 (Kuhnke FIO Drive Control)")) << fio.output;
    // An over-current injected through the simulator's control object, then reset.
    auto inject =
        codrive({"sdo", "write", "--ethercat", iface_, "-n", "2",
                 fmt_control(sim::kControlObject, sim::kControlOverCurrent), "1", "--type", "u8"});
    ASSERT_EQ(inject.status, 0) << inject.output;
    auto faulted = codrive({"drive", "--ethercat", iface_, "-n", "2", "status"});
    EXPECT_TRUE(has(faulted.output, "FAULT")) << faulted.output;
    auto reset = codrive({"drive", "--ethercat", iface_, "-n", "2", "reset"});
    ASSERT_EQ(reset.status, 0) << reset.output;
    EXPECT_TRUE(has(reset.output, "SWITCH ON DISABLED")) << reset.output;
}

} // namespace
} // namespace codrive::testing
