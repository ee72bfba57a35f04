// SPDX-License-Identifier: Apache-2.0
// Kuhnke FIO Drive Control conformance (manual 004_*.txt, chapter 7.13): the object table and
// the behaviours fixed for issue 15, checked on the EtherCAT simulator over CoE and on the
// master's profile.
#include "conformance.hpp"

#include <codrive/sim/sim_device.hpp>

#include <array>

namespace codrive::conformance {
namespace {

TEST(FioConformance, ObjectTableMatchesTheManual) {
    EcatProbe ecat("fio");
    check_facts("fio", drives::fio_profile(), nullptr, &ecat, DeviceFiles::of("fio"), fio_facts(),
                fio_known());
}

TEST(FioConformance, DefaultPdoMaps1600hTo1A03hComeFromTheProfileTable) {
    // §7.13.11-§7.13.18: every default map, entry count and entries, as the profile holds them.
    EcatProbe probe("fio");
    const auto& maps = drives::fio_profile().default_pdo_maps;
    ASSERT_EQ(maps.size(), 8U);
    for (const drives::DefaultPdoMap& m : maps) {
        const Reply n = probe.upload(m.index, 0);
        ASSERT_TRUE(n.ok) << std::hex << m.index;
        EXPECT_EQ(n.data.at(0), m.entries.size()) << std::hex << m.index;
        for (std::size_t i = 0; i < m.entries.size(); ++i) {
            const Reply e = probe.upload(m.index, static_cast<std::uint8_t>(i + 1));
            ASSERT_TRUE(e.ok);
            EXPECT_EQ(get_le<std::uint32_t>(e.data.data()), m.entries[i])
                << std::hex << m.index << ":" << i + 1;
        }
    }
    EXPECT_EQ(maps[1].entries.size(), 2U) << "§7.13.12: 1601h sub 0 = 02h";
    EXPECT_EQ(maps[7].entries.size(), 3U) << "§7.13.18: 1A03h sub 0 = 03h";
}

TEST(FioConformance, StatuswordBit8InCspSaysSynchronisedAndBit15StaysClear) {
    // §7.8.1.4: in CSP bit 8 = 1 "synchronised with the fieldbus"; §7.13 6041h bit 15 CLA = 1
    // only after a successful auto setup (which the simulator does not run).
    EcatProbe probe("fio");
    ASSERT_TRUE(drives::fio_profile().quirks.csp_bit8_synchronised);
    ASSERT_TRUE(probe.write<std::int8_t>(0x6060, 0, 8).ok);
    auto sw = [&] {
        const Reply r = probe.upload(0x6041, 0);
        EXPECT_TRUE(r.ok);
        return r.ok ? get_le<std::uint16_t>(r.data.data()) : std::uint16_t{0xFFFF};
    };
    probe.clock().advance(milliseconds(5));
    probe.master().poll_mailboxes();
    EXPECT_EQ(sw() & 0x0100, 0) << "PRE-OP: no process data, not synchronised";
    ASSERT_TRUE(probe.master().set_state_all(ethercat::AlState::Op)) << probe.master().last_error();
    probe.clock().advance(milliseconds(5));
    ASSERT_TRUE(probe.master().exchange_process_data()) << probe.master().last_error();
    EXPECT_EQ(sw() & 0x0100, 0x0100) << "OP in CSP: synchronised";
    EXPECT_EQ(sw() & 0x8000, 0) << "no auto setup: closed loop not available";
}

TEST(FioConformance, InterpolationTimeIndex60C2h02AcceptsOnlyMinus3) {
    EcatProbe probe("fio");
    const Reply minus4 = probe.write<std::int8_t>(0x60C2, 2, -4);
    ASSERT_FALSE(minus4.ok);
    EXPECT_EQ(minus4.abort & 0xFFFFFF00U, 0x06090000U) << std::hex << minus4.abort;
    EXPECT_TRUE(probe.write<std::int8_t>(0x60C2, 2, -3).ok);
}

TEST(FioConformance, SlaveStatus2110hFollowsTheEsmState) {
    // §7.13.51: bits 3..0 = 1 INIT, 2 PREOP, 4 SAFEOP, 8 OP.
    EcatProbe probe("fio");
    auto status = [&] {
        const Reply r = probe.upload(0x2110, 0);
        EXPECT_TRUE(r.ok);
        return r.ok ? get_le<std::uint16_t>(r.data.data()) & 0x0F : 0xFF;
    };
    EXPECT_EQ(status(), 0x02);
    ASSERT_TRUE(probe.master().set_state_all(ethercat::AlState::SafeOp))
        << probe.master().last_error();
    EXPECT_EQ(status(), 0x04);
    ASSERT_TRUE(probe.master().set_state_all(ethercat::AlState::Op)) << probe.master().last_error();
    EXPECT_EQ(status(), 0x08);
}

TEST(FioConformance, ErrorHistory1003hNumberComesFromTheProfileTable) {
    // §7.13.3: bits 31..24 error number, 23..16 error class, 15..0 error code. The number the
    // simulator records is the one the master's table pairs with the code (one table).
    EcatProbe probe("fio");
    ASSERT_TRUE(probe.write<std::uint8_t>(sim::kControlObject, sim::kControlOverCurrent, 1).ok);
    const Reply entry = probe.upload(0x1003, 1);
    ASSERT_TRUE(entry.ok);
    const auto v = get_le<std::uint32_t>(entry.data.data());
    EXPECT_EQ(v & 0xFFFF, 0x2300U);
    const drives::ErrorNumberRow* row =
        drives::fio_profile().error_number(static_cast<std::uint8_t>(v >> 24));
    ASSERT_NE(row, nullptr) << std::hex << v;
    EXPECT_EQ(row->typical_code, 0x2300U);
    EXPECT_EQ(v >> 24, 0x02U) << "output current too high";
}

TEST(FioConformance, ModesTheSimulatorCannotRunAreRefused) {
    // §7.2.1: 6060h takes -2..10; the simulator runs neither vl (2) nor clock/direction (-1)
    // nor auto setup (-2): refused with 06090030h instead of accepted and ignored.
    EcatProbe probe("fio");
    for (const std::int8_t mode : {std::int8_t{2}, std::int8_t{-1}, std::int8_t{-2}}) {
        const Reply r = probe.write<std::int8_t>(0x6060, 0, mode);
        ASSERT_FALSE(r.ok) << int(mode);
        EXPECT_EQ(r.abort, 0x06090030U) << int(mode);
    }
    EXPECT_TRUE(probe.write<std::int8_t>(0x6060, 0, 8).ok) << "CSP runs";
}

} // namespace
} // namespace codrive::conformance
