// SPDX-License-Identifier: Apache-2.0
// Compile-time builders for the object-dictionary rows of the vendor profile tables.
#pragma once

#include <codrive/drives/profile.hpp>

#include <cstdint>
#include <string_view>

namespace codrive::drives::builders {

/// One object-dictionary row: index:sub, name, type, access, PDO-mappable, default.
constexpr ObjectSpec spec(std::uint16_t index, std::uint8_t sub, std::string_view name, DataType t,
                          Access a, bool pdo, std::int64_t def, bool record = false) {
    ObjectSpec s;
    s.index = index;
    s.subindex = sub;
    s.name = name;
    s.type = t;
    s.access = a;
    s.pdo = pdo;
    s.default_value = def;
    s.record = record;
    return s;
}

/// The row with a value range (SDO writes outside it abort 0x06090030..32).
constexpr ObjectSpec limited(ObjectSpec s, std::int64_t low, std::int64_t high) {
    s.has_limits = true;
    s.low = low;
    s.high = high;
    return s;
}

} // namespace codrive::drives::builders
