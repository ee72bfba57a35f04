// SPDX-License-Identifier: Apache-2.0
// Helpers for the simulated drive tests: an axis on its own dictionary, stepped in 1 ms.
#pragma once

#include <codrive/core/object_dictionary.hpp>
#include <codrive/drives/cia402.hpp>
#include <codrive/sim/drive_core.hpp>

#include <gtest/gtest.h>

#include <functional>
#include <vector>

namespace codrive::sim::testing {

namespace cia = drives::cia402;

struct AxisFixture {
    explicit AxisFixture(const char* profile_name, unsigned axis_count = 1)
        : profile(*find_profile(profile_name)) {
        for (unsigned i = 0; i < axis_count; ++i) {
            axes.push_back(std::make_unique<DriveCore>(od, profile, i));
            axes.back()->set_event_handler([this](const AxisEvent& e) { events.push_back(e); });
        }
    }
    DriveCore& axis(unsigned i = 0) { return *axes.at(i); }

    /// Writes the controlword the way an SDO server would (checks + hooks).
    void controlword(std::uint16_t cw, unsigned i = 0) {
        write<std::uint16_t>(cia::obj::kControlword, cw, i);
    }
    template <typename T>
    tl::expected<void, SdoAbort> write(std::uint16_t base, T v, unsigned i = 0,
                                       std::uint8_t sub = 0) {
        std::uint8_t buf[sizeof(T)];
        put_le<T>(buf, v);
        return od.write(axis(i).index(base), sub, {buf, sizeof(T)});
    }
    template <typename T>
    T read(std::uint16_t base, unsigned i = 0, std::uint8_t sub = 0) {
        return od.get<T>(axis(i).index(base), sub).value_or(T{});
    }
    void run_ms(int ms) {
        for (int k = 0; k < ms; ++k) {
            for (auto& a : axes) {
                a->step(0.001);
            }
        }
    }
    /// Steps until pred() or the budget runs out; true if pred held.
    bool run_until(const std::function<bool()>& pred, int max_ms) {
        for (int k = 0; k < max_ms; ++k) {
            if (pred()) {
                return true;
            }
            run_ms(1);
        }
        return pred();
    }
    cia::State state(unsigned i = 0) {
        return cia::decode_state(read<std::uint16_t>(cia::obj::kStatusword, i));
    }
    std::uint16_t statusword(unsigned i = 0) {
        return read<std::uint16_t>(cia::obj::kStatusword, i);
    }
    void enable(unsigned i = 0) {
        controlword(0x06, i);
        run_ms(1);
        controlword(0x07, i);
        run_ms(1);
        controlword(0x0F, i);
        run_ms(1);
    }

    const SimProfile& profile;
    ObjectDictionary od;
    std::vector<std::unique_ptr<DriveCore>> axes;
    std::vector<AxisEvent> events;
};

} // namespace codrive::sim::testing
