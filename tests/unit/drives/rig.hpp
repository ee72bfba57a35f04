// SPDX-License-Identifier: Apache-2.0
// Test rig: a fake clock, a FakeDevice, its transport and an Axis, stepped one cycle at a time.
#pragma once

#include "fake_drive.hpp"

#include <codrive/drives/axis.hpp>

#include <memory>
#include <optional>

namespace codrive::drives::testing {

struct Rig {
    FakeClock clock;
    FakeDevice dev;
    FakeTransport tr;
    bool cyclic;
    std::vector<std::unique_ptr<Axis>> axes;

    explicit Rig(const Profile& p, bool cyclic_io = true, unsigned axis_count = 1)
        : dev(p, axis_count), tr(dev), cyclic(cyclic_io) {
        if (cyclic) {
            for (unsigned a = 1; a <= axis_count; ++a) {
                for (std::uint16_t o :
                     std::initializer_list<std::uint16_t>{0x6040, 0x6060, 0x607A, 0x60FF, 0x6071}) {
                    tr.map_output(p.axis_index(o, a), 0);
                }
                for (std::uint16_t i :
                     std::initializer_list<std::uint16_t>{0x6041, 0x6061, 0x6064, 0x606C}) {
                    tr.map_input(p.axis_index(i, a), 0);
                }
            }
        }
        for (unsigned a = 1; a <= axis_count; ++a) {
            AxisConfig cfg;
            cfg.axis = a;
            cfg.profile = &p;
            cfg.timeout = std::chrono::milliseconds(500);
            cfg.poll_period = std::chrono::milliseconds(2);
            axes.push_back(std::make_unique<Axis>(tr, cfg));
        }
    }

    Axis& axis(unsigned a = 1) { return *axes.at(a - 1); }

    /// One bus cycle: outputs reach the device, the device steps, object access completes,
    /// the axes run.
    void cycle() {
        clock.advance(std::chrono::milliseconds(1));
        tr.apply_outputs();
        dev.step();
        tr.process();
        for (auto& ax : axes) {
            if (cyclic) {
                ax->on_cycle(clock.now());
            } else {
                ax->on_tick(clock.now());
            }
        }
    }
    void cycles(int n) {
        for (int i = 0; i < n; ++i) {
            cycle();
        }
    }

    /// Starts an operation and cycles until its callback ran (or max cycles).
    template <typename Start>
    DriveVoid run(Start start, int max_cycles = 5000) {
        std::optional<DriveVoid> result;
        start([&result](DriveVoid r) { result = std::move(r); });
        for (int i = 0; i < max_cycles && !result; ++i) {
            cycle();
        }
        if (!result) {
            return drive_fail(DriveErrc::Timeout, "test rig: operation never completed");
        }
        return *result;
    }
};

} // namespace codrive::drives::testing
