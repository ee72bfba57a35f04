// SPDX-License-Identifier: Apache-2.0
// Kollmorgen AKD2G conformance (manual 000_*.txt, chapter 5): the object table and the
// behaviours fixed for issue 15, checked on both simulators (SDO over CAN, CoE over EtherCAT),
// on the device files and on the master's profile.
#include "conformance.hpp"

#include <array>

namespace codrive::conformance {
namespace {

TEST(Akd2gConformance, ObjectTableMatchesTheManual) {
    // Both simulators: SDO on the virtual CAN bus and CoE on the in-process EtherCAT link (the
    // dual-axis slave, the same DriveCore per axis).
    CanProbe can("akd2g");
    EcatProbe ecat("akd2g");
    check_facts("akd2g", drives::akd2g_profile(), &can, &ecat, DeviceFiles::of("akd2g"),
                akd2g_facts(), akd2g_known());
}

TEST(Akd2gConformance, PositionActualInternalValue6063hCounts2To12PerRevolution) {
    // §5.4.6: 6063h is in 2^(32-PSCALE) = 2^12 counts per rev by default; 6064h in 2^16.
    CanProbe probe("akd2g");
    auto& f = probe.fixture();
    ASSERT_TRUE(f.write<std::int8_t>(0x6060, 0, 3));      // PV
    ASSERT_TRUE(f.write<std::int32_t>(0x60FF, 0, 65536)); // 1 rev/s
    for (const int cw : {0x06, 0x07, 0x0F}) {
        ASSERT_TRUE(f.write<std::uint16_t>(0x6040, 0, static_cast<std::uint16_t>(cw)));
        f.run_ms(5);
    }
    f.run_ms(2000);
    ASSERT_TRUE(f.write<std::uint16_t>(0x6040, 0, 0x010F)); // halt: hold still to compare
    f.run_ms(1000);
    const auto actual = *f.read<std::int32_t>(0x6064, 0);
    const auto internal = *f.read<std::int32_t>(0x6063, 0);
    ASSERT_GT(actual, 65536) << "moved more than a revolution";
    EXPECT_NEAR(internal, actual / 16.0, 1.0);
}

TEST(Akd2gConformance, DynamicPdoMappingIsAcceptedWhileOperational) {
    // §5.2.31: "Dynamic mapping allows the content of the PDO to be changed while the drive is
    // running."
    CanProbe probe("akd2g");
    auto& f = probe.fixture();
    f.send(Frame::make(0x000, {0x01, 1}));                       // NMT start
    ASSERT_TRUE(f.write<std::uint32_t>(0x1801, 1, 0x80000281U)); // TPDO2 off
    const auto off = f.write<std::uint8_t>(0x1A01, 0, 0);
    ASSERT_TRUE(off) << off.error().to_string();
    ASSERT_TRUE(f.write<std::uint32_t>(0x1A01, 1, 0x60410010U));
    ASSERT_TRUE(f.write<std::uint8_t>(0x1A01, 0, 1));
    EXPECT_EQ(*f.read<std::uint32_t>(0x1A01, 1), 0x60410010U);
}

TEST(Akd2gConformance, AnalogModesTheSimulatorCannotRunAreRefused) {
    // §5.x lists -1 analog torque and -2 analog velocity; without an analog input the
    // simulator refuses them as an unsupported value (06090030h).
    CanProbe probe("akd2g");
    auto& f = probe.fixture();
    for (const std::int8_t mode : {std::int8_t{-1}, std::int8_t{-2}}) {
        const auto r = f.write<std::int8_t>(0x6060, 0, mode);
        ASSERT_FALSE(r) << int(mode);
        EXPECT_EQ(r.error().abort_code(), 0x06090030U) << int(mode);
    }
}

} // namespace
} // namespace codrive::conformance
