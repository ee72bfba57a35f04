// SPDX-License-Identifier: Apache-2.0
// Continuous drift compensation over veth: two simulated slaves whose clocks run +50 and -50 ppm
// stay within nanoseconds of each other while the cyclic frame distributes the reference time
// (ETG.1000.4 §9.1.3), and drift apart without it; `codrive ecat dc` reports the same.
#include "veth_segment.hpp"

#include <codrive/ethercat/pcap_writer.hpp>

#include <fmt/format.h>

#include <cstdio>
#include <cstdlib>
#include <thread>
#include <unistd.h>

namespace codrive::testing {
namespace {

using namespace codrive::ethercat;

const std::vector<std::string> kDriftingPair{
    "--slave",           "fio",  "--slave",           "akd2g",
    "--clock-drift-ppm", "0:50", "--clock-drift-ppm", "1:-50"};

class DcDriftVeth : public EcatVethTest {
protected:
    /// Cyclic exchange at 1 ms for `duration`; every 100 ms the DC registers are read (one
    /// extra frame). Returns the largest |offset to the reference| and |0x092C| of slave 1 seen
    /// after `settle`.
    struct Seen {
        std::int64_t offset = 0;
        std::int64_t difference = 0;
        std::int64_t last_offset = 0;
        std::int64_t offset_all = 0; ///< including the time before `settle`
    };
    Seen cycle_for(Duration duration, Duration settle) {
        Seen seen;
        const TimePoint start = SteadyClock::now();
        TimePoint next = start;
        TimePoint sample = start + milliseconds(100);
        while (SteadyClock::now() - start < duration) {
            (void)master_->exchange_process_data(); // a lost frame only delays one sample
            if (SteadyClock::now() >= sample) {
                sample += milliseconds(100);
                auto st = master_->dc_status();
                if (st && st->size() == 2) {
                    seen.last_offset = (*st)[1].offset_to_reference;
                    seen.offset_all = std::max(seen.offset_all, std::abs(seen.last_offset));
                    if (SteadyClock::now() - start >= settle) {
                        seen.offset = std::max(seen.offset, std::abs(seen.last_offset));
                        seen.difference = std::max<std::int64_t>(
                            seen.difference, std::abs(std::int64_t{(*st)[1].difference}));
                    }
                }
            }
            next += milliseconds(1);
            std::this_thread::sleep_until(next);
        }
        return seen;
    }
    void bring_up(bool compensation) {
        ASSERT_TRUE(master_->scan()) << master_->last_error();
        master_->config().continuous_drift_compensation = compensation;
        ASSERT_TRUE(master_->configure_dc()) << master_->last_error();
        ASSERT_TRUE(master_->set_state_all(AlState::Op)) << master_->last_error();
    }
};

TEST_F(DcDriftVeth, ClocksOneHundredPpmApartStayWithinABoundWhileTheCycleRuns) {
    start(kDriftingPair);
    if (IsSkipped() || HasFatalFailure()) {
        return;
    }
    bring_up(true);
    // The cyclic frame as tshark's EtherCAT dissector reads it: LRW (12), then FRMW (14) to
    // the reference clock's station address 0x1001 on 0x0910, read by it and written by the
    // other slave (working counter 2); nothing malformed.
    const std::string pcap = fmt::format("/tmp/codrive-dc-{}.pcap", ::getpid());
    PcapWriter writer;
    ASSERT_TRUE(writer.open(pcap));
    link_->set_tap([&](std::span<const std::uint8_t> f, bool) { writer.write(f); });
    for (int i = 0; i < 20; ++i) {
        ASSERT_TRUE(master_->exchange_process_data()) << master_->last_error();
    }
    link_->set_tap({});
    writer.close();
    auto fields = run({"/usr/bin/tshark", "-r", pcap, "-Y", "ecat.sub2.cmd == 14", "-T", "fields",
                       "-e", "ecat.sub1.cmd", "-e", "ecat.sub2.cmd", "-e", "ecat.sub2.adp", "-e",
                       "ecat.sub2.ado", "-e", "ecat.sub2.cnt"});
    ASSERT_EQ(fields.status, 0) << fields.output;
    EXPECT_NE(fields.output.find("0x0c\t0x0e\t0x1001\t0x0910\t2\n"), std::string::npos)
        << fields.output;
    auto bad =
        run({"/usr/bin/tshark", "-r", pcap, "-Y", "_ws.malformed || _ws.expert.severity >= error"});
    EXPECT_EQ(bad.output.find("EtherCAT"), std::string::npos) << bad.output;
    if (!HasFailure()) {
        ::unlink(pcap.c_str());
    }
    const Seen s = cycle_for(seconds(4), seconds(1));
    std::printf("with continuous drift compensation: max |offset| %lld ns in seconds 0..4, %lld "
                "ns in seconds 1..4, max |0x092C| %lld ns (%llu frames carried the time)\n",
                static_cast<long long>(s.offset_all), static_cast<long long>(s.offset),
                static_cast<long long>(s.difference),
                static_cast<unsigned long long>(master_->stats().dc_time_distributions));
    EXPECT_GT(master_->stats().dc_time_distributions, 3000U);
    // 100 ppm is 100 µs per second: held to well under a microsecond.
    EXPECT_LT(s.offset, 1000) << "ns";
    EXPECT_LT(s.difference, 1000) << "ns";
}

TEST_F(DcDriftVeth, WithoutContinuousCompensationTheClocksDriftApart) {
    start(kDriftingPair);
    if (IsSkipped() || HasFatalFailure()) {
        return;
    }
    bring_up(false);
    const Seen first = cycle_for(seconds(1), seconds(0));
    const Seen second = cycle_for(seconds(1), seconds(0));
    std::printf("without continuous drift compensation: |offset| %lld ns after 1 s, %lld ns "
                "after 2 s\n",
                static_cast<long long>(std::abs(first.last_offset)),
                static_cast<long long>(std::abs(second.last_offset)));
    EXPECT_EQ(master_->stats().dc_time_distributions, 0U);
    // Only what the start-up burst taught the slaves' loops: microseconds, growing.
    EXPECT_GT(std::abs(first.last_offset), 2'000) << "ns";
    EXPECT_GT(std::abs(second.last_offset), std::abs(first.last_offset) * 3 / 2) << "ns";
}

TEST_F(DcDriftVeth, CodriveEcatDcReportsEachSlavesDifference) {
    start(kDriftingPair);
    if (IsSkipped() || HasFatalFailure()) {
        return;
    }
    link_.reset();
    master_.reset(); // the CLI opens its own socket
    const std::string iface = veth_->master_if();
    auto r = run({tool_path("codrive"), "ecat", "dc", "--ethercat", iface, "--seconds", "2"});
    ASSERT_EQ(r.status, 0) << r.output;
    EXPECT_NE(r.output.find("reference clock: slave 0 (FIO Drive Control); system time "
                            "distributed over 2.0 s every 1000 µs"),
              std::string::npos)
        << r.output;
    EXPECT_NE(r.output.find("slave 1 (AKD2G): system time difference (0x092C) "), std::string::npos)
        << r.output;
    std::printf("%s", r.output.c_str());
    auto off = run({tool_path("codrive"), "ecat", "dc", "--ethercat", iface, "--seconds", "2",
                    "--no-compensation"});
    ASSERT_EQ(off.status, 0) << off.output;
    EXPECT_NE(off.output.find("system time NOT distributed"), std::string::npos) << off.output;
    std::printf("%s", off.output.c_str());
    auto bad = run({tool_path("codrive"), "ecat", "dc", "--ethercat", iface, "--cycle-us", "0"});
    EXPECT_EQ(bad.status, 2) << bad.output;
}

} // namespace
} // namespace codrive::testing
