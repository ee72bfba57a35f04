// SPDX-License-Identifier: Apache-2.0
// drives::Axis on the CoE DriveTransport against a simulated EtherCAT drive (in-process).
#include <codrive/drives/axis.hpp>
#include <codrive/ethercat/coe_transport.hpp>
#include <codrive/sim/ecat/drive_profiles.hpp>
#include <codrive/sim/ecat/segment.hpp>

#include <gtest/gtest.h>

namespace codrive::ethercat {
namespace {

class CoeTransportTest : public ::testing::Test {
protected:
    CoeTransportTest() {
        segment_.add(sim::ecat::make_drive_slave("akd2g", 5));
        segment_.add(sim::ecat::make_drive_slave("fio", 6));
    }
    void bring_up() {
        ASSERT_TRUE(master_.scan()) << master_.last_error();
        ASSERT_TRUE(master_.set_state_all(AlState::Op)) << master_.last_error();
    }
    /// One control cycle: acyclic work, LRW, axis update.
    void cycle(drives::Axis& axis, CoeTransport& t) {
        t.poll();
        ASSERT_TRUE(master_.exchange_process_data()) << master_.last_error();
        axis.on_cycle(clock_.now());
        clock_.advance(milliseconds(1));
    }

    FakeClock clock_;
    sim::ecat::EcatSegment segment_;
    sim::ecat::SegmentLink link_{segment_, clock_};
    Master master_{link_, clock_};
};

TEST_F(CoeTransportTest, ObjectAccessCompletesOnPollNotInsideTheCall) {
    bring_up();
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
    bring_up();
    CoeTransport t(master_, 1); // FIO: 6040 607A 3202 6060 / 6041 6064 6061
    EXPECT_TRUE(t.output(0x6040, 0).valid());
    EXPECT_TRUE(t.output(0x607A, 0).valid());
    EXPECT_TRUE(t.input(0x6064, 0).valid());
    EXPECT_FALSE(t.input(0x606C, 0).valid()); // not mapped by default
    EXPECT_FALSE(t.output(0x6041, 0).valid());
}

TEST_F(CoeTransportTest, AxisEnablesOverTheCyclicControlwordOnEtherCat) {
    bring_up();
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

TEST_F(CoeTransportTest, InputCountAdvancesOnlyWithFramesWhoseInputsWereTaken) {
    bring_up();
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

} // namespace
} // namespace codrive::ethercat
