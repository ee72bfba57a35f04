// SPDX-License-Identifier: Apache-2.0
// The `ethercat:` section of a bus file: one EtherCAT segment (interface, cycle, slaves with
// drive profiles and axes) that a Controller runs next to its CAN buses.
#pragma once

#include <codrive/ethercat/drive_layout.hpp>
#include <codrive/ethercat/esi.hpp>

#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace codrive::controller {

/// One axis of an EtherCAT slave.
struct EcatAxisEntry {
    unsigned axis = 1;               ///< 1-based (AKD2G axis 2 objects at +0x800)
    std::optional<std::int8_t> mode; ///< written to 6060h in PRE-OP; selects the PDO layout
};

/// One slave of the segment, by position (0 = next to the master).
struct EcatSlaveEntry {
    unsigned position = 0;
    std::string name;    ///< shown in messages
    std::string profile; ///< "akd2g", "ds-bvs", "fio", "generic"
    std::vector<EcatAxisEntry> axes;
    /// Overrides the segment's sync mode (`sync:`, or `dc: true|false`).
    std::optional<ethercat::SyncMode> sync;
    std::optional<std::uint32_t> sync0_shift_us; ///< overrides the segment's `sync0_shift_us`
    /// The slave's ESI file (`esi:`, else the segment's), read when the bus file is parsed: the
    /// SII identity must match one of its devices, and without `axes` its default PDO
    /// assignment (the PDOs with an `Sm`) is written. nullptr: none.
    std::shared_ptr<const ethercat::EsiFile> esi;
    int line = 0;
};

/// An EtherCAT segment: bring-up to OP with the profiles' PDO layouts, then one LRW per cycle.
struct EcatSegmentConfig {
    std::string file;  ///< bus file, for messages
    std::string iface; ///< Ethernet interface ("eth1", a veth end)
    std::uint32_t cycle_us = 1000;
    /// Cyclic frames lost in a row that raise an event naming the segment (each lost frame is
    /// counted in the statistics; the cycle never waits longer than its period for one).
    unsigned lost_frames_event = 3;
    /// How every slave synchronises (a slave's own `sync`/`dc` overrides it), written to
    /// 1C32h:01/1C33h:01 (ETG.1020 §21.1.3.1): `sync: free` (0, the default), `sync: sm` (1,
    /// synchronous with the SM2 event of the cyclic frame), `sync: dc` or `dc: true` (2, DC
    /// SYNC0: the master runs its DC setup, programs SYNC0 at the cycle and distributes the
    /// reference clock's time in every cyclic frame).
    ethercat::SyncMode sync = ethercat::SyncMode::FreeRun;
    /// SYNC0 start after the cycle's time grid, µs (0..cycle_us − 1; only with `dc`).
    std::uint32_t sync0_shift_us = 0;
    /// The segment's `esi:` (every slave's that has none of its own); nullptr: none.
    std::shared_ptr<const ethercat::EsiFile> esi;
    std::vector<EcatSlaveEntry> slaves;
};

/// The sync mode of one slave: its own `sync`/`dc`, else the segment's.
[[nodiscard]] ethercat::SyncMode slave_sync(const EcatSegmentConfig& segment,
                                            const EcatSlaveEntry& slave);
/// Whether one slave runs on DC SYNC0 (slave_sync() is DcSync0).
[[nodiscard]] bool slave_dc(const EcatSegmentConfig& segment, const EcatSlaveEntry& slave);
/// The SYNC0 shift of one slave (µs): its own `sync0_shift_us`, else the segment's.
[[nodiscard]] std::uint32_t slave_sync0_shift_us(const EcatSegmentConfig& segment,
                                                 const EcatSlaveEntry& slave);

/// What from_file() finds in a bus file: CAN buses and EtherCAT segments.
struct BusFileSections {
    std::string can_text;                      ///< the file with the `ethercat:` block blanked
    bool has_can = false;                      ///< a `bus:` section is present
    std::optional<EcatSegmentConfig> ethercat; ///< set when the section parsed without errors
    std::vector<std::string> errors;           ///< "bus.yml:14: ..." one per finding
};

/// Splits a bus file's text: the `ethercat:` block is parsed here (every finding reported, with
/// line numbers), the rest is left for master::parse_bus_config() with the same line numbers.
/// Errors (in `errors`): unknown keys, missing interface, bad cycle, duplicate positions, unknown
/// profiles or modes, an `esi:` file that cannot be read (its own `file:line:` sentence follows
/// the bus file's line), no section at all. `esi:` paths are relative to `file`'s directory.
[[nodiscard]] BusFileSections split_bus_file(const std::string& text, const std::string& file);

} // namespace codrive::controller
