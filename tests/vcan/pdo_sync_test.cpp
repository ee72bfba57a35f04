// SPDX-License-Identifier: Apache-2.0
// PDOs between real processes on vcan: the master configures 2 RPDOs + 2 TPDOs of a node
// process over SDO and runs 10,000 SYNC cycles at 1 ms; every PDO must arrive.
//
// The node process is this test binary itself, started with the disabled test
// PdoVcanDevice.DISABLED_Run selected (it runs only when asked for), configured through
// CODRIVE_PDO_DEVICE_* environment variables.
#include "../unit/pdo/pdo_rig.hpp"

#include <codrive/core/event_loop.hpp>
#include <codrive/core/socket_can_bus.hpp>
#include <codrive/pdo/configure.hpp>
#include <codrive/pdo/device.hpp>
#include <codrive/pdo/master.hpp>
#include <codrive/sdo/client.hpp>
#include <codrive/sdo/server.hpp>
#include <codrive/sync/producer.hpp>
#include <codrive/testing/process.hpp>
#include <codrive/testing/vcan.hpp>

#include <gtest/gtest.h>
#include <unistd.h>

#include <climits>
#include <cstdio>
#include <cstdlib>
#include <optional>
#include <string>

using namespace codrive;
using namespace codrive::pdo;
using namespace codrive::pdo::test;
using namespace std::chrono_literals;
using codrive::testing::Process;
using codrive::testing::self_exe;

namespace {

constexpr NodeId kNode = 9;
constexpr std::uint64_t kCycles = 10'000;

std::vector<PdoConfig> vcan_pdos() {
    return {rpdo(1, {entry(0x2000, 0, 32), entry(0x6040, 0, 16)}, 1),
            rpdo(2, {entry(0x607A, 0, 32), entry(0x6060, 0, 8)}, 1),
            tpdo(1, {entry(0x2001, 0, 32), entry(0x6041, 0, 16)}, 1),
            tpdo(2, {entry(0x6064, 0, 32), entry(0x6061, 0, 8)}, 1)};
}

std::optional<std::uint64_t> field(const std::string& text, const std::string& key) {
    const auto pos = text.find(key + " ");
    if (pos == std::string::npos) {
        return std::nullopt;
    }
    return std::strtoull(text.c_str() + pos + key.size() + 1, nullptr, 10);
}

} // namespace

// The node process: SDO server + DevicePdo on vcan, NMT start/stop handled by hand. Exits after
// NMT stop, printing what it received and sent.
TEST(PdoVcanDevice, DISABLED_Run) {
    const char* ifname = std::getenv("CODRIVE_PDO_DEVICE_IF");
    ASSERT_NE(ifname, nullptr) << "run by PdoVcan tests only";
    auto loop = EventLoop::create();
    ASSERT_TRUE(loop);
    auto bus = SocketCanBus::open(ifname);
    ASSERT_TRUE(bus) << bus.error().message();
    ObjectDictionary od;
    fill_drive_od(od, kNode, quirks::standard());
    sdo::ServerConfig sc;
    sc.node = kNode;
    sdo::SdoServer server(od, **bus, sc);
    DevicePdoOptions opt;
    opt.node = kNode;
    DevicePdo device(od, **bus, opt);
    device.set_rpdo_hook([&](unsigned n, TimePoint) {
        if (n == 1) {
            od.set<std::uint32_t>(0x2001, 0, *od.get<std::uint32_t>(0x2000, 0));
        } else {
            od.set<std::int32_t>(0x6064, 0, *od.get<std::int32_t>(0x607A, 0));
        }
    });
    std::uint64_t syncs = 0;
    std::uint64_t rpdo_frames[2] = {0, 0};
    bool stop = false;
    (*bus)->set_frame_handler([&](const Frame& f, TimePoint t) {
        if (f.id == 0 && f.len == 2 && (f.data[1] == 0 || f.data[1] == kNode)) {
            if (f.data[0] == 0x01) {
                device.set_operational(true, t);
            } else if (f.data[0] == 0x02) {
                device.set_operational(false, t);
                stop = true;
            }
            return;
        }
        syncs += f.id == 0x80 ? 1 : 0;
        rpdo_frames[0] += f.id == cob::rpdo(1, kNode) ? 1 : 0;
        rpdo_frames[1] += f.id == cob::rpdo(2, kNode) ? 1 : 0;
        server.on_frame(f, t);
        device.on_frame(f, t);
    });
    ASSERT_TRUE((*bus)->attach(**loop));
    (*loop)->add_timed(&server);
    (*loop)->add_timed(&device);
    std::printf("device ready\n");
    std::fflush(stdout);
    (*loop)->run_until([&] { return stop; }, 300s);
    (*loop)->remove_timed(&device);
    (*loop)->remove_timed(&server);
    std::printf("device syncs %llu rpdo1 %llu rpdo2 %llu tpdo1 %llu tpdo2 %llu\n",
                static_cast<unsigned long long>(syncs),
                static_cast<unsigned long long>(rpdo_frames[0]),
                static_cast<unsigned long long>(rpdo_frames[1]),
                static_cast<unsigned long long>(device.sent(1)),
                static_cast<unsigned long long>(device.sent(2)));
    std::fflush(stdout);
    EXPECT_TRUE(stop);
}

TEST(PdoVcan, MasterConfiguresNodeProcessAndExchanges10000SyncCyclesWithNoPdoLost) {
    CODRIVE_REQUIRE_VCAN("vcan0");
    ::setenv("CODRIVE_PDO_DEVICE_IF", "vcan0", 1);
    Process node({self_exe(), "--gtest_also_run_disabled_tests",
                  "--gtest_filter=PdoVcanDevice.DISABLED_Run"});
    ::unsetenv("CODRIVE_PDO_DEVICE_IF");
    ASSERT_TRUE(node.wait_for_output("device ready", 20s)) << node.output();

    auto loop = EventLoop::create();
    ASSERT_TRUE(loop);
    auto bus = SocketCanBus::open("vcan0");
    ASSERT_TRUE(bus) << bus.error().message();
    sdo::ClientConfig cc;
    cc.node = kNode;
    cc.timeout = 2s;
    sdo::SdoClient client(**bus, RealClock::instance(), cc);
    PdoMaster master(**bus);
    (*bus)->set_frame_handler([&](const Frame& f, TimePoint t) {
        client.on_frame(f, t);
        master.on_frame(f, t);
    });
    ASSERT_TRUE((*bus)->attach(**loop));
    (*loop)->add_timed(&client);

    // 1. Configure over SDO (the node is pre-operational).
    ObjectDictionary model;
    fill_drive_od(model, kNode, quirks::standard());
    DeviceModel dm;
    dm.od = &model;
    PdoConfigurator configurator(client, dm);
    std::optional<PdoResult<ConfigureReport>> configured;
    configurator.configure(vcan_pdos(),
                           [&](PdoResult<ConfigureReport> r) { configured = std::move(r); });
    (*loop)->run_until([&] { return configured.has_value(); }, 30s);
    ASSERT_TRUE(configured.has_value()) << "configuration did not finish";
    ASSERT_TRUE(*configured) << configured->error().message;

    // 2. NMT start, then SYNC every 1 ms with the engine hooked to it.
    ProcessImage& img = **master.add_node(kNode, vcan_pdos());
    const Slot counter = *img.slot(0x2000, 0);
    const Slot cw = *img.slot(0x6040, 0);
    const Slot target = *img.slot(0x607A, 0);
    const Slot echo = *img.slot(0x2001, 0);
    std::uint64_t missing_events = 0;
    std::string first_event;
    master.set_event_handler([&](const PdoEvent& e) {
        if (e.kind == PdoEventKind::TpdoMissing) {
            ++missing_events;
        }
        if (first_event.empty()) {
            first_event = to_string(e);
        }
    });
    ASSERT_TRUE((*bus)->send(Frame::make(0x000, {0x01, kNode})));
    (*loop)->run_until((*loop)->now() + 50ms);

    sync::SyncProducer producer(**bus);
    sync::SyncConfig scfg;
    scfg.period = 1ms;
    ASSERT_TRUE(producer.configure(scfg));
    std::uint64_t echo_regressions = 0;
    std::uint32_t last_echo = 0;
    std::uint32_t sequence = 0; // SyncInfo::cycle counts skipped slots too; this does not
    producer.set_hook([&](const sync::SyncInfo& info) {
        const std::uint32_t k = ++sequence;
        img.set<std::uint32_t>(counter, k);
        img.set<std::uint16_t>(cw, 0x000F);
        img.set<std::int32_t>(target, static_cast<std::int32_t>(k) * 3);
        master.on_sync(info.cycle, info.actual);
        const std::uint32_t e = img.get<std::uint32_t>(echo);
        if (e < last_echo) {
            ++echo_regressions;
        }
        last_echo = e;
    });
    (*loop)->add_timed(&producer);
    producer.start((*loop)->now() + 1ms);
    (*loop)->run_until([&] { return producer.sent() >= kCycles; }, 180s);
    producer.stop();
    (*loop)->remove_timed(&producer);
    (*loop)->run_until((*loop)->now() + 200ms); // the last TPDOs
    const std::uint64_t syncs = producer.sent();

    ASSERT_TRUE((*bus)->send(Frame::make(0x000, {0x02, kNode})));
    (*loop)->run_until((*loop)->now() + 20ms);
    (*loop)->remove_timed(&client);
    const auto status = node.wait(30s);
    ASSERT_TRUE(status) << "node process hung: " << node.output();
    EXPECT_EQ(*status, 0) << node.output();
    const std::string out = node.output();

    std::uint64_t tpdo1 = 0;
    std::uint64_t tpdo2 = 0;
    for (const auto& p : img.pdos()) {
        if (p.dir == PdoDir::Tpdo) {
            (p.number == 1 ? tpdo1 : tpdo2) = p.rx_count;
        }
    }
    std::printf("master: %llu SYNCs (%llu skipped), %llu RPDOs sent, TPDO1 %llu TPDO2 %llu "
                "received (%llu late), %llu missing events%s%s\n%s",
                static_cast<unsigned long long>(syncs),
                static_cast<unsigned long long>(producer.skipped()),
                static_cast<unsigned long long>(master.stats().rpdos_sent),
                static_cast<unsigned long long>(tpdo1), static_cast<unsigned long long>(tpdo2),
                static_cast<unsigned long long>(master.stats().tpdos_late),
                static_cast<unsigned long long>(missing_events),
                first_event.empty() ? "" : ", first: ", first_event.c_str(), out.c_str());

    EXPECT_GE(syncs, kCycles);
    EXPECT_EQ(master.stats().rpdos_sent, 2 * syncs);
    EXPECT_EQ(field(out, "syncs"), syncs);
    EXPECT_EQ(field(out, "rpdo1"), syncs);
    EXPECT_EQ(field(out, "rpdo2"), syncs);
    EXPECT_EQ(field(out, "tpdo1"), syncs);
    EXPECT_EQ(field(out, "tpdo2"), syncs);
    // Counts, not timing: in a 1-CPU guest on a loaded host the node process can be starved
    // for more than a SYNC period, so some answers come windows late and are reported missing
    // (printed above) although none is lost.
    EXPECT_EQ(tpdo1, syncs);
    EXPECT_EQ(tpdo2, syncs);
    EXPECT_EQ(echo_regressions, 0U);
    // TPDO1 at the n-th SYNC echoes the counter RPDO1 carried after the (n−1)-th: the last
    // echo is S−1.
    EXPECT_EQ(img.get<std::uint32_t>(echo), static_cast<std::uint32_t>(syncs - 1));
}
