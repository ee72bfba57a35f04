// SPDX-License-Identifier: Apache-2.0
// One CiA 402 axis on an EtherCAT slave driven through process data: which PDO layout to use
// (profile, the slave's own 1C12h/1C13h assignment, generic) and the sync objects 1C32h/1C33h.
#pragma once

#include <codrive/drives/cia402.hpp>
#include <codrive/drives/profile.hpp>
#include <codrive/ethercat/esi_pdos.hpp>
#include <codrive/ethercat/master.hpp>
#include <codrive/pdo/types.hpp>

#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include <tl/expected.hpp>

namespace codrive::ethercat {

/// The profile's CANopen PDO layouts as EtherCAT mapping objects: RPDO n → 1600h + n − 1,
/// TPDO n → 1A00h + n − 1 (ETG.1000.6 §5.6.7.4 uses the same CiA 301 numbering).
void to_ecat_pdos(const std::vector<pdo::PdoConfig>& configs, std::vector<PdoMapping>& rx,
                  std::vector<PdoMapping>& tx);

/// Where the PDO layout of a driven axis comes from.
enum class LayoutSource {
    Profile,         ///< the known drive's profile layout for the mode
    SlaveAssignment, ///< the slave's own 1C12h/1C13h assignment (kept, nothing written)
    Esi,             ///< the default assignment of the vendor's ESI file (configured)
    Generic,         ///< the generic CiA 402 layout for the mode (configured)
};

/// "the drive's profile", "the slave's own assignment", "the ESI's default assignment", "the
/// generic CiA 402 layout".
[[nodiscard]] const char* to_string(LayoutSource s);

/// The layout chosen for one axis: the mappings to write (empty for SlaveAssignment).
struct DriveLayout {
    LayoutSource source = LayoutSource::Generic;
    std::vector<PdoMapping> rx;
    std::vector<PdoMapping> tx;
};

/// True when `rx` maps the axis's controlword (6040h) and `tx` its statusword (6041h), the
/// least a CiA 402 state machine run from process data needs (CiA 402-2 / ETG.6010 §4).
[[nodiscard]] bool holds_controlword_statusword(const std::vector<PdoMapping>& rx,
                                                const std::vector<PdoMapping>& tx,
                                                std::uint16_t controlword,
                                                std::uint16_t statusword);

/// Picks the layout: a known drive (profile with a vendor id) uses its profile's layout for
/// `mode`; a slave codrive does not know takes the default assignment of its vendor's ESI
/// (`esi`, ETG.2000 §5.4.4) when that maps 6040h/6041h, else keeps its own assignment
/// (`current`, read from 1C12h/1C13h) when that does, else gets the generic profile's layout for
/// `mode`. Error: a sentence when neither the profile nor the generic profile has a layout for
/// `mode`.
[[nodiscard]] tl::expected<DriveLayout, std::string>
choose_layout(const drives::Profile& profile, unsigned axis, drives::cia402::Mode mode,
              const std::vector<PdoMapping>& current_rx, const std::vector<PdoMapping>& current_tx,
              const EsiDefaultPdos* esi = nullptr);

/// Synchronisation type written to 1C32h:01/1C33h:01 (ETG.1020 §21.1.3: 0 free run, 1
/// synchronous with the SM2 (outputs) event, 2 DC SYNC0; 3 DC SYNC1 is not offered).
enum class SyncMode : std::uint16_t { FreeRun = 0, SmSynchronous = 1, DcSync0 = 2 };

/// "free" (free run), "sm" (SM-synchronous), "dc" (DC SYNC0), as the bus file and
/// `codrive drive --sync` write them; nullopt for anything else.
[[nodiscard]] std::optional<SyncMode> sync_mode_from_string(std::string_view text);

/// How the slave synchronises to the cycle (ETG.1020 §21.1.3, 1C32h:01/1C33h:01).
struct SyncSettings {
    Duration cycle = milliseconds(1);
    SyncMode mode = SyncMode::FreeRun;
    Duration shift{}; ///< SYNC0 start after the cycle's time grid (DC only)
    std::string name; ///< the user's name for the slave (bus file), shown in sentences
};

/// What write_sync_objects() did: the mode written and one sentence per object it left alone
/// (absent or read-only), for an info line.
struct SyncReport {
    std::uint16_t mode = 0;         ///< 0 free run, 1 SM-synchronous, 2 DC SYNC0
    std::uint32_t min_cycle_ns = 0; ///< 1C32h:05, 0 when the slave states none
    std::vector<std::string> notes; ///< "slave 0 (FIO): has no 0x1C32:05 (no minimum stated)"
};

/// "free run" (0), "SM synchronous" (1), "DC SYNC0" (2), ... (ETG.1020 §21.1.3.1).
[[nodiscard]] const char* sync_mode_name(std::uint16_t mode);

/// Before SAFE-OP (the slave in PRE-OP): reads 1C32h:04 (sync modes supported) where the slave
/// has it and refuses a mode it does not offer; reads 1C32h:05 (minimum cycle time) where the
/// slave has it and refuses a shorter cycle; writes 1C32h:01 and 1C33h:01 (sync mode: 0 free
/// run, 1 SM-synchronous, 2 DC SYNC0) and 1C32h:02 (cycle time, ns). An object or sub-index the
/// slave lacks, or one it reports read-only (it sets them itself, as the AKD2G does), is left alone
/// and named in the report's notes (ETG.1020 §21.1.3: the master writes them where writable).
/// Blocking (mailbox frames). Error: one sentence naming the slave, the object and the cause.
tl::expected<SyncReport, std::string> write_sync_objects(Master& master, std::size_t slave,
                                                         const SyncSettings& sync);

/// The one way a slave is synchronised before SAFE-OP, for `codrive drive --ethercat` and the
/// controller alike: write_sync_objects(), then in DC SYNC0 mode SYNC0 at the cycle and shift
/// (Master::configure_sync0). For DC SYNC0, call Master::configure_dc() once for the segment
/// first. Blocking. Error: one sentence naming the slave and the cause.
tl::expected<SyncReport, std::string> configure_sync(Master& master, std::size_t slave,
                                                     const SyncSettings& sync);

} // namespace codrive::ethercat
