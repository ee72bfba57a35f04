// SPDX-License-Identifier: Apache-2.0
// The pre-defined error field (CiA 301 1003h) and vendor history arrays like DS-BVS 4080h:
// the newest entry at sub 1, older ones shift down, sub 0 counts them (the drive's depth).
#pragma once

#include <codrive/core/object_dictionary.hpp>

#include <algorithm>
#include <cstdint>
#include <string>
#include <vector>

namespace codrive::sim {

/// Entries when the drive profile documents no depth.
inline constexpr std::uint8_t kDefaultErrorHistoryDepth = 10;

/// An empty history array: sub 0 (rw UNSIGNED8, the count; writing 0 clears it) and `depth`
/// read-only entries of `entry_type`. `limit_count` gives sub 0 a high limit of the depth
/// (DS-BVS 4080h); 1003h leaves the check to its write hook (CiA 301 §7.5.2.4).
inline Object error_history_object(std::uint16_t index, std::string name, std::string count_name,
                                   std::string entry_name, DataType entry_type, std::uint8_t depth,
                                   bool limit_count = false) {
    if (depth == 0) {
        depth = kDefaultErrorHistoryDepth;
    }
    Object o;
    o.index = index;
    o.name = std::move(name);
    o.code = ObjectCode::Array;
    const auto value = [](DataType t, std::uint64_t v) {
        std::vector<std::uint8_t> b(data_type_size(t));
        for (std::size_t i = 0; i < b.size(); ++i) {
            b[i] = static_cast<std::uint8_t>(v >> (8 * i));
        }
        return Value(t, std::move(b));
    };
    auto count = SubObject::make(0, std::move(count_name), DataType::Unsigned8, Access::Rw,
                                 value(DataType::Unsigned8, 0));
    if (limit_count) {
        count.high_limit = value(DataType::Unsigned8, depth);
    }
    o.subs.emplace(0, std::move(count));
    for (std::uint8_t i = 1; i <= depth; ++i) {
        o.subs.emplace(
            i, SubObject::make(i, entry_name, entry_type, Access::Ro, value(entry_type, 0)));
    }
    return o;
}

/// Adds `value` as the newest entry of the history array `index`; nothing if it does not exist.
template <typename T>
void push_error_history(ObjectDictionary& od, std::uint16_t index, T value) {
    Object* o = od.find(index);
    if (o == nullptr) {
        return;
    }
    const auto depth = static_cast<std::uint8_t>(o->subs.rbegin()->first);
    for (std::uint8_t i = depth; i > 1; --i) {
        o->subs.at(i).value = o->subs.at(static_cast<std::uint8_t>(i - 1)).value;
    }
    od.set(index, 1, value);
    const auto n = od.get<std::uint8_t>(index, 0).value_or(0);
    od.set<std::uint8_t>(index, 0, std::min<std::uint8_t>(depth, static_cast<std::uint8_t>(n + 1)));
}

} // namespace codrive::sim
