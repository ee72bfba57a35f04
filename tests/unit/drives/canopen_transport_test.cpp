// SPDX-License-Identifier: Apache-2.0
// The CANopen DriveTransport end to end on the virtual bus: the profile's PDO layouts written by
// the PDO configurator, SDO access, the PDO master's process image, and two AKD2G axes enabled
// and moved in CSP through it.
#include "fake_drive.hpp"

#include <codrive/core/virtual_bus.hpp>
#include <codrive/drives/axis.hpp>
#include <codrive/drives/canopen_transport.hpp>
#include <codrive/drives/coordinated.hpp>
#include <codrive/pdo/configure.hpp>
#include <codrive/pdo/device.hpp>
#include <codrive/pdo/master.hpp>
#include <codrive/pdo/od_objects.hpp>
#include <codrive/sdo/server.hpp>

#include <gtest/gtest.h>

namespace codrive::drives {
namespace {

using cia402::Mode;
using cia402::State;

TEST(ModePdoConfigs, Akd2gAxesUseNeighbouringPdosAndTheRestIsDisabled) {
    const std::array modes{Mode::CyclicSyncPosition, Mode::ProfileVelocity};
    auto cfgs = mode_pdo_configs(akd2g_profile(), modes);
    ASSERT_TRUE(cfgs.has_value()) << cfgs.error().message;
    ASSERT_EQ(cfgs->size(), 8U);
    EXPECT_EQ((*cfgs)[0].dir, PdoDir::Rpdo);
    EXPECT_EQ((*cfgs)[0].number, 1U);
    EXPECT_EQ((*cfgs)[0].mapping.at(1).raw(), 0x607A0020U);
    EXPECT_EQ((*cfgs)[2].number, 2U);
    EXPECT_EQ((*cfgs)[2].mapping.at(1).raw(), 0x68FF0020U); // axis 2 target velocity
    EXPECT_EQ((*cfgs)[3].mapping.at(0).raw(), 0x68410010U);
    EXPECT_FALSE((*cfgs)[4].enabled);
    for (const auto& c : *cfgs) {
        EXPECT_LE(c.total_bits(), 64U) << c.name();
    }
    const std::array cst{Mode::CyclicSyncTorque};
    auto bad = mode_pdo_configs(akd2g_profile(), cst);
    ASSERT_FALSE(bad.has_value());
    EXPECT_EQ(bad.error().message,
              "Kollmorgen AKD2G has no PDO layout for mode cyclic synchronous torque (CST)");
    EXPECT_TRUE(pdo_quirks(ds_bvs_profile()).cob_id_read_only);
    EXPECT_TRUE(pdo_quirks(akd2g_profile()).maps_volatile);
}

struct CanRig {
    static constexpr NodeId kNode = 5;
    FakeClock clock;
    VirtualNetwork net{clock};
    VirtualBus& mbus = net.endpoint("master");
    VirtualBus& dbus = net.endpoint("drive");
    testing::FakeDevice dev;
    const Profile& profile;
    std::unique_ptr<sdo::SdoServer> server;
    std::unique_ptr<pdo::DevicePdo> dpdo;
    sdo::SdoClient client{mbus, clock, sdo::ClientConfig{kNode}};
    pdo::PdoMaster pm{mbus};
    std::unique_ptr<CanopenTransport> tr;
    std::vector<std::unique_ptr<Axis>> axes;
    std::uint64_t sync = 0;

    CanRig(const Profile& p, unsigned n_axes) : dev(p, n_axes), profile(p) {
        pdo::add_pdo_objects(dev.od(), kNode, pdo_quirks(p));
        sdo::ServerConfig sc;
        sc.node = kNode;
        server = std::make_unique<sdo::SdoServer>(dev.od(), dbus, sc);
        pdo::DevicePdoOptions po;
        po.node = kNode;
        po.quirks = pdo_quirks(p);
        dpdo = std::make_unique<pdo::DevicePdo>(dev.od(), dbus, po);
        dbus.set_frame_handler([this](const Frame& f, TimePoint t) {
            server->on_frame(f, t);
            dpdo->on_frame(f, t);
        });
        mbus.set_frame_handler([this](const Frame& f, TimePoint t) {
            client.on_frame(f, t);
            pm.on_frame(f, t);
        });
        tr = std::make_unique<CanopenTransport>(client);
    }

    /// Runs the bus for `ms` milliseconds without SYNC (configuration phase).
    void idle(int ms) {
        for (int i = 0; i < ms; ++i) {
            clock.advance(milliseconds(1));
            net.deliver();
            client.on_tick(clock.now());
            server->on_tick(clock.now());
            for (auto& a : axes) {
                a->on_tick(clock.now());
            }
            dev.step();
        }
    }

    /// One SYNC cycle: SYNC, the RPDOs for the next one, TPDOs back, the device steps, the axes
    /// run on the received process image.
    void cycle() {
        clock.advance(milliseconds(1));
        ASSERT_TRUE(mbus.send(Frame::make(0x080, {})));
        pm.on_sync(++sync, clock.now());
        net.deliver();
        dev.step();
        client.on_tick(clock.now());
        server->on_tick(clock.now());
        for (auto& a : axes) {
            a->on_cycle(clock.now());
        }
    }

    template <typename Start>
    DriveVoid run(Start start, int max_cycles = 500) {
        std::optional<DriveVoid> result;
        start([&result](DriveVoid r) { result = std::move(r); });
        for (int i = 0; i < max_cycles && !result; ++i) {
            cycle();
        }
        return result ? *result : drive_fail(DriveErrc::Timeout, "rig: never completed");
    }

    bool configure(std::span<const Mode> modes) {
        auto cfgs = mode_pdo_configs(profile, modes);
        if (!cfgs) {
            ADD_FAILURE() << cfgs.error().message;
            return false;
        }
        pdo::DeviceModel model{&dev.od(), nullptr, pdo_quirks(profile)};
        pdo::PdoConfigurator conf(client, model);
        std::optional<pdo::PdoResult<pdo::ConfigureReport>> done;
        conf.configure(*cfgs, [&](pdo::PdoResult<pdo::ConfigureReport> r) { done = r; });
        for (int i = 0; i < 500 && !done; ++i) {
            idle(1);
        }
        if (!done || !*done) {
            ADD_FAILURE() << (done ? done->error().message : "configuration never ended");
            return false;
        }
        auto image = pm.add_node(kNode, *cfgs);
        if (!image) {
            ADD_FAILURE() << image.error().message;
            return false;
        }
        tr->set_image(*image);
        dpdo->set_operational(true, clock.now());
        for (auto& a : axes) {
            a->bind();
        }
        return true;
    }
};

TEST(CanopenTransport, ObjectAccessGoesOverSdo) {
    CanRig rig(akd2g_profile(), 2);
    std::optional<DriveResult<std::uint32_t>> modes;
    rig.tr->read_as<std::uint32_t>(0x6D02, 0, [&](DriveResult<std::uint32_t> r) { modes = r; });
    rig.idle(10);
    ASSERT_TRUE(modes && modes->has_value());
    EXPECT_EQ(**modes, 0xADU);
    std::optional<DriveResult<std::uint32_t>> missing;
    rig.tr->read_as<std::uint32_t>(0x6085, 0, [&](DriveResult<std::uint32_t> r) { missing = r; });
    rig.idle(10);
    ASSERT_TRUE(missing.has_value());
    ASSERT_FALSE(missing->has_value());
    EXPECT_EQ(missing->error().code, DriveErrc::Transport);
    EXPECT_NE(missing->error().message.find("node 5: SDO upload 0x6085:00 aborted"),
              std::string::npos)
        << missing->error().message;
    EXPECT_EQ(rig.tr->name(), "node 5");
}

TEST(CanopenTransport, AxisPollsOverSdoWithoutPdos) {
    CanRig rig(generic_profile(), 1);
    AxisConfig cfg;
    cfg.poll_period = milliseconds(2);
    rig.axes.push_back(std::make_unique<Axis>(*rig.tr, cfg));
    rig.idle(5);
    std::optional<DriveVoid> done;
    rig.axes[0]->enable([&](DriveVoid r) { done = r; });
    for (int i = 0; i < 500 && !done; ++i) {
        rig.idle(1);
    }
    ASSERT_TRUE(done.has_value());
    EXPECT_TRUE(done->has_value()) << done->error().message;
    EXPECT_EQ(rig.dev.model(1).state, State::OperationEnabled);
}

TEST(CanopenTransport, TwoAkd2gAxesRunCspThroughThePdoImage) {
    CanRig rig(akd2g_profile(), 2);
    for (unsigned a = 1; a <= 2; ++a) {
        AxisConfig cfg;
        cfg.axis = a;
        cfg.profile = &akd2g_profile();
        rig.axes.push_back(std::make_unique<Axis>(*rig.tr, cfg));
    }
    rig.idle(5);
    // Mode first over SDO (6060h is not in the RPDOs), then the PDOs.
    const std::array modes{Mode::CyclicSyncPosition, Mode::CyclicSyncPosition};
    ASSERT_TRUE(rig.configure(modes));
    Axis& a1 = *rig.axes[0];
    Axis& a2 = *rig.axes[1];
    ASSERT_TRUE(rig.run([&](auto d) { a1.set_mode(Mode::CyclicSyncPosition, d); }));
    ASSERT_TRUE(rig.run([&](auto d) { a2.set_mode(Mode::CyclicSyncPosition, d); }));
    auto e1 = rig.run([&](auto d) { a1.enable(d); });
    ASSERT_TRUE(e1.has_value()) << e1.error().message;
    auto e2 = rig.run([&](auto d) { a2.enable(d); });
    ASSERT_TRUE(e2.has_value()) << e2.error().message;
    EXPECT_EQ(rig.dev.od().get<std::uint16_t>(0x6840, 0), 0x000F);

    CoordinatedMotion cm({&a1, &a2}, milliseconds(1));
    Eigen::VectorXd end(2), v(2), acc(2), j(2);
    end << 3000, -1500;
    v << 100000, 100000;
    acc << 1e6, 1e6;
    j << 1e8, 1e8;
    std::optional<DriveVoid> done;
    ASSERT_TRUE(
        cm.start(end, v, acc, j, ProfileShape::JerkLimited, [&](DriveVoid r) { done = r; }));
    for (int i = 0; i < 1000 && !done; ++i) {
        cm.on_sync();
        rig.cycle();
    }
    ASSERT_TRUE(done.has_value());
    EXPECT_TRUE(done->has_value()) << done->error().message;
    for (int i = 0; i < 3; ++i) {
        rig.cycle();
    }
    EXPECT_EQ(rig.dev.model(1).position, 3000);
    EXPECT_EQ(rig.dev.model(2).position, -1500);
    EXPECT_EQ(a1.position_actual(), 3000);
    EXPECT_EQ(a2.position_actual(), -1500);
    EXPECT_TRUE(a1.following_setpoints());
    EXPECT_GT(rig.pm.stats().rpdos_sent, 100U);
    EXPECT_GT(rig.pm.stats().tpdos_received, 100U);
}

} // namespace
} // namespace codrive::drives
