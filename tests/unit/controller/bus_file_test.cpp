// SPDX-License-Identifier: Apache-2.0
// The bus file's sections: a CAN `bus:` and an `ethercat:` segment side by side, with every
// finding reported by line (pure parsing, no I/O).
#include <codrive/controller/ethercat_segment.hpp>
#include <codrive/master/bus_config.hpp>

#include <codrive/testing/text.hpp>

#include <gtest/gtest.h>

#include <fstream>
#include <sstream>

using namespace codrive;
using namespace codrive::controller;
using codrive::testing::joined;

TEST(ControllerBusFile, EthercatSectionParsesNextToTheCanBus) {
    const std::string text = "bus:\n"
                             "  interface: vcan0\n"
                             "ethercat:\n"
                             "  interface: ecm0\n"
                             "  cycle_us: 2000\n"
                             "  lost_frames_event: 5\n"
                             "  slaves:\n"
                             "    - {position: 0, name: table, profile: fio, axes: [{axis: 1, "
                             "mode: csp}]}\n"
                             "nodes:\n"
                             "  - id: 1\n"
                             "    profile: akd2g\n";
    const auto s = split_bus_file(text, "bus.yml");
    ASSERT_TRUE(s.errors.empty()) << s.errors.front();
    EXPECT_TRUE(s.has_can);
    ASSERT_TRUE(s.ethercat);
    EXPECT_EQ(s.ethercat->iface, "ecm0");
    EXPECT_EQ(s.ethercat->cycle_us, 2000U);
    EXPECT_EQ(s.ethercat->lost_frames_event, 5U);
    ASSERT_EQ(s.ethercat->slaves.size(), 1U);
    EXPECT_EQ(s.ethercat->slaves[0].profile, "fio");
    EXPECT_EQ(s.ethercat->slaves[0].name, "table");
    ASSERT_EQ(s.ethercat->slaves[0].axes.size(), 1U);
    EXPECT_EQ(s.ethercat->slaves[0].axes[0].mode, std::int8_t{8});
    // The CAN part keeps its line numbers: `nodes:` is still on line 9.
    auto can = master::parse_bus_config(s.can_text, "bus.yml");
    ASSERT_TRUE(can.config) << can.to_string();
    ASSERT_EQ(can.config->nodes.size(), 1U);
    auto bad = master::parse_bus_config(s.can_text + "  - id: 1\n", "bus.yml");
    ASSERT_FALSE(bad.config);
    EXPECT_NE(bad.to_string().find("bus.yml:12:"), std::string::npos) << bad.to_string();
}

TEST(ControllerBusFile, EthercatSectionReportsEveryFindingWithItsLine) {
    const std::string text = "ethercat:\n"
                             "  cycle_us: 5\n"
                             "  lost_frames_event: 0\n"
                             "  slaves:\n"
                             "    - {position: 0, profile: fio, axes: [{axis: 1, mode: warp}]}\n"
                             "    - {position: 0, profile: nosuch}\n"
                             "    - {position: 1, profile: fio, speed: 3}\n";
    const auto s = split_bus_file(text, "e.yml");
    EXPECT_FALSE(s.ethercat);
    std::string all;
    for (const auto& e : s.errors) {
        all += e + "\n";
    }
    EXPECT_NE(all.find("e.yml:1: `ethercat` needs `interface: IFACE`"), std::string::npos) << all;
    EXPECT_NE(all.find("e.yml:2: `ethercat.cycle_us` must be"), std::string::npos) << all;
    EXPECT_NE(all.find("e.yml:3: `ethercat.lost_frames_event` must be a number of frames, 1..1000"),
              std::string::npos)
        << all;
    EXPECT_NE(all.find("e.yml:5: slave 0 axis 1: unknown mode `warp`"), std::string::npos) << all;
    EXPECT_NE(all.find("e.yml:6: slave 0: unknown profile `nosuch`"), std::string::npos) << all;
    EXPECT_NE(all.find("e.yml:6: slave position 0 is configured twice"), std::string::npos) << all;
    EXPECT_NE(all.find("e.yml:7: unknown key `speed` in an EtherCAT slave"), std::string::npos)
        << all;
}

TEST(ControllerBusFile, EthercatAxesMustBeNumberedFromOneWithoutGaps) {
    const std::string ok = "ethercat:\n"
                           "  interface: ecm0\n"
                           "  slaves:\n"
                           "    - position: 0\n"
                           "      profile: akd2g\n"
                           "      axes:\n"
                           "        - {axis: 2, mode: csp}\n"
                           "        - {axis: 1, mode: csv}\n";
    auto s = controller::split_bus_file(ok, "d.yml");
    ASSERT_TRUE(s.ethercat) << (s.errors.empty() ? "" : s.errors[0]);
    ASSERT_EQ(s.ethercat->slaves[0].axes.size(), 2U);
    EXPECT_EQ(s.ethercat->slaves[0].axes[0].axis, 2U);
    const std::string gap = "ethercat:\n"
                            "  interface: ecm0\n"
                            "  slaves:\n"
                            "    - position: 0\n"
                            "      profile: akd2g\n"
                            "      axes:\n"
                            "        - {axis: 2, mode: csp}\n";
    s = controller::split_bus_file(gap, "d.yml");
    EXPECT_FALSE(s.ethercat);
    ASSERT_EQ(s.errors.size(), 1U);
    EXPECT_EQ(s.errors[0], "d.yml:4: slave 0: the axes must be numbered 1..n, each once (axis n "
                           "goes into RxPDO/TxPDO n); akd2g has axes 2");
}

TEST(ControllerBusFile, FileWithoutAnySectionIsRejected) {
    const auto s = split_bus_file("foo: 1\n", "x.yml");
    ASSERT_EQ(s.errors.size(), 1U);
    EXPECT_NE(s.errors[0].find("neither a `bus:` (CAN) nor an `ethercat:` section"),
              std::string::npos);
}

TEST(ControllerBusFile, DcAndSync0ShiftPerSegmentWithASlaveOverride) {
    const std::string text = "ethercat:\n"
                             "  interface: ecm0\n"
                             "  cycle_us: 1000\n"
                             "  dc: true\n"
                             "  sync0_shift_us: 100\n"
                             "  slaves:\n"
                             "    - {position: 0, profile: fio}\n"
                             "    - {position: 1, profile: fio, dc: false}\n"
                             "    - {position: 2, profile: fio, sync0_shift_us: 250}\n";
    const auto s = split_bus_file(text, "dc.yml");
    ASSERT_TRUE(s.ethercat) << joined(s.errors);
    const auto& seg = *s.ethercat;
    EXPECT_TRUE(slave_dc(seg, seg.slaves[0]));
    EXPECT_EQ(slave_sync0_shift_us(seg, seg.slaves[0]), 100U);
    EXPECT_FALSE(slave_dc(seg, seg.slaves[1]));
    EXPECT_TRUE(slave_dc(seg, seg.slaves[2]));
    EXPECT_EQ(slave_sync0_shift_us(seg, seg.slaves[2]), 250U);
    // Without `dc` a segment runs free (sync mode 0).
    const auto plain = split_bus_file("ethercat:\n  interface: ecm0\n  slaves:\n"
                                      "    - {position: 0, profile: fio}\n",
                                      "p.yml");
    ASSERT_TRUE(plain.ethercat) << joined(plain.errors);
    EXPECT_FALSE(slave_dc(*plain.ethercat, plain.ethercat->slaves[0]));
}

TEST(ControllerBusFile, SyncModeFreeSmOrDcPerSegmentWithSlaveOverrides) {
    const std::string text = "ethercat:\n"
                             "  interface: ecm0\n"
                             "  sync: sm\n"
                             "  slaves:\n"
                             "    - {position: 0, profile: fio}\n"
                             "    - {position: 1, profile: fio, sync: free}\n"
                             "    - {position: 2, profile: fio, sync: dc, sync0_shift_us: 50}\n"
                             "    - {position: 3, profile: fio, dc: true}\n";
    const auto s = split_bus_file(text, "sm.yml");
    ASSERT_TRUE(s.ethercat) << joined(s.errors);
    const auto& seg = *s.ethercat;
    EXPECT_EQ(slave_sync(seg, seg.slaves[0]), ethercat::SyncMode::SmSynchronous);
    EXPECT_EQ(slave_sync(seg, seg.slaves[1]), ethercat::SyncMode::FreeRun);
    EXPECT_EQ(slave_sync(seg, seg.slaves[2]), ethercat::SyncMode::DcSync0);
    EXPECT_EQ(slave_sync(seg, seg.slaves[3]), ethercat::SyncMode::DcSync0);
    // Findings: an unknown mode, `sync` and `dc` that disagree, a shift without DC.
    const std::string bad = "ethercat:\n"
                            "  interface: ecm0\n"
                            "  sync: sync1\n"
                            "  slaves:\n"
                            "    - {position: 0, profile: fio, sync: sm, dc: true}\n"
                            "    - {position: 1, profile: fio, sync: sm, sync0_shift_us: 5}\n";
    const auto b = split_bus_file(bad, "b.yml");
    EXPECT_FALSE(b.ethercat);
    const std::string all = joined(b.errors);
    EXPECT_NE(all.find("b.yml:3: `ethercat.sync` must be free, sm or dc (ETG.1020 sync modes 0, "
                       "1, 2), but it is `sync1`"),
              std::string::npos)
        << all;
    EXPECT_NE(all.find("b.yml:5: slave 0: `sync: sm` and `dc: true` disagree: give `sync:` alone"),
              std::string::npos)
        << all;
    EXPECT_NE(all.find("b.yml:6: slave 1: `sync0_shift_us` needs `dc: true`"), std::string::npos)
        << all;
}

TEST(ControllerBusFile, BadDcAndSync0ShiftValuesAreFindingsWithTheirLines) {
    const std::string text = "ethercat:\n"
                             "  interface: ecm0\n"
                             "  cycle_us: 1000\n"
                             "  dc: maybe\n"
                             "  slaves:\n"
                             "    - {position: 0, profile: fio, dc: [1]}\n"
                             "    - {position: 1, profile: fio, dc: true, sync0_shift_us: 1000}\n"
                             "    - {position: 2, profile: fio, dc: false, sync0_shift_us: 5}\n"
                             "    - {position: 3, profile: fio, dc: true, sync0_shift_us: -1}\n";
    const auto s = split_bus_file(text, "e.yml");
    EXPECT_FALSE(s.ethercat);
    const std::string all = joined(s.errors);
    EXPECT_NE(all.find("e.yml:4: `ethercat.dc` must be true or false, but it is `maybe`"),
              std::string::npos)
        << all;
    EXPECT_NE(all.find("e.yml:6: slave 0: `dc` must be true or false, but it is a list"),
              std::string::npos)
        << all;
    EXPECT_NE(all.find("e.yml:7: slave 1: `sync0_shift_us` must be a number of microseconds, "
                       "0..999 (less than the cycle of 1000 µs)"),
              std::string::npos)
        << all;
    EXPECT_NE(all.find("e.yml:8: slave 2: `sync0_shift_us` needs `dc: true` (SYNC0 exists only "
                       "with distributed clocks)"),
              std::string::npos)
        << all;
    EXPECT_NE(all.find("e.yml:9: slave 3: `sync0_shift_us` must be a number of microseconds"),
              std::string::npos)
        << all;
    EXPECT_EQ(s.errors.size(), 5U) << all;
    // A shift on the segment without DC names the segment key.
    const auto no_dc = split_bus_file("ethercat:\n  interface: ecm0\n  sync0_shift_us: 10\n"
                                      "  slaves:\n    - {position: 0, profile: fio}\n",
                                      "n.yml");
    ASSERT_EQ(no_dc.errors.size(), 1U) << joined(no_dc.errors);
    EXPECT_EQ(no_dc.errors[0], "n.yml:3: `ethercat.sync0_shift_us` needs `dc: true` (SYNC0 "
                               "exists only with distributed clocks)");
}

TEST(ControllerBusFile, TheDcExampleOfTheDocsParsesAsPrinted) {
    // docs/bus-file.md, the `dc: true` example, exactly as printed there.
    std::ifstream in(std::string(CODRIVE_SOURCE_DIR) + "/docs/bus-file.md");
    std::stringstream doc;
    doc << in.rdbuf();
    const std::string text = doc.str();
    const auto at = text.find("sync0_shift_us: 100");
    ASSERT_NE(at, std::string::npos) << "docs/bus-file.md lost its DC example";
    const auto begin = text.rfind("```yaml\n", at);
    const auto end = text.find("```", at);
    ASSERT_TRUE(begin != std::string::npos && end != std::string::npos);
    const auto s = split_bus_file(text.substr(begin + 8, end - begin - 8), "bus-file.md");
    ASSERT_TRUE(s.ethercat) << joined(s.errors);
    const auto& seg = *s.ethercat;
    EXPECT_EQ(seg.cycle_us, 1000U);
    ASSERT_EQ(seg.slaves.size(), 2U);
    EXPECT_TRUE(slave_dc(seg, seg.slaves[0]));
    EXPECT_EQ(slave_sync0_shift_us(seg, seg.slaves[0]), 100U);
    EXPECT_FALSE(slave_dc(seg, seg.slaves[1]));
}

TEST(ControllerBusFile, TheSmExampleOfTheDocsParsesAsPrinted) {
    // docs/bus-file.md, the `sync: sm` example, exactly as printed there.
    std::ifstream in(std::string(CODRIVE_SOURCE_DIR) + "/docs/bus-file.md");
    std::stringstream doc;
    doc << in.rdbuf();
    const std::string text = doc.str();
    const auto at = text.find("sync: sm               #");
    ASSERT_NE(at, std::string::npos) << "docs/bus-file.md lost its `sync: sm` example";
    const auto begin = text.rfind("```yaml\n", at);
    const auto end = text.find("```", at);
    ASSERT_TRUE(begin != std::string::npos && end != std::string::npos);
    const auto s = split_bus_file(text.substr(begin + 8, end - begin - 8), "bus-file.md");
    ASSERT_TRUE(s.ethercat) << joined(s.errors);
    const auto& seg = *s.ethercat;
    ASSERT_EQ(seg.slaves.size(), 2U);
    EXPECT_EQ(slave_sync(seg, seg.slaves[0]), ethercat::SyncMode::SmSynchronous);
    EXPECT_EQ(slave_sync(seg, seg.slaves[1]), ethercat::SyncMode::FreeRun);
}
