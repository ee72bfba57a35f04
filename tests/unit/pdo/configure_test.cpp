// SPDX-License-Identifier: Apache-2.0
// Remote PDO configuration: byte-exact SDO sequences for standard, DS-BVS and AKD2G nodes.
#include "pdo_rig.hpp"

#include <gtest/gtest.h>

#include <string>
#include <vector>

using namespace codrive;
using namespace codrive::pdo;
using namespace codrive::pdo::test;

namespace {

std::vector<std::string> recorded_text(const VirtualNetwork& net) {
    std::vector<std::string> out;
    for (const auto& f : net.recorded()) {
        out.push_back(to_string(f));
    }
    return out;
}

PdoConfig status_position_tpdo() {
    return tpdo(1, {entry(0x6041, 0, 16), entry(0x6064, 0, 32)}, 1);
}

} // namespace

TEST(PdoConfigure, StandardNodeSequenceIsByteExact) {
    Rig rig(3);
    rig.net.set_recording(true);
    auto r = rig.configure({status_position_tpdo()});
    ASSERT_TRUE(r) << r.error().message;
    EXPECT_EQ(r->writes, 9U);
    const std::vector<std::string> want = {
        // 1. destroy the PDO: COB-ID 0x183 with bit 31 (invalid) and bit 30 (no RTR)
        "603#23001801830100C0",
        "583#6000180100000000",
        // 2. transmission type 1, inhibit time 0, event timer 0
        "603#2F00180201000000",
        "583#6000180200000000",
        "603#2B00180300000000",
        "583#6000180300000000",
        "603#2B00180500000000",
        "583#6000180500000000",
        // 3. mapping count 0, entries, count 2
        "603#2F001A0000000000",
        "583#60001A0000000000",
        "603#23001A0110004160",
        "583#60001A0100000000",
        "603#23001A0220006460",
        "583#60001A0200000000",
        "603#2F001A0002000000",
        "583#60001A0000000000",
        // 4. create the PDO again
        "603#2300180183010040",
        "583#6000180100000000",
    };
    EXPECT_EQ(recorded_text(rig.net), want);
    EXPECT_TRUE(rig.device->active(PdoDir::Tpdo, 1));
}

TEST(PdoConfigure, WritesListMatchesCia301Procedure) {
    auto writes = configuration_writes(
        5, rpdo(2, {entry(0x6040, 0, 16), entry(0x60FF, 0, 32)}, 255), quirks::standard());
    std::vector<std::string> text;
    for (const auto& w : writes) {
        text.push_back(to_string(w));
    }
    EXPECT_EQ(text, (std::vector<std::string>{
                        "0x1401:01 = 0x80000305 (invalidate RPDO2)",
                        "0x1401:02 = 0xFF (RPDO2 transmission type)",
                        "0x1601:00 = 0x00 (disable RPDO2 mapping)",
                        "0x1601:01 = 0x60400010 (RPDO2 mapping entry 1)",
                        "0x1601:02 = 0x60FF0020 (RPDO2 mapping entry 2)",
                        "0x1601:00 = 0x02 (RPDO2 mapping count)",
                        "0x1401:01 = 0x00000305 (validate RPDO2)",
                    }));
}

TEST(PdoConfigure, SyncStartValueIsWrittenWhenSet) {
    PdoConfig p = status_position_tpdo();
    p.comm.sync_start = 4;
    p.comm.inhibit_time = 10;
    p.comm.event_timer = 20;
    auto writes = configuration_writes(3, p, quirks::standard());
    ASSERT_EQ(writes.size(), 10U);
    EXPECT_EQ(to_string(writes[2]), "0x1800:03 = 0x000A (TPDO1 inhibit time)");
    EXPECT_EQ(to_string(writes[3]), "0x1800:05 = 0x0014 (TPDO1 event timer)");
    EXPECT_EQ(to_string(writes[4]), "0x1800:06 = 0x04 (TPDO1 SYNC start value)");
}

TEST(PdoConfigure, DsBvsSequenceLeavesReadOnlyCobIdAlone) {
    PdoObjectDefaults d;
    d.tpdo_transmission_type = 0; // DS-BVS default (spec §0 item 3)
    Rig rig(1, quirks::ds_bvs(), d);
    rig.net.set_recording(true);
    auto r = rig.configure({status_position_tpdo()});
    ASSERT_TRUE(r) << r.error().message;
    const std::vector<std::string> want = {
        "601#2F001A0000000000", "581#60001A0000000000", // count 0 (disables the PDO) first
        "601#2F00180201000000", "581#6000180200000000", // type 1
        "601#2B00180300000000", "581#6000180300000000", // inhibit 0
        "601#2B00180500000000", "581#6000180500000000", // event timer 0
        "601#23001A0110004160", "581#60001A0100000000",
        "601#23001A0220006460", "581#60001A0200000000",
        "601#2F001A0002000000", "581#60001A0000000000", // count 2 (enables it)
    };
    EXPECT_EQ(recorded_text(rig.net), want);
    EXPECT_TRUE(rig.device->active(PdoDir::Tpdo, 1));
    // The COB-ID stayed the read-only default with bit 30 (no RTR).
    EXPECT_EQ(rig.od.get<std::uint32_t>(0x1800, 1), 0x40000181U);
}

TEST(PdoConfigure, DsBvsActivePdoFromAnEarlierBootIsConfiguredAgain) {
    // The second boot of the same bus file: TPDO1 is still active (mapping count 2), so the
    // device refuses its inhibit time (CiA 301 §7.5.2.37) until mapping count 0 disables it.
    Rig rig(1, quirks::ds_bvs());
    PdoConfig p = status_position_tpdo();
    p.comm.inhibit_time = 10;
    ASSERT_TRUE(rig.configure({p}));
    ASSERT_TRUE(rig.device->active(PdoDir::Tpdo, 1));
    p.comm.inhibit_time = 20;
    auto again = rig.configure({p});
    ASSERT_TRUE(again) << again.error().message;
    EXPECT_TRUE(rig.device->active(PdoDir::Tpdo, 1));
    EXPECT_EQ(rig.od.get<std::uint16_t>(0x1800, 3), 20);
    EXPECT_EQ(rig.od.get<std::uint8_t>(0x1A00, 0), 2);
}

TEST(PdoConfigure, DsBvsDisablesPdoByMappingCountZero) {
    Rig rig(1, quirks::ds_bvs());
    ASSERT_TRUE(rig.configure({status_position_tpdo()}));
    ASSERT_TRUE(rig.device->active(PdoDir::Tpdo, 1));
    PdoConfig off = status_position_tpdo();
    off.enabled = false;
    auto writes = configuration_writes(1, off, quirks::ds_bvs());
    ASSERT_EQ(writes.size(), 1U);
    EXPECT_EQ(to_string(writes[0]), "0x1A00:00 = 0x00 (disable TPDO1 mapping)");
    ASSERT_TRUE(rig.configure({off}));
    EXPECT_FALSE(rig.device->active(PdoDir::Tpdo, 1));
}

TEST(PdoConfigure, DsBvsRefusesACobIdChangeBeforeWriting) {
    Rig rig(1, quirks::ds_bvs());
    rig.net.set_recording(true);
    PdoConfig p = status_position_tpdo();
    p.comm.can_id = 0x1A1;
    auto r = rig.configure({p});
    ASSERT_FALSE(r);
    EXPECT_EQ(r.error().message,
              "node 1: TPDO1 COB-ID 0x1A1 cannot be set: DS-BVS PDO COB-IDs are read-only");
    EXPECT_TRUE(rig.net.recorded().empty());
}

TEST(PdoConfigure, Akd2gSequenceInvalidatesAndRevalidatesWithoutSyncStart) {
    Rig rig(7, quirks::akd2g());
    rig.net.set_recording(true);
    auto r = rig.configure(
        {rpdo(1, {entry(0x6040, 0, 16), entry(0x607A, 0, 32)}, 1), status_position_tpdo()});
    ASSERT_TRUE(r) << r.error().message;
    const std::vector<std::string> want = {
        "607#2300140107020080", "587#6000140100000000", // RPDO1 invalid 0x207
        "607#2F00140201000000", "587#6000140200000000", // type 1 (no sub 5 on AKD2G RPDOs)
        "607#2F00160000000000", "587#6000160000000000", "607#2300160110004060",
        "587#6000160100000000", "607#2300160220007A60", "587#6000160200000000",
        "607#2F00160002000000", "587#6000160000000000", "607#2300140107020000",
        "587#6000140100000000",                         // RPDO1 valid
        "607#23001801870100C0", "587#6000180100000000", // TPDO1 invalid 0x187, no RTR
        "607#2F00180201000000", "587#6000180200000000", "607#2B00180300000000",
        "587#6000180300000000", "607#2B00180500000000", "587#6000180500000000",
        "607#2F001A0000000000", "587#60001A0000000000", "607#23001A0110004160",
        "587#60001A0100000000", "607#23001A0220006460", "587#60001A0200000000",
        "607#2F001A0002000000", "587#60001A0000000000", "607#2300180187010040",
        "587#6000180100000000",
    };
    EXPECT_EQ(recorded_text(rig.net), want);
}

// A device that maps only in pre-operational (the AKD2G does not: manual §5.2.31 dynamic
// mapping; this rule is kept as a device option).
TEST(PdoConfigure, PreOperationalOnlyMappingRefusedInOperationalAndTheErrorSaysWhy) {
    PdoQuirks q = quirks::akd2g();
    q.mapping_only_pre_operational = true;
    EXPECT_FALSE(quirks::akd2g().mapping_only_pre_operational) << "§5.2.31";
    Rig rig(7, q);
    rig.device->set_operational(true, rig.clock.now());
    auto r = rig.configure({status_position_tpdo()});
    ASSERT_FALSE(r);
    EXPECT_EQ(r.error().code, make_error_code(PdoErrc::SdoFailed));
    EXPECT_NE(r.error().message.find("node 7: configuring TPDO1 failed at 0x1A00:00 = 0x00 "
                                     "(disable TPDO1 mapping)"),
              std::string::npos)
        << r.error().message;
    EXPECT_NE(r.error().message.find("0x08000022"), std::string::npos) << r.error().message;
}

TEST(PdoConfigure, Akd2gMapsAreRewrittenAfterBoot) {
    // Maps are volatile: after a reboot (a fresh dictionary) the same configuration is simply
    // written again, with the same sequence.
    for (int boot = 0; boot < 2; ++boot) {
        Rig rig(7, quirks::akd2g());
        ASSERT_TRUE(rig.configure({status_position_tpdo()}));
        EXPECT_TRUE(rig.device->active(PdoDir::Tpdo, 1));
    }
    EXPECT_TRUE(quirks::akd2g().maps_volatile);
}

TEST(PdoConfigure, DeviceAbortIsReportedWithTheFailingWrite) {
    // Skip local validation (no OD given) so the device's own check answers.
    Rig rig(3);
    DeviceModel blind;
    PdoConfigurator cfg(*rig.client, blind);
    std::optional<PdoResult<ConfigureReport>> out;
    cfg.configure({tpdo(1, {entry(0x607A, 0, 32)}, 1)},
                  [&](PdoResult<ConfigureReport> r) { out = std::move(r); });
    for (int i = 0; i < 100 && !out; ++i) {
        rig.run(milliseconds(1));
    }
    ASSERT_TRUE(out.has_value());
    ASSERT_FALSE(*out);
    EXPECT_NE(out->error().message.find("0x1A00:01 = 0x607A0020 (TPDO1 mapping entry 1)"),
              std::string::npos)
        << out->error().message;
    EXPECT_NE(out->error().message.find("0x06040041"), std::string::npos) << out->error().message;
}

TEST(PdoReadBack, ReadsWhatWasConfiguredAndPrintsATable) {
    Rig rig(3);
    PdoConfig t = status_position_tpdo();
    t.comm.inhibit_time = 50;
    t.comm.event_timer = 100;
    ASSERT_TRUE(rig.configure({rpdo(1, {entry(0x6040, 0, 16), entry(0x607A, 0, 32)}, 255), t}));
    auto r = rig.read_back();
    ASSERT_TRUE(r) << r.error().message;
    ASSERT_EQ(r->pdos.size(), 8U);
    const PdoConfig* t1 = r->find(PdoDir::Tpdo, 1);
    ASSERT_NE(t1, nullptr);
    EXPECT_TRUE(t1->enabled);
    EXPECT_EQ(t1->comm.can_id, 0x183U);
    EXPECT_EQ(t1->comm.transmission_type, 1);
    EXPECT_EQ(t1->comm.inhibit_time, 50);
    EXPECT_EQ(t1->comm.event_timer, 100);
    EXPECT_EQ(t1->mapping, t.mapping);
    const PdoConfig* r1 = r->find(PdoDir::Rpdo, 1);
    ASSERT_NE(r1, nullptr);
    EXPECT_EQ(r1->mapping.size(), 2U);
    const std::string table = r->to_string(&rig.od);
    EXPECT_NE(table.find("TPDO1  0x183       yes    1 (every SYNC)              5000 us  100 ms  "
                         "6      0x6041:00/16 (Statusword) 0x6064:00/32 (Position actual value)"),
              std::string::npos)
        << table;
    EXPECT_NE(table.find("RPDO1  0x203       yes    255 (event, profile)"), std::string::npos)
        << table;
}

TEST(PdoReadBack, MissingOptionalSubIndexesBecomeNotes) {
    Rig rig(1, quirks::ds_bvs());
    auto r = rig.read_back();
    ASSERT_TRUE(r) << r.error().message;
    EXPECT_EQ(r->pdos.size(), 8U);
    ASSERT_FALSE(r->notes.empty());
    EXPECT_EQ(r->notes.front(), "TPDO1 has no sub-index 06h");
    const PdoConfig* t1 = r->find(PdoDir::Tpdo, 1);
    ASSERT_NE(t1, nullptr);
    EXPECT_FALSE(t1->comm.rtr_allowed);
}
