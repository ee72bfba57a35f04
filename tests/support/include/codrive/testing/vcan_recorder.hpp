// SPDX-License-Identifier: Apache-2.0
// Records the frames on a vcan interface while a vcan test runs (its own loop and socket).
#pragma once

#include <codrive/core/event_loop.hpp>
#include <codrive/core/socket_can_bus.hpp>

#include <gtest/gtest.h>

#include <chrono>
#include <functional>
#include <memory>
#include <string>
#include <utility>
#include <vector>

namespace codrive::testing {

/// Every frame on `ifname` that passes `filters` (none: every frame), in order of arrival.
struct VcanRecorder {
    explicit VcanRecorder(const std::string& ifname = "vcan0",
                          std::vector<CanFilter> filters = {}) {
        auto l = EventLoop::create();
        EXPECT_TRUE(l);
        loop = std::move(*l);
        SocketCanOptions o;
        o.filters = std::move(filters);
        auto b = SocketCanBus::open(ifname, o);
        EXPECT_TRUE(b) << b.error().message();
        bus = std::move(*b);
        bus->set_frame_handler([this](const Frame& f, TimePoint) { frames.push_back(f); });
        EXPECT_TRUE(bus->attach(*loop));
    }
    /// Records for `d`.
    void drain(Duration d = std::chrono::milliseconds(100)) { loop->run_until(loop->now() + d); }
    /// Records until `pred` holds or `d` passed; true if it holds.
    bool run_until(const std::function<bool()>& pred, Duration d) {
        return loop->run_until(pred, d);
    }
    [[nodiscard]] std::vector<Frame> with_id(std::uint32_t id) const {
        std::vector<Frame> out;
        for (const auto& f : frames) {
            if (f.id == id) {
                out.push_back(f);
            }
        }
        return out;
    }
    std::unique_ptr<EventLoop> loop;
    std::unique_ptr<SocketCanBus> bus;
    std::vector<Frame> frames;
};

} // namespace codrive::testing
