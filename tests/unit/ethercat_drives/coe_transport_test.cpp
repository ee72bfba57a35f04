// SPDX-License-Identifier: Apache-2.0
// drives::Axis on the CoE DriveTransport against a simulated EtherCAT drive (in-process).
#include <codrive/drives/axis.hpp>
#include <codrive/ethercat/coe_transport.hpp>
#include <codrive/testing/sim_segment.hpp>

#include <gtest/gtest.h>

namespace codrive::ethercat {
namespace {

class CoeTransportTest : public codrive::testing::SimSegmentTest {
protected:
    CoeTransportTest() {
        segment_.add(sim::ecat::make_drive_slave("akd2g", 5));
        segment_.add(sim::ecat::make_drive_slave("fio", 6));
    }
    /// One control cycle: acyclic work, LRW, axis update.
    void cycle(drives::Axis& axis, CoeTransport& t) {
        t.poll();
        ASSERT_TRUE(master_.exchange_process_data()) << master_.last_error();
        axis.on_cycle(clock_.now());
        clock_.advance(milliseconds(1));
    }
};

TEST_F(CoeTransportTest, ObjectAccessCompletesOnPollNotInsideTheCall) {
    bring_up(AlState::Op);
    CoeTransport t(master_, 0);
    EXPECT_EQ(t.name(), "slave 0 (AKD2G)");
    std::optional<std::uint32_t> vendor;
    t.read_as<std::uint32_t>(0x1018, 1, [&](drives::DriveResult<std::uint32_t> r) {
        ASSERT_TRUE(r);
        vendor = *r;
    });
    EXPECT_FALSE(vendor);
    EXPECT_EQ(t.poll(), 1U);
    EXPECT_EQ(vendor, 0x6AU);
    std::optional<std::string> error;
    t.read(0x2345, 3, [&](drives::DriveResult<drives::Bytes> r) {
        ASSERT_FALSE(r);
        error = r.error().message;
    });
    t.poll();
    ASSERT_TRUE(error);
    EXPECT_NE(error->find("slave 0 (AKD2G): SDO upload 0x2345:03 aborted 0x06020000"),
              std::string::npos)
        << *error;
}

TEST_F(CoeTransportTest, CyclicHandlesResolveAgainstTheMappedPdos) {
    bring_up(AlState::Op);
    CoeTransport t(master_, 1); // FIO: 6040 607A 3202 6060 / 6041 6064 6061
    EXPECT_TRUE(t.output(0x6040, 0).valid());
    EXPECT_TRUE(t.output(0x607A, 0).valid());
    EXPECT_TRUE(t.input(0x6064, 0).valid());
    EXPECT_FALSE(t.input(0x606C, 0).valid()); // not mapped by default
    EXPECT_FALSE(t.output(0x6041, 0).valid());
}

TEST_F(CoeTransportTest, AxisEnablesOverTheCyclicControlwordOnEtherCat) {
    bring_up(AlState::Op);
    CoeTransport t(master_, 1); // FIO
    drives::AxisConfig cfg;
    drives::Axis axis(t, cfg);
    axis.bind();
    std::optional<drives::DriveVoid> mode_set;
    t.write_as<std::int8_t>(0x6060, 0, 8, [&](drives::DriveVoid r) { mode_set = r; }); // CSP
    t.poll();
    ASSERT_TRUE(mode_set && *mode_set);
    std::optional<drives::DriveVoid> enabled;
    axis.enable([&](drives::DriveVoid r) { enabled = r; });
    for (int i = 0; i < 200 && !enabled; ++i) {
        cycle(axis, t);
    }
    ASSERT_TRUE(enabled);
    ASSERT_TRUE(*enabled) << enabled->error().message;
    EXPECT_EQ(axis.state(), drives::cia402::State::OperationEnabled);
    // The enable ran over the cyclic controlword/statusword, not over SDO.
    EXPECT_EQ(t.pending(), 0U);
    EXPECT_TRUE(t.output(0x6040, 0).valid());
    EXPECT_TRUE(t.input(0x6041, 0).valid());
    EXPECT_EQ(t.get<std::uint16_t>(t.input(0x6041, 0)).value_or(0) & 0x6F, 0x27);
}

/// The FIO's reaction when its master disappears in OP: the SM watchdog (100 ms by default)
/// drops it to SAFE-OP with AL status code 0x001B and the drive applies 6007h (kuhnke-fio.md
/// §1.7). Returns the statusword after the expiry.
class FioBusLossTest : public CoeTransportTest,
                       public ::testing::WithParamInterface<std::int16_t> {};

TEST_P(FioBusLossTest, WatchdogDropsToSafeOpAndAppliesAbortConnectionOption) {
    bring_up(AlState::Op);
    CoeTransport t(master_, 1); // FIO
    std::optional<drives::DriveVoid> option_set;
    t.write_as<std::int16_t>(0x6007, 0, GetParam(), [&](drives::DriveVoid r) { option_set = r; });
    t.write_as<std::int8_t>(0x6060, 0, 8, [](drives::DriveVoid) {});
    t.poll();
    ASSERT_TRUE(option_set && *option_set);
    drives::AxisConfig cfg;
    drives::Axis axis(t, cfg);
    axis.bind();
    std::optional<drives::DriveVoid> enabled;
    axis.enable([&](drives::DriveVoid r) { enabled = r; });
    for (int i = 0; i < 200 && !enabled; ++i) {
        cycle(axis, t);
    }
    ASSERT_TRUE(enabled && *enabled);
    auto& fio = segment_.slave(1);
    // Cycling keeps the watchdog fed: 300 ms of 1 ms cycles, still OP.
    for (int i = 0; i < 300; ++i) {
        cycle(axis, t);
    }
    EXPECT_EQ(fio.state(), AlState::Op);
    EXPECT_EQ(fio.watchdog_expiries(), 0U);
    // The master dies: no frames. 100 ms is not enough, 101 ms is.
    clock_.advance(milliseconds(99));
    EXPECT_FALSE(fio.tick(clock_.now()));
    clock_.advance(milliseconds(2));
    EXPECT_TRUE(fio.tick(clock_.now()));
    EXPECT_EQ(fio.state(), AlState::SafeOp);
    EXPECT_EQ(fio.al_status_code(), 0x001BU); // sync manager watchdog
    EXPECT_EQ(fio.reg16(0x0130) & 0x10U, 0x10U) << "AL status error flag";
    EXPECT_EQ(fio.reg8(0x0440) & 0x01U, 0x00U) << "process data watchdog status: expired";
    ObjectDictionary& od = fio.app().od();
    fio.before_frame(clock_.now() + milliseconds(1)); // the drive runs one more step
    const auto sw = od.get<std::uint16_t>(0x6041, 0).value_or(0);
    switch (GetParam()) {
    case -1: // clear PDOs, coast: controlword 0 → switch on disabled
    case 2:  // disable voltage
        EXPECT_EQ(sw & 0x4F, 0x40) << std::hex << sw;
        break;
    case 0: // no action: still operation enabled
        EXPECT_EQ(sw & 0x6F, 0x27) << std::hex << sw;
        break;
    case 1: // fault signal: 1003h entry 04108000h (error number 04, class 10h COM, code 8000h)
        EXPECT_EQ(sw & 0x4F, 0x08) << std::hex << sw;
        EXPECT_EQ(od.get<std::uint8_t>(0x1003, 0).value_or(0), 1);
        EXPECT_EQ(od.get<std::uint32_t>(0x1003, 1).value_or(0), 0x04108000U);
        EXPECT_EQ(od.get<std::uint16_t>(0x603F, 0).value_or(0), 0x8000U);
        break;
    case 3: // quick stop: quick stop active (bit 5 clear) or already switch on disabled
        EXPECT_TRUE((sw & 0x6F) == 0x07 || (sw & 0x4F) == 0x40) << std::hex << sw;
        break;
    default:
        FAIL();
    }
    // Only once: the slave is out of OP now.
    clock_.advance(milliseconds(500));
    EXPECT_FALSE(fio.tick(clock_.now()));
    EXPECT_EQ(fio.watchdog_expiries(), 1U);
}

INSTANTIATE_TEST_SUITE_P(AbortConnectionOption, FioBusLossTest,
                         ::testing::Values(std::int16_t{-1}, std::int16_t{0}, std::int16_t{1},
                                           std::int16_t{2}, std::int16_t{3}),
                         [](const ::testing::TestParamInfo<std::int16_t>& p) {
                             return p.param < 0 ? std::string("Minus1")
                                                : "Option" + std::to_string(p.param);
                         });

TEST_F(CoeTransportTest, InputCountAdvancesOnlyWithFramesWhoseInputsWereTaken) {
    bring_up(AlState::Op);
    CoeTransport t(master_, 0);
    const auto sw = t.input(0x6041, 0);
    ASSERT_TRUE(sw.valid());
    EXPECT_FALSE(t.input_count(t.output(0x6040, 0))); // outputs have no reception count
    const auto before = t.input_count(sw);
    ASSERT_TRUE(before);
    ASSERT_TRUE(master_.exchange_process_data()) << master_.last_error();
    EXPECT_EQ(t.input_count(sw), *before + 1);
    link_.drop_next(1); // the LRW is lost: inputs stay as they were
    EXPECT_FALSE(master_.exchange_process_data());
    EXPECT_EQ(t.input_count(sw), *before + 1);
    segment_.slave(1).faults().silent = true; // working counter short: inputs not taken
    EXPECT_FALSE(master_.exchange_process_data());
    EXPECT_EQ(t.input_count(sw), *before + 1);
}

TEST_F(CoeTransportTest, NoInputBeforeAFrameBroughtTheInputsIn) {
    // The slaves stay in SAFE-OP, where they take no outputs: every frame comes back with a
    // working counter short of OP's, and the master keeps its image of zeros, which is no
    // statusword (the fault reset of `codrive drive reset` took it for NOT READY TO SWITCH ON
    // and ended "ok" on a drive still in FAULT when the slave was slow to reach OP).
    ASSERT_TRUE(master_.scan()) << master_.last_error();
    ASSERT_TRUE(master_.set_state_all(AlState::SafeOp)) << master_.last_error();
    CoeTransport t(master_, 0);
    drives::Axis axis(t, drives::AxisConfig{});
    axis.bind();
    const auto sw = t.input(0x6041, 0);
    ASSERT_TRUE(sw.valid());
    for (int i = 0; i < 5; ++i) {
        EXPECT_FALSE(master_.exchange_process_data());
        axis.on_cycle(clock_.now());
        clock_.advance(milliseconds(1));
    }
    EXPECT_EQ(t.input_count(sw), 0U);
    EXPECT_FALSE(t.get_raw(sw)) << "zeros from no frame read as a statusword";
    EXPECT_FALSE(axis.has_statusword());
    ASSERT_TRUE(master_.set_state_all(AlState::Op)) << master_.last_error();
    ASSERT_TRUE(master_.exchange_process_data()) << master_.last_error();
    axis.on_cycle(clock_.now());
    ASSERT_TRUE(t.get_raw(sw));
    EXPECT_TRUE(axis.has_statusword());
    EXPECT_NE(axis.statusword(), 0U) << "the AKD2G's real statusword";
}

TEST_F(CoeTransportTest, NoInputFromTheFramesThatTookTheSlavesToOp) {
    // set_state_all(Op) sends two frames in SAFE-OP first (valid outputs before OP), whose short
    // working counter is expected and not counted as an error: they bring no inputs in. When the
    // first frame in OP was then lost (a loaded host), `codrive drive reset` took the image of
    // zeros for a statusword and ended "ok" on an AKD2G still in FAULT.
    bring_up(AlState::Op);
    CoeTransport t(master_, 0);
    drives::Axis axis(t, drives::AxisConfig{});
    axis.bind();
    const auto sw = t.input(0x6041, 0);
    ASSERT_TRUE(sw.valid());
    EXPECT_EQ(master_.stats().wkc_errors, 0U);
    EXPECT_EQ(t.input_count(sw), 0U);
    EXPECT_FALSE(t.get_raw(sw)) << "zeros from the frames before OP read as a statusword";
    axis.on_cycle(clock_.now());
    EXPECT_FALSE(axis.has_statusword());
    ASSERT_TRUE(master_.exchange_process_data()) << master_.last_error();
    EXPECT_EQ(t.input_count(sw), 1U);
    axis.on_cycle(clock_.now());
    ASSERT_TRUE(axis.has_statusword());
    EXPECT_NE(axis.statusword(), 0U) << "the AKD2G's real statusword";
}

} // namespace
} // namespace codrive::ethercat
