// SPDX-License-Identifier: Apache-2.0
// The error objects of a simulated drive, one set for the CAN and the EtherCAT simulator: the
// pre-defined error field (CiA 301 1003h), vendor history arrays like DS-BVS 4080h (the newest
// entry at sub 1, older ones shift down, sub 0 counts them) and error behaviour 1029h.
#pragma once

#include <codrive/core/object_dictionary.hpp>
#include <codrive/drives/profile.hpp>
#include <codrive/sim/profile.hpp>

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
        count.low_limit = value(DataType::Unsigned8, 0);
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

/// Writing sub 0 of a history array: only 0 is accepted, and it clears the history
/// (CiA 301 §7.5.2.4; DS-BVS §6.2.44.1; FIO §7.13.3 "setting this object to 0 starts a new count").
inline tl::expected<void, SdoAbort> clear_error_history(std::uint16_t, std::uint8_t sub,
                                                        std::span<const std::uint8_t> d) {
    if (sub == 0 && (d.empty() || d[0] != 0)) {
        return tl::unexpected(SdoAbort::InvalidValue);
    }
    return {};
}

/// The drive's error objects as its manual lists them, on either transport: the error history
/// the drive profile names (1003h for AKD2G and FIO, 4080h for DS-BVS §6.2.44) with its
/// clear-on-0 hook, and 1029h (DS-BVS §6.2.12) from the drive profile.
inline void add_error_objects(ObjectDictionary& od, const SimProfile& p) {
    const std::uint16_t history = p.drive->error_history_index;
    if (history == 0x1003) {
        od.insert(error_history_object(0x1003, "Pre-defined error field", "Number of errors",
                                       "Standard error field", DataType::Unsigned32,
                                       p.drive->error_history_depth));
    } else {
        od.insert(error_history_object(history, "Error history", "Number of entries", "Error code",
                                       DataType::Unsigned16, p.drive->error_history_depth, true));
    }
    od.on_write(history, clear_error_history);
    drives::add_error_behaviour_object(od, *p.drive); // DS-BVS 1029h, as the master has it
}

/// Records a fault in the drive's error history: 1003h in the drive's own layout
/// (SimProfile::error_history_entry), a vendor array (DS-BVS 4080h) the EMCY code. `reg` is 1001h
/// with the fault already in it.
inline void record_error_history(ObjectDictionary& od, const SimProfile& p, const FaultCode& code,
                                 std::uint8_t reg) {
    const std::uint16_t history = p.drive->error_history_index;
    if (history == 0x1003) {
        push_error_history(od, history, p.error_history_entry(code, reg));
    } else {
        push_error_history(od, history, code.emcy);
    }
}

} // namespace codrive::sim
