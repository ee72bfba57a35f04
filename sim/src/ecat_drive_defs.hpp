// SPDX-License-Identifier: Apache-2.0
// The EtherCAT side of the simulated drives as data: PDO maps, 1C12h/1C13h defaults, sync
// managers and AL status codes of the FIO, AKD2G and DS-BVS, from their manuals (private header).
#pragma once

#include <codrive/pdo/quirks.hpp>

#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace codrive::sim::ecat {

struct PdoDef {
    std::uint16_t index;
    std::vector<std::uint32_t> entries;
    bool fixed = false; ///< read-only mapping (DS-BVS 1604h.., AKD2G 17xxh/1Bxxh)
};

/// The EtherCAT side of a simulated drive: ESC buffers and PDO maps. The identity (1018h and
/// SII) is filled in by make_drive_slave() from the SimProfile, the one the CAN simulator uses.
struct DriveDef {
    std::string name;
    std::string_view profile; ///< SimProfile name
    std::uint32_t vendor = 0;
    std::uint32_t product = 0;
    std::uint32_t revision = 0;
    /// Mailbox sync managers SM0 (master → slave) and SM1 (slave → master).
    std::uint16_t mbx_out = 0x1000;
    std::uint16_t mbx_in = 0x1080;
    std::uint16_t mbx_size = 128;
    std::uint16_t sm2 = 0x1100;
    std::uint16_t sm3 = 0x1180;
    std::vector<PdoDef> rx;
    std::vector<PdoDef> tx;
    std::vector<std::uint16_t> rx_assign;
    std::vector<std::uint16_t> tx_assign;
    std::uint8_t assign_max = 4;
    /// Mapping entries per free PDO (sub-indexes 1..n; sub 0 takes 0..map_slots).
    std::uint8_t map_slots = 8;
    /// The mapping objects 1C12h:01../1C13h:01.. accept (0: any), where the manual gives them.
    std::uint16_t rx_assign_low = 0;
    std::uint16_t rx_assign_high = 0;
    std::uint16_t tx_assign_low = 0;
    std::uint16_t tx_assign_high = 0;
    /// Sync managers 1C00h lists (the first four are mailbox out/in, outputs, inputs; the rest 0).
    std::uint8_t sm_channels = 4;
    /// Entries written to the free maps are checked with these rules (AKD2G §3.11); unset: not
    /// checked.
    std::optional<pdo::PdoQuirks> map_rules;
    /// 1C32h/1C33h: highest sub-index reported, entries present (1..n) and the default cycle
    /// time. Drives whose manual is silent keep sub 1..2 and 1 ms.
    std::uint8_t sm_out_highest = 2;
    std::uint8_t sm_in_highest = 2;
    std::uint8_t sm_entries = 2;
    std::uint32_t sm_cycle_time = 1'000'000;
    /// When set: 1C32h/1C33h sub-indices 1.. exactly as a manual lists them (the AKD2G's).
    struct SyncSub {
        std::uint8_t sub;
        const char* name;
        bool u16;
        bool writable;
        std::uint32_t value;
    };
    std::vector<SyncSub> sm_subs;
    /// The AL status codes the drive reports (ETG code → the drive's); unset: all of ETG.1000.6.
    std::uint16_t (*al_code)(std::uint16_t) = nullptr;
};

/// Kuhnke FIO Drive Control (one axis).
[[nodiscard]] DriveDef fio_def();
/// Kollmorgen AKD2G with `axes` axes (1 or 2).
[[nodiscard]] DriveDef akd2g_def(unsigned axes);
/// DS-BVS/BVM (one axis).
[[nodiscard]] DriveDef dsbvs_def();
/// A CiA 402 slave no profile of codrive's knows; `assigned`: its 1C12h/1C13h hold a layout.
[[nodiscard]] DriveDef generic_def(bool assigned);

} // namespace codrive::sim::ecat
