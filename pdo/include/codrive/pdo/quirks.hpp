// SPDX-License-Identifier: Apache-2.0
// How a device's PDO implementation deviates from plain CiA 301; filled in by drive profiles.
#pragma once

#include <cstdint>
#include <string>

namespace codrive::pdo {

/// PDO behaviour of a device model. The defaults describe a CiA 301 device; drive profiles fill
/// in what their manuals say (see the presets below and docs/pdo.md).
struct PdoQuirks {
    std::string device = "CiA 301"; ///< for messages: "DS-BVS", "AKD2G"
    /// COB-ID sub-index 01h is read-only: the COB-ID cannot be changed, and a PDO cannot be
    /// disabled by bit 31 — it is disabled by mapping count 0 (DS-BVS manual §6.2.13/§6.2.21).
    bool cob_id_read_only = false;
    /// Mappings are not stored by 1010h and come back empty/default after every boot, so the
    /// master must rewrite them after each boot-up (AKD2G manual §5.2.20: "not saved").
    bool maps_volatile = false;
    /// Mapping objects accept writes only in NMT pre-operational (abort 0x08000022 otherwise).
    bool mapping_only_pre_operational = false;
    /// RTR-triggered TPDOs (types 252/253, COB-ID bit 30 clear) are supported.
    bool rtr_supported = true;
    /// 29-bit COB-IDs (bit 29) are supported.
    bool extended_ids_supported = true;
    /// Every entry must start on a byte boundary and be a whole number of bytes.
    bool byte_aligned = false;
    /// Index 0000h with a length is padding (AKD2G §3.11.1); CiA 301 uses dummies 0002h..0007h.
    bool zero_index_padding = false;
    /// Dummy entries (0001h..0007h) may be mapped into RPDOs.
    bool dummy_mapping = true;
    /// Maximum entries per PDO (AKD2G: 8 on CAN; DS-BVS: 10; CiA 301: 64).
    unsigned max_entries = 64;
    /// TPDO sub-index 06h (SYNC start value) exists.
    bool has_sync_start = true;
    /// TPDO sub-index 03h/05h (inhibit time, event timer) exist.
    bool has_inhibit_and_timer = true;
    /// RPDO sub-index 05h (event timer, deadline monitoring) exists.
    bool rpdo_has_event_timer = false;
    /// Transmission type 254 (manufacturer event) is accepted.
    bool type_254_supported = true;
    /// Number of RPDOs / TPDOs the device offers on CAN.
    unsigned rpdo_count = 4;
    unsigned tpdo_count = 4;
};

namespace quirks {

/// A plain CiA 301 device.
[[nodiscard]] PdoQuirks standard();

/// DS-BVS/BVM (ds-bvs spec §0, §1.7, §1.8, §8): COB-IDs read-only (disable by mapping count 0),
/// mapping only in pre-operational, no RTR (bit 30 set, types 252/253 not listed), no SYNC
/// start value, 10 entries per PDO, RPDO comm has sub 0..2 only.
[[nodiscard]] PdoQuirks ds_bvs();

/// Kollmorgen AKD2G (akd2g spec §3): maps volatile (rewrite after every boot), remap in
/// pre-operational with COB-ID bit 31 set, byte aligned with index 0000h padding, 8 entries on
/// CAN, 11-bit only, no RTR types, RPDO comm has sub 0..2 only, no SYNC start value.
[[nodiscard]] PdoQuirks akd2g();

} // namespace quirks

} // namespace codrive::pdo
