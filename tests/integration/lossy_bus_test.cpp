// SPDX-License-Identifier: Apache-2.0
// Eight devices and a master on a virtual bus that loses, duplicates and reorders 1% of all
// frames while SDO transfers, PDOs and heartbeats run: every SDO transfer ends, byte-exact or
// with a sentence, and every lost PDO is reported; with corruption injected, the
// block-transfer CRC lets no wrong data through.
#include "fault_rig.hpp"
#include "sdo_traffic.hpp"

#include <codrive/pdo/master.hpp>
#include <codrive/sync/producer.hpp>

#include <gtest/gtest.h>

#include <fmt/format.h>

#include <cstdio>
#include <cstdlib>
#include <map>
#include <memory>

using namespace codrive;
using namespace codrive::integration;

namespace {

constexpr std::uint64_t kDefaultCycles = 10'000;

/// Cycles (1 ms each) of the long runs. The default keeps the suite fast under ASan; the full
/// issue-11 run is CODRIVE_FAULT_CYCLES=100000 (figures in docs/reliability.md).
std::uint64_t cycles_from_env(std::uint64_t fallback) {
    if (const char* v = std::getenv("CODRIVE_FAULT_CYCLES"); v != nullptr && *v != '\0') {
        return std::strtoull(v, nullptr, 10);
    }
    return fallback;
}

void print_faults(const FaultInjector::Counts& c, std::uint64_t cycles) {
    std::printf("  cycles run: %llu (1 ms each, fake clock)\n",
                static_cast<unsigned long long>(cycles));
    std::printf(
        "  frames seen %llu, faults injected %llu: dropped %llu, duplicated %llu, "
        "reordered %llu, corrupted %llu\n",
        static_cast<unsigned long long>(c.frames), static_cast<unsigned long long>(c.injected()),
        static_cast<unsigned long long>(c.dropped), static_cast<unsigned long long>(c.duplicated),
        static_cast<unsigned long long>(c.reordered), static_cast<unsigned long long>(c.corrupted));
}

master::MasterConfig master_config() {
    master::MasterConfig c;
    c.sdo.timeout = milliseconds(200);
    c.sdo.retries = 1;
    return c;
}

} // namespace

TEST(FaultInjection, EightNodesOnePercentLossDuplicationReorderEveryTransferEnds) {
    constexpr int kNodes = 8;
    const std::uint64_t cycles = cycles_from_env(kDefaultCycles);
    Rig rig(kNodes, master_config());
    FaultInjector injector({.drop = 0.01, .duplicate = 0.01, .reorder = 0.01, .corrupt = 0},
                           /*seed=*/20261121);
    // SYNC every cycle, as a motion application would run next to the SDO traffic.
    VirtualBus& sync_bus = rig.net.endpoint("sync");
    sync::SyncProducer sync_producer(sync_bus);
    // A frame storm (a protocol feeding on its own traffic) grows exponentially within one
    // cycle; the filter sees every frame, so it cuts the storm (drops everything) as soon as far
    // more frames are in flight than the traffic can explain. The SYNC endpoint receives every
    // frame but its own, so launched - received there = in flight.
    constexpr std::uint64_t kMaxInFlight = 10'000;
    bool storm = false;
    // PDO exchange: every node sends TPDO1 (its SYNC counter) after each SYNC once operational;
    // the master's PDO engine reports each one that does not come (TpdoMissing).
    bool pdo_running = false;
    std::uint64_t tpdos_dropped = 0;
    std::uint64_t tpdos_duplicated = 0;
    std::uint64_t tpdos_delayed = 0;
    pdo::PdoMaster pdo_master(rig.master.bus());
    std::uint64_t tpdo_missing_events = 0;
    std::uint64_t bad_pdo_sentences = 0;
    pdo_master.set_event_handler([&](const pdo::PdoEvent& e) {
        if (e.kind != pdo::PdoEventKind::TpdoMissing) {
            return;
        }
        ++tpdo_missing_events;
        const std::string text = pdo::to_string(e);
        if (text.rfind(
                fmt::format("node {}: TPDO1 (0x{:03X}) missing after SYNC", e.node, 0x180 + e.node),
                0) != 0) {
            ++bad_pdo_sentences;
        }
    });
    rig.master.add_listener([&](const Frame& f, TimePoint t) { (void)pdo_master.on_frame(f, t); });
    rig.net.set_fault_filter([&](const std::string&, const Frame& f) {
        const auto& c = injector.counts();
        const std::uint64_t launched = c.frames - c.dropped + c.duplicated;
        const std::uint64_t delivered = sync_bus.stats().rx_frames + sync_producer.sent();
        if (storm || launched > delivered + kMaxInFlight) {
            storm = true;
            FaultAction drop;
            drop.drop = true;
            return drop;
        }
        const FaultAction a = injector.decide(f);
        if (pdo_running && f.id > cob::kTpdo1 && f.id <= cob::kTpdo1 + kNodes) {
            tpdos_dropped += a.drop ? 1 : 0;
            tpdos_duplicated += a.duplicates > 0 ? 1 : 0;
            tpdos_delayed += !a.drop && a.delay.count() > 0 ? 1 : 0;
        }
        return a;
    });
    ASSERT_TRUE(sync_producer.configure({.period = milliseconds(1), .counter_overflow = 0}));
    sync_producer.set_hook([&](const sync::SyncInfo& s) {
        if (pdo_running) {
            pdo_master.on_sync(s.cycle, rig.clock.now());
        }
    });
    sync_producer.start(rig.clock.now());
    rig.extra_timed.push_back(&sync_producer);
    rig.extra_timed.push_back(&pdo_master);

    rig.power_on_all();
    const int boot_failures = rig.boot_all();
    ASSERT_GE(boot_failures, 0) << "a node never booted on the lossy bus";
    // NMT start is unconfirmed (CiA 301 §7.2.8.3.1); boot-up repeats it until the heartbeat
    // reports operational, so every node is operational although start frames were lost.
    for (auto& d : rig.devices) {
        EXPECT_EQ(d->state(), nmt::NmtState::Operational) << "node " << int{d->node()};
        ASSERT_TRUE(pdo_master.add_node(d->node(), {counter_tpdo()}));
    }
    pdo_running = true;

    TrafficFigures figures;
    std::vector<std::unique_ptr<SdoTraffic>> traffic;
    const auto plan = full_plan();
    for (auto& d : rig.devices) {
        traffic.push_back(std::make_unique<SdoTraffic>(rig.master.sdo().client(d->node()), *d, plan,
                                                       figures, d->node() * 7U));
        traffic.back()->start();
    }
    const std::uint64_t ran = rig.run_cycles(cycles, [&](std::uint64_t) {
        for (auto& t : traffic) {
            t->poll();
        }
        const std::uint64_t delivered = sync_bus.stats().rx_frames + sync_producer.sent();
        const std::uint64_t launched =
            rig.net.frames_sent() - rig.net.frames_dropped() + injector.counts().duplicated;
        storm = launched > delivered + kMaxInFlight;
        return !storm;
    });
    EXPECT_FALSE(storm) << "frame storm: more than " << kMaxInFlight << " frames in flight after "
                        << ran << " cycles";
    if (storm) {
        // For diagnosis: frames per COB-ID over one more cycle.
        rig.net.clear_recorded();
        rig.net.set_recording(true);
        rig.run_for(milliseconds(1));
        std::map<std::uint32_t, std::uint64_t> per_id;
        for (const Frame& f : rig.net.recorded()) {
            ++per_id[f.id];
        }
        for (const auto& [id, n] : per_id) {
            std::printf("  storm: 0x%03X %llu frames in 1 ms\n", static_cast<unsigned>(id),
                        static_cast<unsigned long long>(n));
        }
        for (std::size_t i = 0; i < rig.net.recorded().size() && i < 12; ++i) {
            std::printf("  storm frame: %s\n", to_string(rig.net.recorded()[i]).c_str());
        }
        print_faults(injector.counts(), ran);
        print_figures("  results before the storm:", figures);
        return;
    }

    // No new transfers; whatever runs must end within its timeouts (no hang).
    for (auto& t : traffic) {
        t->stop();
    }
    std::uint64_t drain_cycles = 0;
    auto all_idle = [&] {
        for (auto& t : traffic) {
            if (!t->idle()) {
                return false;
            }
        }
        return true;
    };
    while (!all_idle() && drain_cycles < 10'000) {
        rig.run_for(milliseconds(1));
        ++drain_cycles;
    }

    std::printf("[fault injection] 8 nodes, 1%% drop + 1%% duplicate + 1%% reorder\n");
    print_faults(injector.counts(), ran + drain_cycles);
    print_figures("  results:", figures);
    const auto& ps = pdo_master.stats();
    std::printf("  PDO: %llu SYNCs, %llu TPDOs received, %llu dropped, %llu duplicated and %llu "
                "delayed by the injector, %llu reported missing (%llu late)\n",
                static_cast<unsigned long long>(ps.syncs),
                static_cast<unsigned long long>(ps.tpdos_received),
                static_cast<unsigned long long>(tpdos_dropped),
                static_cast<unsigned long long>(tpdos_duplicated),
                static_cast<unsigned long long>(tpdos_delayed),
                static_cast<unsigned long long>(ps.tpdos_missing),
                static_cast<unsigned long long>(ps.tpdos_late));
    std::printf(
        "  boot attempts failed and repeated: %d; heartbeat losses reported %llu, "
        "recovered %llu; node reboots %llu; SYNC sent %llu\n",
        boot_failures,
        static_cast<unsigned long long>(rig.count(master::MasterEventKind::HeartbeatLost)),
        static_cast<unsigned long long>(rig.count(master::MasterEventKind::HeartbeatRecovered)),
        static_cast<unsigned long long>(rig.count(master::MasterEventKind::NodeRebooted)),
        static_cast<unsigned long long>(sync_producer.sent()));

    EXPECT_TRUE(all_idle()) << "a transfer never ended";
    EXPECT_EQ(figures.callbacks, figures.submitted);
    EXPECT_EQ(figures.ok + figures.failed, figures.submitted);
    EXPECT_EQ(figures.wrong_data, 0U);
    EXPECT_EQ(figures.double_callbacks, 0U);
    EXPECT_EQ(figures.bad_sentences, 0U);
    EXPECT_GT(figures.ok, 0U);
    // Every TPDO the injector dropped is reported, except where a duplicated TPDO of the same
    // node stood in for it: the engine counts TPDOs per SYNC window (one window of lateness
    // allowed) and a TPDO carries no sequence number. The last windows may still be open.
    EXPECT_GT(tpdos_dropped, 0U);
    EXPECT_EQ(tpdo_missing_events, ps.tpdos_missing);
    EXPECT_GE(ps.tpdos_missing + tpdos_duplicated + kNodes, tpdos_dropped);
    // A delayed (reordered) TPDO can miss its window plus the tolerance: then it is reported
    // missing too, rightly (it was not there in time).
    EXPECT_LE(ps.tpdos_missing, tpdos_dropped + tpdos_delayed);
    EXPECT_EQ(bad_pdo_sentences, 0U);
    EXPECT_GT(injector.counts().dropped, 0U);
    EXPECT_GT(injector.counts().duplicated, 0U);
    EXPECT_GT(injector.counts().reordered, 0U);
    // Nothing the faults do looks like a reboot: no spurious recovery runs.
    EXPECT_EQ(rig.count(master::MasterEventKind::NodeRebooted), 0U);
    EXPECT_FALSE(rig.master.sdo().busy());
}

TEST(FaultInjection, BlockCrcLetsNoCorruptedTransferComplete) {
    constexpr int kNodes = 2;
    const std::uint64_t cycles = cycles_from_env(kDefaultCycles) / 5;
    Rig rig(kNodes, master_config());
    rig.power_on_all();
    ASSERT_EQ(rig.boot_all(), 0);

    // Corrupt 1% of SDO frames only (one flipped payload bit each): bits that slip past the CAN
    // CRC. Only block transfers carry an end-to-end CRC (CiA 301 §7.2.4.3.16), so only they run.
    FaultInjector injector({.drop = 0, .duplicate = 0, .reorder = 0, .corrupt = 0.01},
                           /*seed=*/7);
    injector.set_scope(is_sdo_frame);
    rig.set_injector(&injector);

    std::vector<PlannedTransfer> plan;
    for (std::size_t k = 4; k < kReferenceSizes.size(); ++k) { // 100 bytes .. 64 KiB
        plan.push_back({true, k, sdo::Mode::Block});
        plan.push_back({false, k, sdo::Mode::Block});
    }
    TrafficFigures figures;
    std::vector<std::unique_ptr<SdoTraffic>> traffic;
    for (auto& d : rig.devices) {
        traffic.push_back(std::make_unique<SdoTraffic>(rig.master.sdo().client(d->node()), *d, plan,
                                                       figures, d->node()));
        traffic.back()->start();
    }
    const std::uint64_t ran = rig.run_cycles(cycles);
    for (auto& t : traffic) {
        t->stop();
    }
    rig.run_for(seconds(10));

    std::printf("[fault injection] block transfers with 1%% of SDO frames corrupted\n");
    print_faults(injector.counts(), ran);
    print_figures("  results:", figures);

    EXPECT_EQ(figures.callbacks, figures.submitted);
    EXPECT_EQ(figures.wrong_data, 0U) << "a corrupted block transfer completed";
    EXPECT_EQ(figures.bad_sentences, 0U);
    EXPECT_GT(injector.counts().corrupted, 0U);
    EXPECT_GT(figures.failed_by_cause["abort 0x05040004 by client"] +
                  figures.failed_by_cause["abort 0x05040004 by server"],
              0U)
        << "no CRC error was ever detected";
}
