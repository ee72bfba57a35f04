// SPDX-License-Identifier: Apache-2.0
// The Controller brings back a slave of its EtherCAT segment that left OP by itself: the FIO's
// SM watchdog drops it to SAFE-OP while it is mute (codrive-ecat-sim on veth); the controller
// reports the AL status code once, acknowledges it and requests OP from the cycle's frames. The
// master's interface going down is named once too, and its return reported.
#include "veth_segment.hpp"

#include <codrive/controller/controller.hpp>

#include <fmt/format.h>

#include <csignal>
#include <cstdio>
#include <memory>
#include <sched.h>

namespace codrive::testing {
namespace {

using namespace std::chrono_literals;

class ControllerRecovery : public EcatVethTest {
protected:
    void SetUp() override { start_for_controller({"--slave", "fio"}); }
    /// The bus file of both tests: the FIO at position 0 as `table`, one axis in CSP.
    std::string write_table_bus_file() {
        return write_temp_file("recover", fmt::format("ethercat:\n"
                                                      "  interface: {}\n"
                                                      "  cycle_us: 2000\n"
                                                      "  slaves:\n"
                                                      "    - {{position: 0, name: table, profile: "
                                                      "fio, axes: [{{axis: 1, mode: csp}}]}}\n",
                                                      veth_->master_if()));
    }
    [[nodiscard]] std::size_t count(const std::string& text) const {
        std::size_t n = 0;
        for (auto at = events_.find(text); at != std::string::npos;
             at = events_.find(text, at + 1)) {
            ++n;
        }
        return n;
    }
    /// Loads the table bus file with `o`, collects every event in events_, starts (fatal on
    /// failure: the caller checks HasFatalFailure()).
    void start_controller(const controller::ControllerOptions& o) {
        path_ = write_table_bus_file();
        auto c = controller::Controller::from_file(path_, o);
        ASSERT_TRUE(c) << c.error().detail;
        c_ = std::move(*c);
        c_->set_event_callback([this](const std::string& t) { events_ += t + "\n"; });
        auto started = c_->start();
        ASSERT_TRUE(started) << started.error().detail;
    }
    /// The controller goes before the simulator and the veth pair, as a local of the test did.
    void TearDown() override {
        c_.reset();
        EcatVethTest::TearDown();
    }
    std::unique_ptr<controller::Controller> c_;
    std::string path_;
    std::string events_;
};

TEST_F(ControllerRecovery, ASlaveThatLeftOpIsReportedOnceAndBroughtBack) {
    if (IsSkipped() || HasFatalFailure()) {
        return;
    }
    controller::ControllerOptions o;
    o.threading = controller::Threading::Single;
    start_controller(o);
    if (HasFatalFailure()) {
        return;
    }
    c_->run_for(200ms);
    ASSERT_EQ(count("left OP"), 0U) << events_;
    // No process data for longer than the FIO's 100 ms SM watchdog (the master stalled: this
    // thread runs the single-threaded controller's cycles and stops running them): the FIO
    // drops to SAFE-OP with AL status code 0x001B, as kuhnke-fio.md §1.7 describes.
    ASSERT_TRUE(sim_->wait_for_output("SM watchdog expired", 3s)) << sim_->output();
    const auto back = [&] { return count("back in OP") > 0; };
    ASSERT_TRUE(c_->run_until(back, 5s)) << events_;
    EXPECT_EQ(count("slave 0 (FIO Drive Control): left OP, now in SAFE-OP with AL status code "
                    "0x001B (sync manager watchdog); requesting OP again\n"),
              1U)
        << events_;
    EXPECT_EQ(count("slave 0 (FIO Drive Control): back in OP after 1 OP request(s)"), 1U)
        << events_;
    std::printf("%s", events_.c_str()); // the recovery's events, with its duration
    // It stays there: the process data runs again and nothing more is reported.
    c_->run_for(300ms);
    EXPECT_EQ(count("left OP"), 1U) << events_;
    EXPECT_EQ(c_->stats().ecat_frame_errors > 0, true);
    c_->shutdown();
}

// The master's own interface is taken away during cyclic operation (`ip link set down`): send
// and receive fail with ENETDOWN, not a timeout. The cyclic thread goes on trying every cycle;
// the controller names the cause once and reports the return once the interface is up again.
TEST_F(ControllerRecovery, AnInterfaceThatGoesDownIsNamedOnceAndItsReturnIsReported) {
    if (IsSkipped() || HasFatalFailure()) {
        return;
    }
    controller::ControllerOptions o;
    o.threading = controller::Threading::DedicatedCyclic;
    start_controller(o);
    if (HasFatalFailure()) {
        return;
    }
    c_->run_for(200ms);
    ASSERT_EQ(count("cyclic exchange failed"), 0U) << events_;
    ASSERT_TRUE(veth_->set_master_up(false)) << veth_->error();
    const std::string failed =
        fmt::format("EtherCAT segment on {}: cyclic exchange failed: cannot ", veth_->master_if());
    const bool named = c_->run_until([&] { return count(failed) > 0; }, 3s);
    c_->run_for(50ms);
    ASSERT_TRUE(veth_->set_master_up(true)) << veth_->error();
    ASSERT_TRUE(named) << events_;
    EXPECT_NE(events_.find(" the cyclic frame: Network is down\n"), std::string::npos) << events_;
    ASSERT_TRUE(c_->run_until([&] { return count("cyclic exchange works again") > 0; }, 5s))
        << events_;
    std::printf("%s", events_.c_str());
    EXPECT_EQ(count("cyclic exchange failed"), 1U) << "once per run of failed cycles\n" << events_;
    EXPECT_GT(c_->stats().ecat_frame_errors, 0U);
    c_->shutdown();
}

// A slave's local error in OP (codrive-ecat-sim --leave-op-on-signal: SAFE-OP with 0x001A,
// then two OP requests refused with it), on the dedicated cyclic thread: reported once, OP
// requested again with back-off (100 ms, 200 ms) until it takes it.
class ControllerRecoveryBackoff : public ControllerRecovery {
protected:
    void SetUp() override {
        start_for_controller({"--slave", "fio", "--leave-op-on-signal", "0:0x001A:2"});
    }
};

TEST_F(ControllerRecoveryBackoff, RefusedOpRequestsAreRepeatedWithBackOffOnTheCyclicThread) {
    if (IsSkipped() || HasFatalFailure()) {
        return;
    }
    controller::ControllerOptions o;
    o.threading = controller::Threading::DedicatedCyclic;
    o.realtime.fifo = true;
    start_controller(o);
    if (HasFatalFailure()) {
        return;
    }
    c_->run_for(200ms);
    const auto baseline = c_->stats().overruns;
    c_->run_for(400ms);
    std::printf("cycles skipped in 400 ms without recovery: %llu\n",
                static_cast<unsigned long long>(c_->stats().overruns - baseline));
    const auto overruns_before = c_->stats().overruns;
    sim_->signal(SIGRTMIN + 1);
    ASSERT_TRUE(sim_->wait_for_output("left OP with AL status code 0x001A", 3s)) << sim_->output();
    ASSERT_TRUE(c_->run_until([&] { return count("back in OP") > 0; }, 5s)) << events_;
    std::printf("%s", events_.c_str());
    EXPECT_EQ(count("slave 0 (FIO Drive Control): left OP, now in SAFE-OP with AL status code "
                    "0x001A (synchronization error); requesting OP again\n"),
              1U)
        << events_;
    // Two refused, the third taken: 100 ms + 200 ms of back-off at least.
    EXPECT_EQ(count("slave 0 (FIO Drive Control): back in OP after 3 OP request(s)"), 1U)
        << events_;
    c_->run_for(300ms);
    EXPECT_EQ(count("left OP"), 1U) << events_;
    // Measured, not asserted (a loaded 2-core host may delay a cycle for reasons of its own):
    // the AL control writes ride in the cyclic frame, so the recovery itself waits for nothing.
    std::printf("cycles skipped during the recovery: %llu\n",
                static_cast<unsigned long long>(c_->stats().overruns - overruns_before));
    c_->shutdown();
}

} // namespace
} // namespace codrive::testing
