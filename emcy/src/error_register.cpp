// SPDX-License-Identifier: Apache-2.0
// Error register (1001h) bit names.
#include <codrive/emcy/error_register.hpp>

#include <array>

namespace codrive::emcy {

std::string_view error_register_bit_name(unsigned bit) {
    static constexpr std::array<std::string_view, 8> kNames{
        "generic",       "current",        "voltage",  "temperature",
        "communication", "device profile", "reserved", "manufacturer"};
    return bit < kNames.size() ? kNames[bit] : std::string_view{"invalid"};
}

std::string describe_error_register(std::uint8_t reg) {
    if (reg == 0) {
        return "none";
    }
    std::string out;
    for (unsigned bit = 0; bit < 8; ++bit) {
        if ((reg & (1U << bit)) == 0) {
            continue;
        }
        if (!out.empty()) {
            out += ", ";
        }
        out += error_register_bit_name(bit);
    }
    return out;
}

} // namespace codrive::emcy
