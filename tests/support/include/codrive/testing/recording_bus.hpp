// SPDX-License-Identifier: Apache-2.0
// An ICanBus that accepts every frame and keeps it, for tests that play the other side.
#pragma once

#include <codrive/core/can_bus.hpp>

#include <string>
#include <utility>
#include <vector>

namespace codrive::testing {

/// Records what a service sends (`sent`, and `stats().tx_frames`); delivers nothing.
class RecordingBus final : public ICanBus {
public:
    explicit RecordingBus(std::string name = "recording") : name_(std::move(name)) {}
    VoidResult send(const Frame& frame) override {
        sent.push_back(frame);
        ++stats_.tx_frames;
        return {};
    }
    void set_frame_handler(FrameHandler /*handler*/) override {}
    void set_event_handler(EventHandler /*handler*/) override {}
    [[nodiscard]] std::size_t tx_pending() const override { return 0; }
    [[nodiscard]] const BusStats& stats() const override { return stats_; }
    [[nodiscard]] const std::string& name() const override { return name_; }

    std::vector<Frame> sent;

private:
    BusStats stats_;
    std::string name_;
};

} // namespace codrive::testing
