// SPDX-License-Identifier: Apache-2.0
// Controller::read_object()/write_object() on an EtherCAT slave whose mailbox has gone silent,
// then shutdown(): every callback runs before shutdown() returns, once, with a sentence naming
// the slave, the object and why, in both threading modes; none waits for a frame that will
// never come (with a dedicated cyclic thread, the accesses still queued for it or under way in
// its frame were left without an answer before).
#include "veth_segment.hpp"

#include <codrive/controller/controller.hpp>

#include <fmt/format.h>

#include <chrono>
#include <csignal>
#include <cstdio>
#include <string>
#include <vector>

namespace codrive::testing {
namespace {

using namespace std::chrono_literals;

class ObjectAccessAtShutdown : public EcatVethTest,
                               public ::testing::WithParamInterface<controller::Threading> {
protected:
    std::string path_;
};

TEST_P(ObjectAccessAtShutdown, EveryCallbackRunsOnceWithItsSentence) {
    start({"--slave", "akd2g", "--mute-mailbox-on-signal", "0"});
    if (IsSkipped() || HasFatalFailure()) {
        return;
    }
    master_.reset(); // the controller opens its own socket
    link_.reset();
    path_ = write_temp_file("shutdown", fmt::format("ethercat:\n"
                                                    "  interface: {}\n"
                                                    "  cycle_us: 2000\n"
                                                    "  slaves:\n"
                                                    "    - position: 0\n"
                                                    "      name: spindle\n"
                                                    "      profile: akd2g\n"
                                                    "      axes:\n"
                                                    "        - {{axis: 1, mode: csp}}\n",
                                                    veth_->master_if()));
    controller::ControllerOptions o;
    o.threading = GetParam();
    auto made = controller::Controller::from_file(path_, o);
    ASSERT_TRUE(made) << made.error().detail;
    auto& c = **made;
    auto started = c.start();
    ASSERT_TRUE(started) << started.error().detail;

    sim_->signal(SIGUSR2);
    ASSERT_TRUE(sim_->wait_for_output("slave 0 mailbox goes silent", 3s)) << sim_->output();
    std::vector<std::string> sentences;
    int calls = 0;
    const auto note = [&](const auto& r) {
        ++calls;
        if (!r) {
            sentences.push_back(r.error().message);
        }
    };
    c.read_object(0, 0, 0x1018, 1, [&](drives::DriveResult<drives::Bytes> r) { note(r); });
    c.read_object(0, 0, 0x6502, 0, [&](drives::DriveResult<drives::Bytes> r) { note(r); });
    c.write_object(0, 0, 0x6081, 0, drives::Bytes{0xE8, 0x03, 0x00, 0x00},
                   [&](drives::DriveVoid r) { note(r); });
    c.run_for(100ms); // the first is under way in the frame, the others wait behind it
    EXPECT_EQ(calls, 0) << "a silent mailbox answers nothing within 100 ms (its timeout: 1 s)";

    const auto t0 = std::chrono::steady_clock::now();
    c.shutdown();
    const double ms =
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    std::printf("shutdown with 3 object accesses to a silent mailbox: %.0f ms\n", ms);
    for (const auto& s : sentences) {
        std::printf("  %s\n", s.c_str());
    }
    EXPECT_EQ(calls, 3) << "every callback ran before shutdown() returned, once";
    ASSERT_EQ(sentences.size(), 3U);
    for (const auto& s : sentences) {
        EXPECT_NE(s.find("slave 0 (AKD2G)"), std::string::npos) << s;
        EXPECT_NE(s.find("cancelled: the controller shut down before the slave answered"),
                  std::string::npos)
            << s;
    }
    const std::string all = sentences[0] + "\n" + sentences[1] + "\n" + sentences[2];
    for (const char* object : {"1018", "6502", "6081"}) {
        EXPECT_NE(all.find(object), std::string::npos) << object << " not named:\n" << all;
    }
    EXPECT_LT(ms, 1500.0) << "shutdown waited for the mailbox";
}

std::string threading_name(const ::testing::TestParamInfo<controller::Threading>& p) {
    return p.param == controller::Threading::Single ? "Single" : "DedicatedCyclic";
}

INSTANTIATE_TEST_SUITE_P(Threading, ObjectAccessAtShutdown,
                         ::testing::Values(controller::Threading::Single,
                                           controller::Threading::DedicatedCyclic),
                         threading_name);

} // namespace
} // namespace codrive::testing
