// SPDX-License-Identifier: Apache-2.0
// Kuhnke FIO Drive Control conformance (manual 004_*.txt, chapter 7.13): the object table and
// the behaviours fixed for issue 15, checked on the EtherCAT simulator over CoE and on the
// master's profile.
#include "conformance.hpp"

#include <codrive/sim/sim_device.hpp>

#include <array>

namespace codrive::conformance {
namespace {

using DT = DataType;

// clang-format off
const std::array kFacts{
    Fact{0x1003, 0, DT::Unsigned8, Acc::Rw, 0, "§7.13.3", false},
    Fact{0x1003, 8, DT::Unsigned32, Acc::Ro, 0, "§7.13.3 (sub 01h..08h)", false},
    Fact{0x1003, 9, DT::Unsigned32, Acc::Absent, std::nullopt, "§7.13.3 (sub 01h..08h)", false},
    Fact{0x1018, 1, DT::Unsigned32, Acc::Ro, 0x0048554B, "§7.13 1018h", false},
    Fact{0x1C32, 0, DT::Unsigned8, Acc::Ro, 5, "§7.13.22", false},
    Fact{0x1C32, 2, DT::Unsigned32, Acc::Rw, 0, "§7.13.22", false},
    Fact{0x1C33, 0, DT::Unsigned8, Acc::Ro, 3, "§7.13.23", false},
    Fact{0x1C33, 3, DT::Unsigned32, Acc::Rw, 0, "§7.13.23", false},
    Fact{0x2110, 0, DT::Unsigned16, Acc::Ro, std::nullopt, "§7.13.51", false},
    Fact{0x3202, 0, DT::Unsigned32, Acc::Rw, 0, "§7.13.52"},
    Fact{0x607A, 0, DT::Integer32, Acc::Rw, 4000, "§7.13.115"},
    Fact{0x608F, 1, DT::Unsigned32, Acc::Rw, 2000, "§7.13.13x 608Fh"},
    Fact{0x608F, 2, DT::Unsigned32, Acc::Rw, 1, "§7.13.13x 608Fh"},
    Fact{0x6099, 2, DT::Unsigned32, Acc::Rw, 1, "§7.13 6099h"},
    Fact{0x60A8, 0, DT::Unsigned32, Acc::Rw, 0xFF410000LL, "§7.13.140"},
    Fact{0x60A9, 0, DT::Unsigned32, Acc::Rw, 0x00B44700LL, "§7.13.141"},
    Fact{0x60C2, 2, DT::Integer8, Acc::Rw, -3, "§7.13.146"},
};
// clang-format on

TEST(FioConformance, ObjectTableMatchesTheManual) {
    EcatProbe probe("fio");
    check_facts("fio", drives::fio_profile(), probe, kFacts);
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
