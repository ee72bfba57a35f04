// SPDX-License-Identifier: Apache-2.0
// Boot-up from whatever NMT state an earlier run left: the pre-operational step before the first
// configuration write, and reset communication with its wait for the boot-up message.
#include "test_device.hpp"

#include <codrive/master/master.hpp>

#include <gtest/gtest.h>

#include <algorithm>
#include <optional>

using namespace codrive;
using namespace codrive::master;
using namespace std::chrono_literals;

namespace {

constexpr NodeId kNode = 3;

/// One device; a master per "run" of the application (a second run finds the node as the first
/// one left it: operational, heartbeat on, PDO mapping active).
struct Rig {
    FakeClock clock;
    VirtualNetwork net{clock, 100us};
    VirtualBus& master_bus = net.endpoint("master");
    VirtualBus& dev_bus = net.endpoint("device");
    codrive::testing::TestDevice device{dev_bus, kNode};
    std::optional<Master> master;

    Rig() {
        // A PDO mapping count that, like the drives' (CiA 301 §7.5.2.36, AKD2G, DS-BVS manual
        // §6.2.22), accepts writes only in NMT pre-operational and aborts 0x08000022 otherwise.
        device.od().add_sub(0x1600,
                            SubObject::make(0, "Number of mapped objects", DataType::Unsigned8,
                                            Access::Rw, Value::zero(DataType::Unsigned8)),
                            "RPDO1 mapping");
        device.od().on_write(0x1600,
                             [this](std::uint16_t, std::uint8_t,
                                    std::span<const std::uint8_t>) -> tl::expected<void, SdoAbort> {
                                 if (device.state() != nmt::NmtState::PreOperational) {
                                     return tl::unexpected(SdoAbort::DataTransferState);
                                 }
                                 return {};
                             });
        net.set_recording(true);
        device.boot(clock.now());
        run_for(1ms);
    }

    void run_for(Duration d) {
        std::vector<ITimed*> timed = device.timed();
        if (master) {
            timed.push_back(&*master);
        }
        net.run_until(clock, clock.now() + d, timed);
    }

    static NodeConfig config(BootReset reset) {
        NodeConfig c;
        c.id = kNode;
        c.identity.vendor_id = 0x6A;
        c.writes.push_back(ObjectWrite::of<std::uint8_t>(0x1600, 0, 1, "RPDO1 mapping count"));
        c.heartbeat_producer = 100ms;
        c.boot_reset = reset;
        return c;
    }

    /// A new master (a new run of the application) boots the node.
    BootReport boot(BootReset reset) {
        master.reset();
        master.emplace(master_bus, clock);
        master->add_node(config(reset));
        std::optional<BootReport> report;
        master->boot(kNode, [&](const BootReport& r) { report = r; });
        run_for(3s);
        EXPECT_TRUE(report) << "boot-up did not finish";
        return report.value_or(BootReport{});
    }

    /// Index of the first recorded frame (from `from` on) whose text starts with `prefix`.
    std::optional<std::size_t> find(const std::string& prefix, std::size_t from = 0) const {
        const auto& f = net.recorded();
        for (std::size_t i = from; i < f.size(); ++i) {
            if (to_string(f[i]).rfind(prefix, 0) == 0) {
                return i;
            }
        }
        return std::nullopt;
    }

    /// The first run: boots the fresh node and leaves it operational with heartbeat 100 ms.
    void first_run() {
        const BootReport r = boot(BootReset::PreOperational);
        ASSERT_TRUE(r.ok) << r.to_string();
        ASSERT_EQ(device.state(), nmt::NmtState::Operational);
        ASSERT_EQ(device.od().get<std::uint16_t>(0x1017, 0), 100);
        run_for(500ms); // the node keeps producing heartbeats
    }
};

bool has_step(const BootReport& r, const std::string& name, const std::string& detail) {
    return std::any_of(r.steps.begin(), r.steps.end(), [&](const BootStep& s) {
        return s.ok && s.name == name && s.detail.find(detail) != std::string::npos;
    });
}

} // namespace

TEST(BootState, OperationalNodeIsPutPreOperationalBeforeTheFirstConfigurationWrite) {
    Rig rig;
    rig.first_run();
    const std::size_t second_run = rig.net.recorded().size();
    const BootReport r = rig.boot(BootReset::PreOperational);
    ASSERT_TRUE(r.ok) << r.to_string();
    EXPECT_EQ(rig.device.state(), nmt::NmtState::Operational);
    EXPECT_EQ(rig.device.od().get<std::uint8_t>(0x1600, 0), 1);
    ASSERT_FALSE(r.steps.empty());
    EXPECT_EQ(r.steps.front().name, "NMT enter pre-operational") << r.to_string();
    EXPECT_TRUE(has_step(r, "pre-operational check", "confirmed by heartbeat")) << r.to_string();
    // On the wire: NMT enter pre-operational (000#80 03) before the SDO download to 1600h:00.
    const auto nmt = rig.find("000#8003", second_run);
    const auto first_write = rig.find("603#2F00160001", second_run);
    ASSERT_TRUE(nmt && first_write);
    EXPECT_LT(*nmt, *first_write);
    // ...and a heartbeat reporting pre-operational (7Fh) between them: the state was confirmed.
    const auto pre_op_heartbeat = rig.find("703#7F", *nmt);
    ASSERT_TRUE(pre_op_heartbeat);
    EXPECT_LT(*pre_op_heartbeat, *first_write);
}

TEST(BootState, PreOperationalNodeWithoutHeartbeatBootsWithAnUnconfirmedState) {
    Rig rig; // fresh node: pre-operational, 1017h = 0
    const BootReport r = rig.boot(BootReset::PreOperational);
    ASSERT_TRUE(r.ok) << r.to_string();
    EXPECT_TRUE(has_step(r, "pre-operational check", "no heartbeat (1017h = 0)")) << r.to_string();
}

TEST(BootState, WithoutTheStateStepAnOperationalNodeRefusesItsMapping) {
    // The failure the pre-operational step prevents (issue 19's 0x08000022).
    Rig rig;
    rig.first_run();
    const BootReport r = rig.boot(BootReset::None);
    EXPECT_FALSE(r.ok);
    EXPECT_NE(r.error().find("0x1600:00"), std::string::npos) << r.error();
    EXPECT_NE(r.error().find("0x08000022"), std::string::npos) << r.error();
}

TEST(BootState, ResetCommunicationWaitsForTheBootUpMessageBeforeProbing) {
    Rig rig;
    rig.first_run();
    const std::size_t second_run = rig.net.recorded().size();
    const BootReport r = rig.boot(BootReset::Communication);
    ASSERT_TRUE(r.ok) << r.to_string();
    ASSERT_FALSE(r.steps.empty());
    EXPECT_EQ(r.steps.front().name, "NMT reset communication");
    EXPECT_NE(r.steps.front().detail.find("boot-up message after"), std::string::npos);
    EXPECT_EQ(rig.device.state(), nmt::NmtState::Operational);
    EXPECT_EQ(rig.device.od().get<std::uint8_t>(0x1600, 0), 1);
    // 000#82 03, then the boot-up message 703#00, and only then the first SDO request.
    const auto reset = rig.find("000#8203", second_run);
    ASSERT_TRUE(reset);
    const auto boot_up = rig.find("703#00", *reset);
    const auto first_sdo = rig.find("603#", second_run);
    ASSERT_TRUE(boot_up && first_sdo);
    EXPECT_LT(*boot_up, *first_sdo);
    EXPECT_FALSE(rig.find("000#8003", second_run)) << "no pre-operational command needed";
}

TEST(BootState, ResetCommunicationWithoutBootUpMessageFailsWithASentence) {
    Rig rig;
    rig.dev_bus.set_connected(false); // the node does not answer
    const BootReport r = rig.boot(BootReset::Communication);
    EXPECT_FALSE(r.ok);
    EXPECT_EQ(r.error(), "node 3: no boot-up message within 2000 ms after NMT reset communication");
}
