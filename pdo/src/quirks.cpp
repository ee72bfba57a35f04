// SPDX-License-Identifier: Apache-2.0
// PDO quirk presets for the drives in scope (values from /work/shared/specs).
#include <codrive/pdo/quirks.hpp>

namespace codrive::pdo::quirks {

PdoQuirks standard() {
    return {};
}

PdoQuirks ds_bvs() {
    PdoQuirks q;
    q.device = "DS-BVS";
    q.cob_id_read_only = true;             // §1.7: 1400h–1403h:01 and 1800h–1803h:01 are RO
    q.mapping_only_pre_operational = true; // §1.8: "Write access only in NMT Pre-Operational"
    q.rtr_supported = false;               // §8 item 8: bit 30 set, 252/253 not listed
    q.extended_ids_supported = false;
    q.max_entries = 10; // §1.8: sub 01h..0Ah
    q.has_sync_start = false;
    q.rpdo_has_event_timer = false; // RPDO record has 2 entries
    return q;
}

PdoQuirks akd2g() {
    PdoQuirks q;
    q.device = "AKD2G";
    q.maps_volatile = true;                 // §3.2: maps are not saved by 1010h
    q.mapping_only_pre_operational = false; // §5.2.31: dynamic mapping while running
    q.rtr_supported = false;                // 241–254 not mentioned → unsupported
    q.extended_ids_supported = false;       // bit 29: 29-bit not supported
    q.byte_aligned = true;                  // §3.2 "AKD2G PDOs are byte aligned"
    q.zero_index_padding = true;            // padding with index 0000h and a length
    q.max_entries = 8;                      // "8 on CAN bus"
    q.has_sync_start = false;
    q.rpdo_has_event_timer = false; // RPDO has only subs 0–2
    q.type_254_supported = false;
    return q;
}

} // namespace codrive::pdo::quirks
