// SPDX-License-Identifier: Apache-2.0
// The error register (object 1001h, CiA 301 §7.5.2.2), sent in every EMCY.
#pragma once

#include <cstdint>
#include <string>
#include <string_view>

namespace codrive::emcy {

/// Bits of 1001h.
enum ErrorRegisterBit : std::uint8_t {
    kGeneric = 1U << 0,
    kCurrent = 1U << 1,
    kVoltage = 1U << 2,
    kTemperature = 1U << 3,
    kCommunication = 1U << 4, ///< overrun, error state
    kDeviceProfile = 1U << 5, ///< device-profile specific
    kReserved = 1U << 6,      ///< always 0 per CiA 301
    kManufacturer = 1U << 7,
};

/// Name of bit 0..7: "generic", "current", "voltage", "temperature", "communication",
/// "device profile", "reserved", "manufacturer".
[[nodiscard]] std::string_view error_register_bit_name(unsigned bit);

/// The set bits as a list: "generic, current"; "none" for 0.
[[nodiscard]] std::string describe_error_register(std::uint8_t reg);

} // namespace codrive::emcy
