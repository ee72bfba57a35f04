// SPDX-License-Identifier: Apache-2.0
// Simulated EtherCAT drives: FIO, AKD2G and DS-BVS identities, PDO defaults (specs in
// /work/shared/specs) and a CiA 402 device model behind the ESC.
#pragma once

#include <codrive/sim/ecat/esc_slave.hpp>

#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace codrive::sim::ecat {

/// Profile names accepted by make_drive_slave(): "fio", "akd2g", "ds-bvs".
[[nodiscard]] std::vector<std::string_view> ecat_profile_names();

/// Builds a simulated EtherCAT drive slave for a profile, or nullptr for an unknown name.
/// `serial` is reported in 1018h:04 and the SII.
[[nodiscard]] std::unique_ptr<EscSlave> make_drive_slave(std::string_view profile,
                                                         std::uint32_t serial = 1);

/// Object 5FFFh: a writable VISIBLE_STRING scratch object every simulated slave carries so
/// tests can exercise segmented transfers in both directions (simulator only).
inline constexpr std::uint16_t kScratchStringIndex = 0x5FFF;

} // namespace codrive::sim::ecat
