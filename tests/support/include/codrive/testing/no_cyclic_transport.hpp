// SPDX-License-Identifier: Apache-2.0
// Base of the tests' object-access transports: a drives::DriveTransport without process data
// (no cyclic entry is mapped, so every handle is invalid and reads nothing).
#pragma once

#include <codrive/drives/transport.hpp>

#include <cstdint>
#include <optional>

namespace codrive::testing {

class NoCyclicTransport : public drives::DriveTransport {
public:
    [[nodiscard]] drives::CyclicHandle output(std::uint16_t, std::uint8_t) const override {
        return {};
    }
    [[nodiscard]] drives::CyclicHandle input(std::uint16_t, std::uint8_t) const override {
        return {};
    }
    void set_raw(drives::CyclicHandle, std::uint64_t) override {}
    [[nodiscard]] std::optional<std::uint64_t> get_raw(drives::CyclicHandle) const override {
        return std::nullopt;
    }
};

} // namespace codrive::testing
