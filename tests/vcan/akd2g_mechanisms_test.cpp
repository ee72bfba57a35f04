// SPDX-License-Identifier: Apache-2.0
// AKD2G mechanisms through a real simulator process on vcan: touch probes (manual §4.1.5), the
// axis of a fault found in 5004h/5104h (§5.3.84; the EMCY names no axis), and the units of
// read_si_scale read over SDO from the simulated AKD2G and DS-BVS.
#include <codrive/core/event_loop.hpp>
#include <codrive/core/socket_can_bus.hpp>
#include <codrive/drives/blocking.hpp>
#include <codrive/drives/canopen_transport.hpp>
#include <codrive/drives/drive_device.hpp>
#include <codrive/drives/touch_probe.hpp>
#include <codrive/drives/units.hpp>
#include <codrive/emcy/consumer.hpp>
#include <codrive/sdo/client.hpp>
#include <codrive/sim/sim_device.hpp>
#include <codrive/testing/process.hpp>
#include <codrive/testing/vcan.hpp>

#include <gtest/gtest.h>

#include <numbers>
#include <optional>

using namespace codrive;
using namespace std::chrono_literals;
using codrive::testing::Process;
using codrive::testing::tool_path;
using drives::DriveResult;
using drives::DriveVoid;
using drives::ProbeEdge;
using drives::ProbeTrigger;

namespace {

constexpr double kPi = std::numbers::pi;

/// This process as a master on vcan0: an SDO client per node, an EMCY consumer, the loop.
struct Master {
    std::unique_ptr<EventLoop> loop;
    std::unique_ptr<SocketCanBus> bus;
    std::vector<std::unique_ptr<sdo::SdoClient>> clients;
    emcy::EmcyConsumer emcy;

    Master() {
        auto l = EventLoop::create();
        EXPECT_TRUE(l);
        loop = std::move(*l);
        auto b = SocketCanBus::open("vcan0");
        EXPECT_TRUE(b);
        bus = std::move(*b);
        bus->set_frame_handler([this](const Frame& f, TimePoint t) {
            for (auto& c : clients) {
                c->on_frame(f, t);
            }
            emcy.on_frame(f, t);
        });
        EXPECT_TRUE(bus->attach(*loop));
    }
    ~Master() {
        for (auto& c : clients) {
            loop->remove_timed(c.get());
        }
    }
    sdo::SdoClient& client(NodeId node) {
        sdo::ClientConfig cc;
        cc.node = node;
        cc.timeout = 2s;
        clients.push_back(std::make_unique<sdo::SdoClient>(*bus, RealClock::instance(), cc));
        loop->add_timed(clients.back().get());
        return *clients.back();
    }
    template <typename T>
    T wait(const std::function<void(std::function<void(T)>)>& start) {
        auto out = std::make_shared<std::optional<T>>();
        start([out](T r) { *out = std::move(r); });
        loop->run_until([&out] { return out->has_value(); }, 10s);
        EXPECT_TRUE(out->has_value()) << "no answer within 10 s";
        return out->has_value() ? std::move(**out) : T{};
    }
    DriveVoid run(const std::function<void(drives::Axis::Done)>& start) {
        return drives::run_blocking(*loop, start, 20s);
    }
};

} // namespace

TEST(VcanAkd2g, TouchProbeLatchesTheSensorPositionDuringAMoveOnAxisOneAndAnEdgeOnAxisTwo) {
    CODRIVE_REQUIRE_VCAN("vcan0");
    Process sim({tool_path("codrive-sim"), "-i", "vcan0", "--node", "7:akd2g:2"});
    ASSERT_TRUE(sim.wait_for_output("ready on vcan0", 10s)) << sim.output();
    Master m;
    drives::CanopenTransport transport(m.client(7));
    drives::AxisConfig base;
    base.timeout = 10s;
    drives::DriveDevice akd(transport, drives::akd2g_profile(), 2, base);
    m.loop->add_timed(&akd);
    drives::Axis& x = akd.axis(1);

    // A sensor at 200000 on axis 1 (the simulator's control object, 2FF0h:08), probe 1 armed
    // for its rising edge, first event only.
    ASSERT_TRUE(m.wait<DriveVoid>([&](auto done) {
        transport.write_as<std::int32_t>(sim::kControlObject, sim::kControlProbe1At, 200000, done);
    }));
    drives::TouchProbes probes(transport, drives::akd2g_profile(), 1);
    auto armed = m.wait<DriveVoid>(
        [&](auto done) { probes.arm(1, ProbeEdge::Rising, ProbeTrigger::FirstEvent, done); });
    ASSERT_TRUE(armed) << armed.error().message;
    auto st =
        m.wait<DriveResult<drives::ProbeStatus>>([&](auto done) { probes.read_status(1, done); });
    ASSERT_TRUE(st) << st.error().message;
    EXPECT_TRUE(st->enabled);
    EXPECT_FALSE(st->rising_stored);

    auto r = m.run([&](auto d) { x.set_mode(drives::cia402::Mode::ProfilePosition, d); });
    ASSERT_TRUE(r) << r.error().message;
    r = m.run([&](auto d) { x.enable(d); });
    ASSERT_TRUE(r) << r.error().message;
    r = m.run([&](auto d) { x.move_to(400000, {}, d); });
    ASSERT_TRUE(r) << r.error().message;

    st = m.wait<DriveResult<drives::ProbeStatus>>([&](auto done) { probes.read_status(1, done); });
    ASSERT_TRUE(st) << st.error().message;
    EXPECT_TRUE(st->rising_stored) << "60B9h bit 1 after passing the sensor";
    EXPECT_FALSE(st->falling_stored);
    auto pos = m.wait<DriveResult<std::int32_t>>(
        [&](auto done) { probes.read_position(1, ProbeEdge::Rising, done); });
    ASSERT_TRUE(pos) << pos.error().message;
    EXPECT_EQ(*pos, 200000) << "60BAh holds the position of the edge, not the end of the move";

    // Axis 2 (68B8h..68BDh): probe 2, falling edge, continuous; the input driven directly.
    drives::TouchProbes probes2(transport, drives::akd2g_profile(), 2);
    armed = m.wait<DriveVoid>(
        [&](auto done) { probes2.arm(2, ProbeEdge::Falling, ProbeTrigger::Continuous, done); });
    ASSERT_TRUE(armed) << armed.error().message;
    const auto control2 = static_cast<std::uint16_t>(sim::kControlObject + 1);
    for (const std::uint8_t level : {std::uint8_t{1}, std::uint8_t{0}}) {
        ASSERT_TRUE(m.wait<DriveVoid>([&](auto done) {
            transport.write_as<std::uint8_t>(control2, sim::kControlProbe2Input, level, done);
        }));
    }
    st = m.wait<DriveResult<drives::ProbeStatus>>([&](auto done) { probes2.read_status(2, done); });
    ASSERT_TRUE(st) << st.error().message;
    EXPECT_TRUE(st->enabled && st->falling_stored && !st->rising_stored);
    auto raw = m.wait<DriveResult<std::uint16_t>>(
        [&](auto done) { transport.read_as<std::uint16_t>(0x68B9, 0, done); });
    ASSERT_TRUE(raw);
    EXPECT_EQ(*raw, 0x0500) << "68B9h: probe 2 enabled (bit 8), falling stored (bit 10)";
    std::printf("touch probe: 60BAh = %d after a move 0 -> 400000 past a sensor at 200000\n", *pos);
    sim.signal(SIGINT);
    EXPECT_TRUE(sim.wait(5s));
    m.loop->remove_timed(&akd);
}

TEST(VcanAkd2g, FaultOnAxisTwoIsFoundInItsFaultListNotInTheEmcy) {
    CODRIVE_REQUIRE_VCAN("vcan0");
    Process sim({tool_path("codrive-sim"), "-i", "vcan0", "--node", "7:akd2g:2"});
    ASSERT_TRUE(sim.wait_for_output("ready on vcan0", 10s)) << sim.output();
    Master m;
    drives::CanopenTransport transport(m.client(7));
    drives::DriveDevice akd(transport, drives::akd2g_profile(), 2);
    akd.attach_emcy_text(m.emcy, 7);
    std::vector<emcy::EmcyEvent> emcys;
    m.emcy.set_handler([&](const emcy::EmcyEvent& e) {
        emcys.push_back(e);
        akd.on_emcy(e);
    });
    std::vector<std::pair<unsigned, drives::AxisFault>> faults;
    for (unsigned a = 1; a <= 2; ++a) {
        akd.axis(a).on_fault(
            [&faults, a](const drives::AxisFault& f) { faults.emplace_back(a, f); });
    }
    m.loop->add_timed(&akd);

    // Over-current on axis 2 (2FF1h:02): F2002, EMCY FF07h.
    const auto control2 = static_cast<std::uint16_t>(sim::kControlObject + 1);
    ASSERT_TRUE(m.wait<DriveVoid>([&](auto done) {
        transport.write_as<std::uint8_t>(control2, sim::kControlOverCurrent, 1, done);
    }));
    m.loop->run_until([&] { return !faults.empty(); }, 5s);
    ASSERT_EQ(emcys.size(), 1U);
    EXPECT_EQ(emcys[0].message.error_code, 0xFF07);
    EXPECT_EQ(emcys[0].message.manufacturer, (std::array<std::uint8_t, 5>{}))
        << "the manual documents no axis byte in the EMCY";
    ASSERT_EQ(faults.size(), 1U);
    EXPECT_EQ(faults[0].first, 2U) << "attributed to axis 2 through 5104h";
    EXPECT_EQ(faults[0].second.code, 0xFF07);
    EXPECT_EQ(faults[0].second.text, "F2002 Output over current");
    m.loop->run_until([] { return false; }, 100ms); // both axes' list reads are answered
    EXPECT_EQ(akd.axis(1).last_error_code(), 0) << "axis 1 lists no fault (5004h:01 = 0)";
    EXPECT_EQ(akd.axis(2).last_error_code(), 0xFF07);
    auto list1 = m.wait<DriveResult<std::vector<drives::AxisFault>>>(
        [&](auto done) { akd.axis(1).read_faults(done); });
    ASSERT_TRUE(list1) << list1.error().message;
    EXPECT_TRUE(list1->empty());
    std::printf("EMCY %s -> axis %u: %s\n", emcys[0].text.c_str(), faults[0].first,
                faults[0].second.text.c_str());
    sim.signal(SIGINT);
    EXPECT_TRUE(sim.wait(5s));
    m.loop->remove_timed(&akd);
}

TEST(VcanUnits, ReadSiScaleOverSdoFromTheSimulatedAkd2gAndDsBvs) {
    CODRIVE_REQUIRE_VCAN("vcan0");
    Process sim(
        {tool_path("codrive-sim"), "-i", "vcan0", "--node", "7:akd2g:2", "--node", "8:ds-bvs"});
    ASSERT_TRUE(sim.wait_for_output("node 8", 10s)) << sim.output();
    Master m;
    drives::CanopenTransport akd(m.client(7));
    drives::CanopenTransport bvs(m.client(8));
    const auto scale = [&](drives::DriveTransport& t, const drives::Profile& p, unsigned axis) {
        return m.wait<DriveResult<drives::SiScale>>(
            [&](auto done) { drives::read_si_scale(t, p, axis, 2 * kPi, false, done); });
    };

    // AKD2G defaults: 6092h:01 = 65536 per revolution (§4.1.4), 6091h/6096h/6097h 1/1.
    auto s = scale(akd, drives::akd2g_profile(), 1);
    ASSERT_TRUE(s) << s.error().message;
    EXPECT_EQ(s->to_position(kPi), 32768);
    EXPECT_EQ(s->to_velocity(100.0 / 60.0 * 2 * kPi), 109227); // the manual's 100 rpm example

    // The manual's degree example on axis 2 (6892h, 6896h): feed 36000, velocity factor
    // 60/36000 → position in 0.01°, velocity in rpm.
    const auto put = [&](std::uint16_t index, std::uint8_t sub, std::uint32_t v) {
        auto r =
            m.wait<DriveVoid>([&](auto done) { akd.write_as<std::uint32_t>(index, sub, v, done); });
        EXPECT_TRUE(r) << r.error().message;
    };
    put(0x6892, 1, 36000);
    put(0x6896, 1, 60);
    put(0x6896, 2, 36000);
    s = scale(akd, drives::akd2g_profile(), 2);
    ASSERT_TRUE(s) << s.error().message;
    EXPECT_EQ(s->to_position(kPi), 18000);
    EXPECT_EQ(s->to_velocity(100.0 / 60.0 * 2 * kPi), 100);
    auto fg = m.wait<DriveResult<drives::FactorGroup>>(
        [&](auto done) { drives::read_factor_group(akd, drives::akd2g_profile(), 2, done); });
    ASSERT_TRUE(fg) << fg.error().message;
    EXPECT_DOUBLE_EQ(fg->increments_per_motor_rev, 4294967296.0); // §4.1.4: 2^32, no 608Fh
    s = scale(akd, drives::akd2g_profile(), 1);
    ASSERT_TRUE(s);
    EXPECT_EQ(s->to_position(kPi), 32768) << "axis 1 keeps its own factor group";

    // DS-BVS fixed units: counts per 608Fh:01 (default 500), velocity in rpm.
    s = scale(bvs, drives::ds_bvs_profile(), 1);
    ASSERT_TRUE(s) << s.error().message;
    EXPECT_EQ(s->to_position(2 * kPi), 500);
    EXPECT_EQ(s->to_velocity(2 * kPi), 60);
    sim.signal(SIGINT);
    EXPECT_TRUE(sim.wait(5s));
}
