// SPDX-License-Identifier: Apache-2.0
// Object names and types for decoding: a node's EDS/DCF if given, else built-in CiA 301/402 names.
#pragma once

#include <codrive/core/cob_id.hpp>
#include <codrive/core/data_type.hpp>
#include <codrive/core/eds.hpp>

#include <fmt/format.h>

#include <array>
#include <cstdint>
#include <memory>
#include <optional>
#include <string_view>

namespace codrive::dump {

/// What the decoder knows about one sub-object.
struct ObjectInfo {
    bool known = false;
    DataType type = DataType::Unsigned32;
    bool type_known = false;
    bool hex = false; ///< show unsigned values in hex (COB-IDs, bit fields, identity)
};

/// One row of the built-in table: `sub` 0xFF matches every sub-index not listed; `last` spans an
/// index range (PDO parameters) with `number_base` giving the number shown ("RPDO3 ...").
struct BuiltinObject {
    std::uint16_t index;
    std::uint16_t last;
    std::uint16_t sub; ///< 0..255, or 0x100 for "any sub-index"
    std::string_view object;
    std::string_view name; ///< sub-object name; empty for VAR objects
    DataType type;
    bool hex;
};

/// Names and types of objects, per node: EDS/DCF objects first, then the CiA 301 communication
/// area and CiA 402 objects (axis n of a multi-axis device at +0x800 per axis, CiA 402-1 §6).
class ObjectCatalog {
public:
    ObjectCatalog();
    /// Uses `desc` for `node` (its names, types and default PDO mappings).
    void set_description(NodeId node, std::shared_ptr<const DeviceDescription> desc);
    [[nodiscard]] const DeviceDescription* description(NodeId node) const;

    /// Looks the object up; if `name_out` is given, appends its name ("Statusword",
    /// "Identity object.Vendor-ID", "TPDO1 mapping parameter.Mapped object 2") or nothing.
    ObjectInfo lookup(NodeId node, std::uint16_t index, std::uint8_t subindex,
                      fmt::memory_buffer* name_out) const;

private:
    std::array<std::shared_ptr<const DeviceDescription>, kMaxNodeId + 1> eds_{};
};

/// The built-in table (for tests and docs).
[[nodiscard]] std::span<const BuiltinObject> builtin_objects();

} // namespace codrive::dump
