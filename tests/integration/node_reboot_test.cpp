// SPDX-License-Identifier: Apache-2.0
// A node reboots (boot-up message, fresh dictionary) in the middle of an SDO block transfer:
// the transfer ends with a sentence saying so and the master re-runs the node's boot-up.
#include "fault_rig.hpp"

#include <gtest/gtest.h>

#include <cstdio>
#include <optional>
#include <string>

using namespace codrive;
using namespace codrive::integration;

namespace {

struct Outcome {
    std::optional<sdo::SdoError> error;
    bool ok = false;
    bool fired = false;
};

/// Starts a 64 KiB block transfer to node 2, reboots the node once `reboot_after` bytes have
/// moved, and returns what the transfer reported.
Outcome block_transfer_interrupted_by_reboot(Rig& rig, bool upload, std::size_t reboot_after) {
    Outcome out;
    std::size_t progress = 0;
    sdo::TransferOptions opt;
    opt.mode = sdo::Mode::Block;
    opt.progress = [&](std::size_t done, std::optional<std::size_t>) { progress = done; };
    sdo::SdoClient& client = rig.master.sdo().client(2);
    if (upload) {
        const auto big = static_cast<std::uint16_t>(kReference + kReferenceSizes.size() - 1);
        client.upload(
            big, 0,
            [&](sdo::SdoResult<sdo::Bytes> r) {
                out.fired = true;
                out.ok = r.has_value();
                if (!r) {
                    out.error = r.error();
                }
            },
            opt);
    } else {
        client.download(
            kScratch, 0, reference_pattern(65536),
            [&](sdo::SdoResult<void> r) {
                out.fired = true;
                out.ok = r.has_value();
                if (!r) {
                    out.error = r.error();
                }
            },
            opt);
    }
    // Let part of the transfer happen (frames are 100 µs apart on this bus).
    for (int i = 0; i < 100'000 && progress < reboot_after && !out.fired; ++i) {
        rig.run_for(microseconds(100));
    }
    EXPECT_GE(progress, reboot_after) << "the transfer never got going";
    EXPECT_TRUE(rig.device(2).server().busy()) << "the server should be mid-transfer";
    rig.net.clear_recorded();
    rig.net.set_recording(true);
    rig.device(2).power_on(rig.clock.now());
    rig.run_for(seconds(2));
    rig.net.set_recording(false);
    return out;
}

class NodeReboot : public ::testing::TestWithParam<bool> {};

TEST_P(NodeReboot, DuringBlockTransferEndsTransferAndMasterRecoversTheNode) {
    const bool upload = GetParam();
    Rig rig(2);
    rig.power_on_all();
    ASSERT_EQ(rig.boot_all(), 0);
    ASSERT_EQ(rig.device(2).state(), nmt::NmtState::Operational);
    const unsigned boots_before = rig.device(2).boots();

    const Outcome out = block_transfer_interrupted_by_reboot(rig, upload, 16 * 1024);

    ASSERT_TRUE(out.fired) << "the transfer callback never ran";
    ASSERT_FALSE(out.ok);
    ASSERT_TRUE(out.error);
    const std::string text = out.error->to_string();
    std::printf("[reboot during block %s] %s\n", upload ? "upload" : "download", text.c_str());
    EXPECT_EQ(out.error->cause, make_error_code(sdo::SdoErrc::NodeRebooted));
    EXPECT_EQ(text.rfind("node 2: SDO block ", 0), 0U) << text;
    EXPECT_NE(text.find(upload ? "0x2208:00" : "0x2100:00"), std::string::npos) << text;
    EXPECT_NE(text.find("node rebooted"), std::string::npos) << text;

    // The master noticed the unexpected boot-up and brought the node back to operational.
    EXPECT_EQ(rig.device(2).boots(), boots_before + 1);
    EXPECT_EQ(rig.count(master::MasterEventKind::NodeRebooted), 1U);
    EXPECT_EQ(rig.count(master::MasterEventKind::Recovered), 1U);
    for (const auto& e : rig.events) {
        if (e.node == 2) {
            std::printf("  master event: %s: %s\n", std::string(master::to_string(e.kind)).c_str(),
                        e.text.c_str());
        }
    }
    if (rig.count(master::MasterEventKind::Recovered) != 1) {
        // For diagnosis: what crossed node 2's SDO channel right after the reboot.
        int shown = 0;
        for (const Frame& f : rig.net.recorded()) {
            if ((f.id == 0x582 || f.id == 0x602 || f.id == 0x702) && shown < 12) {
                std::printf("  after reboot: %s\n", to_string(f).c_str());
                ++shown;
            }
        }
    }
    EXPECT_EQ(rig.device(2).state(), nmt::NmtState::Operational);
    EXPECT_EQ(rig.device(2).od().get<std::uint16_t>(0x1017, 0), 100) << "heartbeat configured";
    EXPECT_EQ(rig.device(1).boots(), 1U) << "the other node is untouched";

    // The channel works again: the same transfer now completes byte-exact.
    bool done = false;
    sdo::TransferOptions opt;
    opt.mode = sdo::Mode::Block;
    rig.master.sdo().client(2).download(
        kScratch, 0, reference_pattern(65536, 3),
        [&](sdo::SdoResult<void> r) {
            done = true;
            EXPECT_TRUE(r) << r.error().to_string();
        },
        opt);
    rig.run_for(seconds(2));
    EXPECT_TRUE(done);
    EXPECT_EQ(rig.device(2).scratch(), reference_pattern(65536, 3));
}

INSTANTIATE_TEST_SUITE_P(Integration, NodeReboot, ::testing::Values(false, true),
                         [](const ::testing::TestParamInfo<bool>& p) {
                             return p.param ? "Upload" : "Download";
                         });

} // namespace
