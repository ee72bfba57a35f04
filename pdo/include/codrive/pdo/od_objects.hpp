// SPDX-License-Identifier: Apache-2.0
// Adds the PDO communication and mapping objects of a device to an object dictionary.
#pragma once

#include <codrive/core/object_dictionary.hpp>
#include <codrive/pdo/quirks.hpp>
#include <codrive/pdo/types.hpp>

#include <span>

namespace codrive::pdo {

struct PdoObjectDefaults {
    std::uint8_t rpdo_transmission_type = transmission::kEventProfile;
    std::uint8_t tpdo_transmission_type = transmission::kEventProfile;
    /// Mappings to preset (count and entries); others start empty (sub 0 = 0).
    std::span<const PdoConfig> preset;
};

/// Adds 1400h.. / 1600h.. (quirks.rpdo_count) and 1800h.. / 1A00h.. (quirks.tpdo_count) as
/// CiA 301 §7.5.2.35–38 describes them, shaped by the quirks: COB-ID read-only where
/// cob_id_read_only (DS-BVS), RPDO records with sub 5 only where rpdo_has_event_timer, TPDO sub
/// 6 only where has_sync_start, quirks.max_entries mapping entries. COB-IDs default to the
/// predefined connection set (PDOs 1..4, valid; others invalid), TPDOs with bit 30 set unless
/// RTR is supported. Presets set transmission type, timers and mapping of the given PDOs.
void add_pdo_objects(ObjectDictionary& od, NodeId node, const PdoQuirks& quirks,
                     const PdoObjectDefaults& defaults = {});

} // namespace codrive::pdo
