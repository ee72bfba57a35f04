// SPDX-License-Identifier: Apache-2.0
// The objects of each manual's object tables that a profile describes without behaviour.
#pragma once

#include <codrive/drives/profile.hpp>

#include <span>
#include <vector>

namespace codrive::drives {

/// AKD2G §5.2/§5.4 objects (axis 1; axis 2 by the profile's offset).
[[nodiscard]] std::span<const ObjectSpec> akd2g_table_objects();
/// DS-BVS §6.2 objects (manufacturer objects 4000h-5010h, VL and unit objects).
[[nodiscard]] std::span<const ObjectSpec> ds_bvs_table_objects();
/// FIO §7.13 objects (manufacturer objects 2010h-3701h, VL and further CiA 402 objects).
[[nodiscard]] std::span<const ObjectSpec> fio_table_objects();

/// A profile's own overrides followed by its table objects, kept for the life of the program.
[[nodiscard]] inline std::vector<ObjectSpec> joined(std::span<const ObjectSpec> overrides,
                                                    std::span<const ObjectSpec> table) {
    std::vector<ObjectSpec> out(overrides.begin(), overrides.end());
    out.insert(out.end(), table.begin(), table.end());
    return out;
}

} // namespace codrive::drives
