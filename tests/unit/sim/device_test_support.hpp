// SPDX-License-Identifier: Apache-2.0
// A simulated node and a master endpoint (SDO client, frame log) on a virtual bus.
#pragma once

#include <codrive/core/virtual_bus.hpp>
#include <codrive/sdo/client.hpp>
#include <codrive/sim/sim_device.hpp>

#include <gtest/gtest.h>

#include <optional>
#include <vector>

namespace codrive::sim::testing {

struct DeviceFixture {
    explicit DeviceFixture(const char* profile, NodeId node = 3, unsigned axes = 0)
        : dev_bus(net.endpoint("node")), master(net.endpoint("master")),
          device(dev_bus, make_config(profile, node, axes)),
          client(master, clock, sdo::ClientConfig{.node = node}) {
        dev_bus.set_frame_handler([this](const Frame& f, TimePoint t) { device.on_frame(f, t); });
        master.set_frame_handler([this](const Frame& f, TimePoint t) {
            frames.push_back(f);
            client.on_frame(f, t);
        });
    }
    static SimDeviceConfig make_config(const char* profile, NodeId node, unsigned axes) {
        SimDeviceConfig c;
        c.node = node;
        c.profile = find_profile(profile);
        c.axes = axes;
        return c;
    }
    void start() {
        device.start(clock.now());
        run_ms(0);
    }
    void run_ms(int ms) {
        net.run_until(clock, clock.now() + milliseconds(ms), {&device, &client});
    }
    void send(const Frame& f) {
        ASSERT_TRUE(master.send(f));
        run_ms(0);
    }
    template <typename T>
    sdo::SdoResult<T> read(std::uint16_t index, std::uint8_t sub) {
        std::optional<sdo::SdoResult<T>> out;
        client.read<T>(index, sub, [&](sdo::SdoResult<T> r) { out = std::move(r); });
        for (int i = 0; i < 3000 && !out; ++i) {
            run_ms(1);
        }
        EXPECT_TRUE(out.has_value());
        return out ? std::move(*out) : tl::unexpected(sdo::SdoError{});
    }
    template <typename T>
    sdo::SdoResult<void> write(std::uint16_t index, std::uint8_t sub, T value) {
        std::optional<sdo::SdoResult<void>> out;
        client.write<T>(index, sub, value, [&](sdo::SdoResult<void> r) { out = std::move(r); });
        for (int i = 0; i < 3000 && !out; ++i) {
            run_ms(1);
        }
        EXPECT_TRUE(out.has_value());
        return out ? std::move(*out) : tl::unexpected(sdo::SdoError{});
    }
    /// Frames the master saw with this COB-ID.
    std::vector<Frame> with_id(std::uint32_t id) const {
        std::vector<Frame> out;
        for (const auto& f : frames) {
            if (f.id == id) {
                out.push_back(f);
            }
        }
        return out;
    }
    std::vector<std::uint16_t> emcy_codes(NodeId node) const {
        std::vector<std::uint16_t> out;
        for (const auto& f : with_id(0x80U + node)) {
            out.push_back(static_cast<std::uint16_t>(f.data[0] | (f.data[1] << 8)));
        }
        return out;
    }

    FakeClock clock;
    VirtualNetwork net{clock};
    VirtualBus& dev_bus;
    VirtualBus& master;
    SimDevice device;
    sdo::SdoClient client;
    std::vector<Frame> frames;
};

} // namespace codrive::sim::testing
