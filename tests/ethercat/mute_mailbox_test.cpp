// SPDX-License-Identifier: Apache-2.0
// Issue 20: acyclic work never stops the EtherCAT cycle. Two slaves on veth, the controller's
// dedicated cyclic thread ramps the FIO's axis in CSP while the AKD2G's mailbox goes silent in OP:
// the AKD2G's SDO fails alone with its sentence, no cycle is skipped, the FIO stays in OP. The
// same with 1% of the frames lost on the wire.
#include "veth_segment.hpp"

#include <codrive/controller/controller.hpp>
#include <codrive/testing/enable_then_ramp.hpp>

#include <fmt/format.h>

#include <atomic>
#include <cstdio>
#include <sched.h>

namespace codrive::testing {
namespace {

using namespace std::chrono_literals;

constexpr unsigned kCycleUs = 2000;

class MuteMailboxInOp : public EcatVethTest, public ::testing::WithParamInterface<int> {
protected:
    std::string path_;
};

TEST_P(MuteMailboxInOp, CostsOnlyItsOwnTransferNeverACycle) {
    const int drop_permille = GetParam();
    std::vector<std::string> args{"--slave", "fio", "--slave", "akd2g", "--mute-mailbox-on-signal",
                                  "1"};
    if (drop_permille > 0) {
        args.insert(args.end(), {"--drop-frames", std::to_string(drop_permille)});
    }
    start(args);
    if (IsSkipped() || HasFatalFailure()) {
        return;
    }
    master_.reset(); // the controller opens its own socket
    link_.reset();
    // A machine runs its cyclic thread and its slaves with real-time priority; here that keeps
    // the other load of the host out of the measurement (both are root on the test host).
    sched_param rt{};
    rt.sched_priority = 50;
    ASSERT_EQ(::sched_setscheduler(sim_->pid(), SCHED_FIFO, &rt), 0) << "simulator at SCHED_FIFO";
    path_ = write_temp_file("mute", fmt::format("ethercat:\n"
                                                "  interface: {}\n"
                                                "  cycle_us: {}\n"
                                                "  slaves:\n"
                                                "    - position: 0\n"
                                                "      name: table\n"
                                                "      profile: fio\n"
                                                "      axes:\n"
                                                "        - {{axis: 1, mode: csp}}\n"
                                                "    - position: 1\n"
                                                "      name: spindle\n"
                                                "      profile: akd2g\n"
                                                "      axes:\n"
                                                "        - {{axis: 1, mode: csp}}\n",
                                                veth_->master_if(), kCycleUs));
    controller::ControllerOptions o;
    o.threading = controller::Threading::DedicatedCyclic;
    o.realtime.fifo = true;
    o.realtime.priority = 60;
    auto made = controller::Controller::from_file(path_, o);
    ASSERT_TRUE(made) << made.error().detail;
    auto& c = **made;
    std::string events;
    c.set_event_callback([&events](const std::string& t) { events += t + "\n"; });
    auto started = c.start();
    ASSERT_TRUE(started) << started.error().detail << events;
    auto* table = c.axis(0, 1, 0);
    auto* spindle = c.axis(1, 1, 0);
    ASSERT_NE(table, nullptr);
    ASSERT_NE(spindle, nullptr);

    // Everything on the axes happens in the cycle callback (the cyclic thread owns them).
    EnableThenRamp ramp(*table, 20, 30000); // 3 s of CSP ramp at 2 ms
    std::atomic<bool> ask{false};
    std::atomic<bool> answered{false};
    std::atomic<std::uint64_t> skipped{0};
    std::atomic<std::uint64_t> late{0};      // cycles that started one slot or more late
    std::atomic<std::uint64_t> worst_gap{0}; // the most slots skipped at once
    bool asked = false;
    std::string sdo_error;
    TimePoint asked_at{};
    TimePoint answered_at{};
    TimePoint last_ideal{};
    c.set_cycle_callback([&](const controller::CycleInfo& info) {
        // Slots the cycle skipped: a cycle whose ideal start is more than one period after the
        // previous one's.
        if (last_ideal != TimePoint{} && info.ideal - last_ideal > microseconds(kCycleUs)) {
            const auto gap =
                static_cast<std::uint64_t>((info.ideal - last_ideal) / microseconds(kCycleUs)) - 1;
            skipped.fetch_add(gap, std::memory_order_relaxed);
            late.fetch_add(1, std::memory_order_relaxed);
            if (gap > worst_gap.load(std::memory_order_relaxed)) {
                worst_gap.store(gap, std::memory_order_relaxed);
            }
        }
        last_ideal = info.ideal;
        ramp.on_cycle();
        if (!asked && ask.load(std::memory_order_acquire)) {
            asked = true;
            asked_at = SteadyClock::now();
            spindle->discover([&](drives::DriveVoid r) { // reads 6502h over CoE
                sdo_error = r ? std::string("no error") : r.error().message;
                answered_at = SteadyClock::now();
                answered.store(true, std::memory_order_release);
            });
        }
    });
    ASSERT_TRUE(c.run_until([&] { return ramp.phase() >= EnableThenRamp::Moving; }, 10s))
        << ramp.failure() << events;
    ASSERT_EQ(ramp.phase(), EnableThenRamp::Moving) << ramp.failure() << events;
    sim_->signal(SIGUSR2);
    ASSERT_TRUE(sim_->wait_for_output("slave 1 mailbox goes silent", 3s)) << sim_->output();
    const std::uint64_t skipped_before = skipped.load();
    const std::uint64_t late_before = late.load();
    worst_gap.store(0);
    ask.store(true, std::memory_order_release);
    ASSERT_TRUE(c.run_until([&] { return answered.load(std::memory_order_acquire); }, 5s))
        << events;
    const std::uint64_t skipped_during = skipped.load() - skipped_before;
    const std::uint64_t late_during = late.load() - late_before;
    const std::uint64_t worst_during = worst_gap.load();
    ASSERT_TRUE(c.run_until([&] { return ramp.finished(); }, 10s)) << events;
    const double sdo_ms = std::chrono::duration<double, std::milli>(answered_at - asked_at).count();
    const auto stats = c.stats();
    std::printf("mute mailbox in OP, %d/1000 frames dropped: SDO failed after %.0f ms, %llu "
                "cycles skipped meanwhile (%llu late starts, at most %llu slots at once); %s\n",
                drop_permille, sdo_ms, static_cast<unsigned long long>(skipped_during),
                static_cast<unsigned long long>(late_during),
                static_cast<unsigned long long>(worst_during), stats.to_string().c_str());
    // The AKD2G's transfer failed on its own timeout, with its sentence.
    EXPECT_NE(sdo_error.find("slave 1 (AKD2G): CoE SDO upload 0x6502:00 timed out after 1000 ms "
                             "(mailbox silent"),
              std::string::npos)
        << sdo_error;
    EXPECT_GE(sdo_ms, 990.0);
    EXPECT_LT(sdo_ms, 1500.0);
    // No cycle waited for it. A cycle that blocked on the mailbox until the SDO's timeout would
    // skip ~500 slots at once (and the FIO's 100 ms SM watchdog would drop it to SAFE-OP); one
    // that waited a little every cycle would start late on most of the ~500 cycles. On a quiet
    // host both counts are 0 (measured with 0 % and 1 % drops). A host busy with other builds
    // stalls the cyclic thread now and then, each stall one late start skipping several slots
    // (one 26 ms stall skipped 13 under a parallel ASan build), so the bounds are on the number
    // of late starts (5 % of the cycles) and on the longest gap (below the SM watchdog), not on
    // the slots a stall happened to cover.
    EXPECT_LE(late_during, 25U) << skipped_during << " slots skipped";
    EXPECT_LT(worst_during, 50U) << "a gap of " << worst_during << " slots (100 ms is 50)";
    ASSERT_TRUE(ramp.done()) << ramp.failure() << events;
    c.run_for(200ms);
    EXPECT_NEAR(ramp.position(), ramp.start() + 30000, 200) << events;
    EXPECT_EQ(table->state(), drives::cia402::State::OperationEnabled) << events;
    EXPECT_EQ(events.find("cyclic exchange failed"), std::string::npos) << events;
    // "N cyclic frames lost in a row" is not asserted absent: on a busy host frames come back
    // after their cycle and that event is then right. What the mute must not cause is checked
    // above (skipped slots, the FIO in OP) and below (no SM watchdog expiry).
    if (drop_permille > 0) {
        EXPECT_GT(stats.ecat_wire_errors(), 0U) << "the simulator dropped frames";
    }
    // A stall of the host makes frames come back after their cycle too: they count as frame
    // errors (up to 154 in 1,508 cycles in one CI run on a 2-vCPU VM that stalls, 10-48 alone
    // there) but are told apart (ecat_late_frames) and not bounded. The frames the simulator
    // dropped never come back; beside them the allowance is the other EtherCAT tests' one frame
    // in 50 (controller_ecat_test.cpp).
    EXPECT_LE(stats.ecat_wire_errors(),
              stats.cycles * static_cast<std::uint64_t>(drop_permille + 20) / 1000)
        << events;
    c.set_cycle_callback(nullptr);
    c.shutdown();
    EXPECT_EQ(sim_->output().find("SM watchdog expired"), std::string::npos) << sim_->output();
}

INSTANTIATE_TEST_SUITE_P(FramesLostPerThousand, MuteMailboxInOp, ::testing::Values(0, 10));

} // namespace
} // namespace codrive::testing
