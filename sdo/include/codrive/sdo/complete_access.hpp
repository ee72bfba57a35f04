// SPDX-License-Identifier: Apache-2.0
// CoE SDO complete access (ETG.1000.6 §5.6.2.1.1, ETG.1020 §12.2): a whole ARRAY or RECORD as
// one SDO value, read from and written to an ObjectDictionary.
#pragma once

#include <codrive/core/object_dictionary.hpp>

#include <cstdint>
#include <span>
#include <tl/expected.hpp>
#include <vector>

namespace codrive::sdo {

/// The object `index` as complete access lays it out, starting at sub-index `sub` (0 or 1):
/// sub-index 0 padded to 16 bits (its ETG.2000 DataType puts sub-index 1 at bit offset 16), then
/// every sub-index 1..n packed. Starting at 1 leaves sub-index 0 out. Aborts: 0x06020000 no
/// such object, 0x06010000 a VAR or a start beyond sub-index 1, or what reading an entry gives.
[[nodiscard]] tl::expected<std::vector<std::uint8_t>, SdoAbort>
read_complete(ObjectDictionary& od, std::uint16_t index, std::uint8_t sub);

/// Checks a complete-access download before its data arrives (object, object code, start).
[[nodiscard]] tl::expected<void, SdoAbort> check_complete(const ObjectDictionary& od,
                                                          std::uint16_t index, std::uint8_t sub);

/// Writes `data` laid out as read_complete() gives it. From sub-index 0, sub-index 0 is cleared
/// first and set last (how PDO assignment and mapping objects must be changed, ETG.1000.6
/// §5.6.7.4); the data must hold every entry it announces (0x06070010 otherwise).
[[nodiscard]] tl::expected<void, SdoAbort> write_complete(ObjectDictionary& od, std::uint16_t index,
                                                          std::uint8_t sub,
                                                          std::span<const std::uint8_t> data);

} // namespace codrive::sdo
