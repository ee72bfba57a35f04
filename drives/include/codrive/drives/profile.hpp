// SPDX-License-Identifier: Apache-2.0
// Drive profiles: the vendor knowledge (identity, modes, PDO layouts, fault tables, quirks) as
// data shared by the master-side axis model and the simulated drives.
#pragma once

#include <codrive/core/data_type.hpp>
#include <codrive/core/object_dictionary.hpp>
#include <codrive/drives/cia402.hpp>
#include <codrive/emcy/text_provider.hpp>

#include <cstdint>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

namespace codrive::drives {

/// Identity a profile matches (1000h device type, 1018h:1 vendor, 1018h:2 product code).
/// A zero field or mask matches anything.
struct Identity {
    std::uint32_t device_type = 0;       ///< 1000h as reported on CAN
    std::uint32_t device_type_mask = 0;  ///< bits of 1000h compared
    std::uint32_t vendor_id = 0;         ///< 1018h:1
    std::uint32_t product_code = 0;      ///< 1018h:2 (example value for simulators)
    std::uint32_t product_code_mask = 0; ///< bits of 1018h:2 compared
    std::string_view device_name;        ///< 1008h prefix, when the vendor id is not documented
    std::uint32_t axes_mask = 0;         ///< bits of 1018h:2 holding the axis count (AKD2G)
    std::uint8_t axes_shift = 0;
};

/// One vendor fault/error row: EMCY error code → the vendor's fault number and text.
struct FaultRow {
    std::uint16_t code = 0;          ///< EMCY / 603Fh error code
    std::string_view number;         ///< vendor fault/warning number ("F2006", "W6011"), may be ""
    std::string_view text;           ///< the manual's text
    std::uint8_t error_register = 0; ///< 1001h bits the drive sets with it (0 = not documented)
    [[nodiscard]] bool is_warning() const { return !number.empty() && number[0] == 'W'; }
};

/// A vendor error number carried in the EMCY manufacturer bytes (Kuhnke FIO: 1003h bits 31..24,
/// EMCY manufacturer byte 0).
struct ErrorNumberRow {
    std::uint8_t number = 0;
    std::string_view text;
    std::uint16_t typical_code = 0; ///< the code the simulator pairs with it (inferred, see spec)
};

/// A manufacturer-specific mode of operation (negative 6060h values).
struct ManufacturerMode {
    std::int8_t value = 0;
    std::string_view name;
};

/// One mapped object in a PDO, for axis 1 (axis offsets are applied when resolving).
struct PdoEntry {
    std::uint16_t index = 0;
    std::uint8_t subindex = 0;
    std::uint8_t bits = 0;
};

/// The PDOs a mode needs for one axis: one receive PDO (master → drive) and one transmit PDO
/// (drive → master), each at most 8 bytes so it fits a classic CAN frame. The PDO number
/// (0-based: RPDO1/TPDO1 = 0) is `first_pdo + axis - 1`, so axes of a dual-axis drive use
/// neighbouring PDOs.
struct ModeLayout {
    cia402::Mode mode = cia402::Mode::NoMode;
    std::span<const PdoEntry> rx;
    std::span<const PdoEntry> tx;
    std::uint8_t first_pdo = 0;
};

/// Behaviour of a drive that a master must respect and a simulator must reproduce.
struct Quirks {
    bool canopen = true;                ///< has a CAN interface (FIO: EtherCAT only)
    bool error_behaviour_1029 = false;  ///< 1029h:01/02 exist (DS-BVS; AKD2G: no)
    bool pdo_cob_ids_read_only = false; ///< DS-BVS: 1400h/1800h sub 1 RO, disable via mapping sub 0
    bool pdo_maps_volatile = false;     ///< AKD2G, DS-BVS: 1600h/1A00h not stored by 1010h
    /// DS-BVS: 1011h restores only in NMT pre-operational with the power stage disabled.
    bool restore_needs_preop_power_disabled = false;
    bool pdo_mapping_preop_only = true;      ///< mapping writes only in NMT pre-operational
    bool empty_default_pdo_maps = false;     ///< DS-BVS: no predefined mapping at all
    std::uint8_t max_pdo_entries = 8;        ///< mapping entries per CAN PDO
    bool switch_on_needs_bit3_clear = false; ///< DS-BVS: 0x0F in READY does only transition 3
    bool sto_in_statusword_bit8 = false;     ///< AKD2G: statusword bit 8 = STO active
    /// Statusword bit 8 in CSP = "synchronised with the fieldbus" (FIO §7.8.1.4).
    bool csp_bit8_synchronised = false;
    /// Statusword bit 15 = CLA "closed loop available": 1 after a successful auto setup (FIO
    /// §7.13 6041h); the simulator runs no auto setup, so it stays 0.
    bool statusword_bit15_closed_loop = false;
    bool voltage_bit4_is_dc_bus = false;     ///< AKD2G: statusword bit 4 = DC bus present
    bool remote_bit9_always_set = false;     ///< DS-BVS, FIO: bit 9 always 1
    bool has_shutdown_option_codes = true;   ///< 605Bh..605Eh exist (AKD2G: no)
    bool halt_ignored_in_csp = false;        ///< AKD2G: halt has no function in CSP
    bool interpolation_period_object = true; ///< 60C2h exists (DS-BVS: no)
    std::uint32_t fixed_encoder_increments =
        0; ///< internal counts/rev if 608Fh is absent (AKD2G 2^32)
    /// 6063h counts per motor revolution (AKD2G: 2^(32-PSCALE) = 2^12 by default, §5.4.6);
    /// 0 = the same units as 6064h.
    std::uint32_t internal_counts_per_rev = 0;
    /// Type of 1016h sub 0 (CiA 301: UNSIGNED8; the AKD2G manual §5.2.14 says Unsigned32).
    DataType heartbeat_consumer_sub0_type = DataType::Unsigned8;
    bool si_unit_objects = false;               ///< FIO: 60A8h/60A9h define the user units
    bool sync_consumer_only = true;             ///< the drive never produces SYNC
    bool fault_reset_only_without_cause = true; ///< transition 15 only if the cause is gone
};

/// The signatures CiA 301 §7.5.2.13/§7.5.2.14 defines for 1010h (store) and 1011h (restore):
/// "save" and "load" read as little-endian UNSIGNED32.
inline constexpr std::uint32_t kSaveSignature = 0x65766173;
inline constexpr std::uint32_t kLoadSignature = 0x64616F6C;

/// A parameter category of 1010h (store) and 1011h (restore): one sub-index in each.
struct StoreCategory {
    std::uint8_t subindex = 1;
    std::string_view name;  ///< "all", "comm", "app", … (what `codrive save --what` takes)
    std::string_view title; ///< the manual's name of the sub-index
    /// Indexes the category stores; empty: every writable object the drive backs up (for a
    /// drive with several categories, every object of the others).
    std::span<const std::uint16_t> objects;
};

/// How a drive keeps parameters in non-volatile memory (1010h/1011h).
struct Persistence {
    /// The categories the drive offers; empty: one, "all" at sub-index 1 (CiA 301).
    std::span<const StoreCategory> categories;
    std::uint8_t highest_subindex = 1;        ///< 1010h/1011h sub 0
    std::uint32_t store_read_before_save = 1; ///< 1010h:n read before any save (FIO: 0)
    /// 1011h makes the drive restart on its own (FIO §7.12.4.16); otherwise the defaults take
    /// effect at the next reset node or power-on (CiA 301 §7.5.2.14).
    bool restore_restarts = false;
};

/// One CAN bit rate a drive accepts in its bit-rate object, and the code it is written as.
struct BitRateCode {
    std::uint8_t code = 0;
    unsigned kbit = 0;
};

/// Node-ID and bit-rate objects a drive reads at start (DS-BVS 5000h/5002h, §6.2.74/§6.2.76):
/// written, saved with 1010h and effective after a restart.
struct Commissioning {
    std::uint16_t node_id_object = 0; ///< 0: the drive has none (set the node-ID otherwise)
    std::uint16_t bit_rate_object = 0;
    std::span<const BitRateCode> bit_rates; ///< the supported codes
    /// The code for `kbit`, or nullopt if the drive does not support that rate.
    [[nodiscard]] std::optional<std::uint8_t> code_for(unsigned kbit) const {
        for (const BitRateCode& b : bit_rates) {
            if (b.kbit == kbit) {
                return b.code;
            }
        }
        return std::nullopt;
    }
};

/// A PDO mapping object as the drive ships it: entries index << 16 | sub << 8 | bits.
struct DefaultPdoMap {
    std::uint16_t index = 0;
    std::span<const std::uint32_t> entries;
};

/// Description of one CiA 402 object (or sub-object) as a device holds it.
struct ObjectSpec {
    std::uint16_t index = 0;
    std::uint8_t subindex = 0;
    std::string_view name;
    DataType type = DataType::Unsigned8;
    Access access = Access::Ro;
    bool pdo = false;
    std::int64_t default_value = 0;
    bool has_limits = false;
    std::int64_t low = 0;
    std::int64_t high = 0;
    /// Part of a RECORD/ARRAY: sub 0 is added as "highest sub-index", unless the record lists
    /// its own sub 0, which is then kept as described.
    bool record = false;
};

/// Everything codrive knows about a drive family.
struct Profile {
    std::string_view name;  ///< "akd2g", "ds-bvs", "fio", "generic"
    std::string_view title; ///< "Kollmorgen AKD2G"
    Identity identity;
    std::uint16_t axis_offset = 0; ///< index offset per further axis (AKD2G: 0x800)
    std::uint8_t max_axes = 1;
    std::uint32_t supported_modes = 0; ///< 6502h value the drive reports
    /// Modes the drive accepts in 6060h although 6502h does not say so (AKD2G: CSV).
    std::span<const std::int8_t> extra_modes;
    /// Modes 6502h claims but 6060h rejects (DS-BVS: VL 2 and PT 4).
    std::span<const std::int8_t> rejected_modes;
    std::span<const ManufacturerMode> manufacturer_modes;
    std::span<const std::int8_t> homing_methods;
    std::span<const std::int16_t> quick_stop_options; ///< supported 605Ah values
    std::int16_t default_quick_stop_option = 2;
    /// 6007h values the drive accepts when its range has reserved holes (DS-BVS: 1 is
    /// reserved); empty = every value in the object's range.
    std::span<const std::int16_t> abort_connection_options;
    std::int8_t default_mode = 0; ///< 6060h after power-on
    std::span<const FaultRow> faults;
    std::span<const ErrorNumberRow> error_numbers;
    /// The object holding the error history: the pre-defined error field 1003h (CiA 301
    /// §7.5.2.4, UNSIGNED32 entries) or a vendor array of error codes (DS-BVS 4080h, §6.2.44,
    /// UNSIGNED16 entries, instead of 1003h).
    std::uint16_t error_history_index = 0x1003;
    /// Entries of the error history the manual gives; 0 = not documented.
    std::uint8_t error_history_depth = 0;
    std::span<const ModeLayout> layouts;
    Quirks quirks;
    /// Objects this drive has in addition to / instead of the generic CiA 402 set.
    std::span<const ObjectSpec> object_overrides;
    /// The manual's object tables give a default value for each object (DS-BVS "Default
    /// Value", FIO "Default Value"); false where they do not (AKD2G): then the defaults of
    /// object_overrides are placeholders and a simulator keeps its own.
    bool documents_defaults = false;
    /// Generic CiA 402 objects this drive does not have.
    std::span<const std::uint16_t> absent_objects;
    /// The drive has no 603Fh but keeps its error history in 1003h: sub-index 1 holds the first
    /// four bytes of the last EMCY, the error code in bits 0..15 (CiA 301 §7.5.2.5). The axis
    /// reads it on FAULT so messages name the fault (AKD2G manual §5.2.3).
    bool fault_code_in_1003 = false;
    /// Manufacturer-specific axis objects: offset per axis (AKD2G: 0x100 for 50xxh → 51xxh).
    std::uint16_t manufacturer_axis_offset = 0;
    /// The per-axis list of active faults, sub-indexes 1..axis_fault_slots (AKD2G 5004h
    /// AXIS#.FAULT1..10, axis 2 at 5104h, §5.3.84): where the drive says which axis a fault
    /// belongs to, as its EMCY does not. 0 = the drive has none.
    std::uint16_t axis_fault_list = 0;
    std::uint8_t axis_fault_slots = 0;
    /// 1010h/1011h categories and rules.
    Persistence persistence;
    /// The PDO maps the drive ships with, where its manual gives them (FIO §7.13.11-§7.13.18).
    std::span<const DefaultPdoMap> default_pdo_maps;
    /// Node-ID / bit-rate objects (commissioning over the bus).
    Commissioning commissioning;

    /// Index of a CiA 402 object for axis `axis` (1-based): 6040h → 6840h for AKD2G axis 2.
    [[nodiscard]] std::uint16_t axis_index(std::uint16_t index, unsigned axis) const;
    /// True if 6060h accepts `mode` (standard bit in supported_modes, extra or manufacturer).
    [[nodiscard]] bool supports_mode(std::int8_t mode) const;
    /// The layout for a mode, or nullptr.
    [[nodiscard]] const ModeLayout* layout(cia402::Mode mode) const;
    /// The fault row for an EMCY/603Fh code, or nullptr.
    [[nodiscard]] const FaultRow* fault(std::uint16_t code) const;
    /// The FIO-style error number row, or nullptr.
    [[nodiscard]] const ErrorNumberRow* error_number(std::uint8_t number) const;
    /// The fault row an entry of the axis fault list names: the entry as an EMCY code, else as
    /// the number of an "F"/"W" row (2006 → F2006; the AKD2G manual does not say which of the
    /// two AXIS#.FAULT# holds), else nullptr.
    [[nodiscard]] const FaultRow* axis_list_fault(std::uint16_t entry) const;
    /// "F2006 Bus over voltage", or "" if the code is unknown to the profile.
    [[nodiscard]] std::string fault_text(std::uint16_t code) const;
    [[nodiscard]] bool has_object(std::uint16_t index) const;
    /// The 1010h/1011h categories (at least "all" at sub-index 1).
    [[nodiscard]] std::span<const StoreCategory> store_categories() const;
    /// The category named `name` ("all", "comm", …), or nullptr.
    [[nodiscard]] const StoreCategory* store_category(std::string_view name) const;
    /// The category at 1010h/1011h sub-index `subindex`, or nullptr.
    [[nodiscard]] const StoreCategory* store_category(std::uint8_t subindex) const;
    /// True if a save of category `c` stores object `index`: a member of the category, never
    /// 1010h/1011h themselves, never a PDO map the drive marks "Backup NO" (pdo_maps_volatile).
    [[nodiscard]] bool saves(const StoreCategory& c, std::uint16_t index) const;
    /// Axis count encoded in a product code (AKD2G bits 23..20), else 1.
    [[nodiscard]] unsigned axes_from_product_code(std::uint32_t product_code) const;
};

/// The built-in profiles.
[[nodiscard]] const Profile& akd2g_profile();
[[nodiscard]] const Profile& ds_bvs_profile();
[[nodiscard]] const Profile& fio_profile();
[[nodiscard]] const Profile& generic_profile();
/// A CANopen device that is not a CiA 402 drive (1000h names another device profile, or none):
/// no axes, only the CiA 301 store/restore of all parameters (1010h/1011h sub-index 1). Not in
/// all_profiles(); identify_device() gives it so that messages do not call such a device a drive.
[[nodiscard]] const Profile& canopen_device_profile();
[[nodiscard]] std::span<const Profile* const> all_profiles();

/// A profile by name ("akd2g", "ds-bvs", "fio", "generic"; case-insensitive, "dsbvs" and
/// "kuhnke-fio" accepted), or nullptr.
[[nodiscard]] const Profile* find_profile(std::string_view name);
/// A profile by name; unknown names give the generic profile.
[[nodiscard]] const Profile& profile_by_name(std::string_view name);

/// The profile whose identity matches 1000h and 1018h:1/:2; the generic profile when the
/// device is a CiA 402 drive (1000h bits 0..15 = 402) that no vendor profile claims; nullptr
/// for non-drives.
[[nodiscard]] const Profile* match_identity(std::uint32_t device_type, std::uint32_t vendor_id,
                                            std::uint32_t product_code,
                                            std::string_view device_name = {});

/// The generic CiA 402 object set every profile starts from.
[[nodiscard]] std::span<const ObjectSpec> generic_objects();

/// The EMCY text provider for a profile, to plug into EmcyConsumer::set_text_provider(node, …):
/// AKD2G "F2006 Bus over voltage", DS-BVS "Over voltage", FIO "error number 0x0D: following
/// error …; position monitoring: following error too large". The provider lives as long as
/// the profile (static).
[[nodiscard]] std::shared_ptr<const emcy::IEmcyTextProvider> emcy_text_provider(const Profile& p);

/// The CiA 402 object descriptions of a profile for one axis (generic set minus absent objects,
/// plus overrides), indexes already offset for `axis`.
[[nodiscard]] std::vector<ObjectSpec> device_objects(const Profile& p, unsigned axis);

/// Error behaviour 1029h where the drive has it (`quirks.error_behaviour_1029`; DS-BVS §6.2.12,
/// "CANopen, EtherCAT"): subs 1 communication and 2 application error, 0 PRE-OP (if
/// operational), 1 no state change (default), 2 STOPPED. Nothing for a drive without it. The one
/// description of the object, for the master's dictionary and both simulators.
void add_error_behaviour_object(ObjectDictionary& od, const Profile& p);

/// Adds the identity objects (1000h, 1018h) and every axis's CiA 402 objects with the types,
/// access, PDO flags, defaults and limits from the profile to `od`. `axes` is clamped to
/// 1..max_axes. Existing objects with the same index are replaced.
void build_device_dictionary(ObjectDictionary& od, const Profile& p, unsigned axes = 1);

/// Adds one described object (a VAR, or one sub-index of a RECORD/ARRAY with its sub 0 kept at
/// the highest sub-index) to `od` with the type, access, PDO flag, default and limits of `s`.
void add_object(ObjectDictionary& od, const ObjectSpec& s);

/// The mapping entry value (index << 16 | sub << 8 | bits) of a PDO entry for an axis.
[[nodiscard]] std::uint32_t mapping_value(const Profile& p, const PdoEntry& e, unsigned axis);

} // namespace codrive::drives
