// SPDX-License-Identifier: Apache-2.0
// Continuous drift compensation (ETG.1000.4 §9.1.3): the cyclic frame carries the reference
// clock's system time, and drifting simulated clocks stay together with it and apart without.
#include <codrive/ethercat/registers.hpp>
#include <codrive/testing/sim_segment.hpp>

#include <gtest/gtest.h>

#include <cstdio>
#include <cstdlib>

namespace codrive::ethercat {
namespace {

class DcDrift : public codrive::testing::SimSegmentTest {
protected:
    DcDrift() {
        segment_.add(sim::ecat::make_drive_slave("fio", 11));
        segment_.add(sim::ecat::make_drive_slave("akd2g", 22));
        segment_.add(sim::ecat::make_drive_slave("ds-bvs", 33));
        // Crystal errors: the reference clock fast, the others slow and fast.
        segment_.slave(0).dc_clock().set_drift_ppm(20);
        segment_.slave(1).dc_clock().set_drift_ppm(50);
        segment_.slave(2).dc_clock().set_drift_ppm(-50);
    }
    void to_op(bool dc) {
        ASSERT_TRUE(master_.scan()) << master_.last_error();
        if (dc) {
            ASSERT_TRUE(master_.configure_dc()) << master_.last_error();
        }
        ASSERT_TRUE(master_.set_state_all(AlState::Op)) << master_.last_error();
    }
    /// The datagrams of the last frame the master sent.
    std::vector<Datagram> last_sent() {
        auto d = decode_frame(link_.sent().back());
        EXPECT_TRUE(d);
        return d ? *d : std::vector<Datagram>{};
    }
    /// Runs `cycles` cycles of 1 ms; the largest |system time - reference time| of slaves 1
    /// and 2 seen in the last `tail` of them (read from the simulated ESCs directly).
    std::int64_t run(int cycles, int tail) {
        std::int64_t worst = 0;
        for (int i = 0; i < cycles; ++i) {
            clock_.advance(milliseconds(1));
            EXPECT_TRUE(master_.exchange_process_data()) << master_.last_error();
            if (i < cycles - tail) {
                continue;
            }
            const auto ref = segment_.slave(0).system_time(clock_.now());
            for (std::size_t s = 1; s < 3; ++s) {
                // Synchronised clocks show the same time at the same instant.
                const auto off =
                    static_cast<std::int64_t>(segment_.slave(s).system_time(clock_.now()) - ref);
                worst = std::max(worst, std::abs(off));
            }
        }
        return worst;
    }
};

TEST_F(DcDrift, CyclicFrameCarriesTheReferenceTimeBehindTheLrw) {
    to_op(true);
    ASSERT_EQ(master_.dc_reference(), std::size_t{0});
    link_.record(true);
    const auto before = master_.stats().dc_time_distributions;
    ASSERT_TRUE(master_.exchange_process_data()) << master_.last_error();
    const auto frame = last_sent();
    ASSERT_GE(frame.size(), 2U);
    EXPECT_EQ(frame[0].command, Command::Lrw);
    // FRMW to the reference clock's configured address, register 0x0910, 64 bits: one frame,
    // no extra exchange.
    EXPECT_EQ(frame[1].command, Command::Frmw);
    EXPECT_EQ(frame[1].address & 0xFFFFU, master_.slaves()[0].station_address);
    EXPECT_EQ(frame[1].address >> 16, reg::kDcSystemTime);
    EXPECT_EQ(frame[1].data.size(), 8U);
    EXPECT_EQ(link_.sent().size(), 1U) << "no second frame for the time";
    EXPECT_EQ(master_.stats().dc_time_distributions, before + 1);
}

TEST_F(DcDrift, WithoutDcOrWithCompensationOffTheFrameHoldsOnlyTheCyclicTraffic) {
    to_op(false);
    link_.record(true);
    ASSERT_TRUE(master_.exchange_process_data()) << master_.last_error();
    for (const auto& d : last_sent()) {
        EXPECT_NE(d.command, Command::Frmw);
    }
    ASSERT_TRUE(master_.configure_dc()) << master_.last_error();
    master_.config().continuous_drift_compensation = false;
    ASSERT_TRUE(master_.exchange_process_data()) << master_.last_error();
    for (const auto& d : last_sent()) {
        EXPECT_NE(d.command, Command::Frmw);
    }
    EXPECT_EQ(master_.stats().dc_time_distributions, 0U);
}

TEST_F(DcDrift, DriftingClocksStayWithinNanosecondsWithCompensation) {
    to_op(true);
    // 2 s of 1 ms cycles; the loop settles in the first few hundred ms.
    const std::int64_t first = run(1000, 1000);
    const std::int64_t settled = run(1000, 1000);
    std::printf("max |offset|: first second %lld ns, second second %lld ns\n",
                static_cast<long long>(first), static_cast<long long>(settled));
    EXPECT_LT(first, 1000) << "ns";
    EXPECT_LT(settled, 50) << "ns";
    // What the slaves report (0x092C, mean difference) agrees.
    auto st = master_.dc_status();
    ASSERT_TRUE(st) << master_.last_error();
    for (const auto& s : *st) {
        EXPECT_LT(std::abs(s.difference), 50) << "slave " << s.position;
    }
}

TEST_F(DcDrift, DriftingClocksDriftApartWithoutCompensation) {
    to_op(true);
    master_.config().continuous_drift_compensation = false;
    // Slave 2 runs 70 ppm slower than the reference, less what the start-up burst taught its
    // loop: microseconds apart after a second, twice as far after two.
    const std::int64_t after_1s = run(1000, 1);
    const std::int64_t after_2s = run(1000, 1);
    std::printf("|offset| after 1 s %lld ns, after 2 s %lld ns\n", static_cast<long long>(after_1s),
                static_cast<long long>(after_2s));
    EXPECT_GT(after_1s, 5'000) << "ns";
    EXPECT_GT(after_2s, after_1s * 18 / 10) << "ns: the difference grows";
}

TEST(DcDifferenceRegister, SignAndMagnitudeAsTheEscDatasheetDefines) {
    // ET1100 datasheet 0x092C: bit 31 set = local copy smaller than the received time.
    EXPECT_EQ(dc_difference::encode(1234), 1234U);
    EXPECT_EQ(dc_difference::encode(-1234), 0x80000000U | 1234U);
    EXPECT_EQ(dc_difference::decode(0x80000000U | 1234U), -1234);
    EXPECT_EQ(dc_difference::encode(std::int64_t{1} << 40), 0x7FFFFFFFU);
}

} // namespace
} // namespace codrive::ethercat
