// SPDX-License-Identifier: Apache-2.0
// An EtherCAT slave information file (ESI XML, ETG.2000) as the master reads it: identities,
// object dictionary, PDOs, sync managers and mailbox protocols of each device in the file.
#pragma once

#include <codrive/core/data_type.hpp>

#include <tl/expected.hpp>

#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace codrive::ethercat {

/// One sub-index of an ESI object (ETG.2000 §5.4.3: Object, its DataType's SubItem, its Info).
struct EsiEntry {
    std::uint8_t subindex = 0;
    std::string name;
    std::string type_name;                   ///< as written ("UDINT", "STRING(17)", "DT1018")
    std::optional<DataType> type;            ///< the CiA 301 type of a base type; none for others
    std::uint32_t bit_size = 0;              ///< BitSize
    std::optional<std::string> default_data; ///< Info/DefaultData, hex bytes little endian
    Access access = Access::Ro;              ///< Flags/Access (ro, rw, wo)
    bool rx_mappable = false;                ///< Flags/PdoMapping has R (master → slave)
    bool tx_mappable = false;                ///< Flags/PdoMapping has T (slave → master)
    int line = 0;                            ///< where the object or sub-item is described
};

/// One object of the dictionary: a variable (one entry, sub-index 0) or a record/array.
struct EsiObject {
    std::uint16_t index = 0;
    std::string name;
    std::string type_name;
    std::uint32_t bit_size = 0;
    std::vector<EsiEntry> entries; ///< sub-index order as the file gives them
    int line = 0;
    /// The entry of a sub-index; nullptr when the object has none.
    [[nodiscard]] const EsiEntry* entry(std::uint8_t subindex) const;
};

/// One entry of a PDO (ETG.2000 §5.4.4 RxPdo/TxPdo Entry). Index 0 is a gap of BitLen bits.
struct EsiPdoEntry {
    std::uint16_t index = 0;
    std::uint8_t subindex = 0;
    std::uint8_t bit_len = 0;
    std::string name;
    std::string data_type;
};

/// One RxPdo (outputs) or TxPdo (inputs).
struct EsiPdo {
    bool rx = true;          ///< RxPdo (master → slave); false: TxPdo
    std::uint16_t index = 0; ///< 1600h.., 1A00h..
    std::string name;
    bool fixed = false;             ///< Fixed="1": the mapping cannot be changed
    std::optional<std::uint8_t> sm; ///< Sm="n": assigned to SM n by default (ETG.2000 §5.4.4)
    std::vector<EsiPdoEntry> entries;
    int line = 0;
};

/// One sync manager of the device (ETG.2000 §5.4.2 Sm).
struct EsiSyncManager {
    std::string kind; ///< MBoxOut, MBoxIn, Outputs, Inputs
    std::uint16_t start_address = 0;
    std::uint16_t default_size = 0; ///< 0 when the file gives none (process data SMs)
    std::uint8_t control_byte = 0;
    bool enable = false;
};

/// One Devices/Device.
struct EsiDevice {
    std::string type;               ///< Type text
    std::string name;               ///< Name
    std::uint32_t product_code = 0; ///< Type@ProductCode
    std::uint32_t revision = 0;     ///< Type@RevisionNo
    std::vector<EsiSyncManager> sync_managers;
    std::vector<EsiPdo> rx_pdos;
    std::vector<EsiPdo> tx_pdos;
    std::vector<EsiObject> objects; ///< Profile/Dictionary/Objects, index order as written
    bool coe = false;               ///< Mailbox/CoE present
    bool sdo_info = false;          ///< CoE@SdoInfo
    bool pdo_assign = false;        ///< CoE@PdoAssign (1C12h/1C13h writable)
    bool pdo_config = false;        ///< CoE@PdoConfig (16xxh/1Axxh writable)
    int line = 0;
    /// The object at `index`; nullptr when the dictionary has none.
    [[nodiscard]] const EsiObject* object(std::uint16_t index) const;
    /// The entry at index:subindex; nullptr when the dictionary has none.
    [[nodiscard]] const EsiEntry* entry(std::uint16_t index, std::uint8_t subindex) const;
    /// "product 0x0002BA67 revision 0x00000000 (Kuhnke FIO Drive Control)"
    [[nodiscard]] std::string describe() const;
};

/// A whole ESI file.
struct EsiFile {
    std::string file;            ///< as given to load_esi() / parse_esi(), for messages
    std::uint32_t vendor_id = 0; ///< Vendor/Id
    std::string vendor_name;     ///< Vendor/Name
    std::vector<EsiDevice> devices;
    /// The device describing a slave with this identity (SII words 8..0Dh, ETG.2010 Table 2):
    /// the vendor and the product code equal, the device with the same revision if the file has
    /// one, else the first with that product code (firmware revisions move on; the file's
    /// revision is the one it was written for); nullptr when vendor or product differ.
    [[nodiscard]] const EsiDevice* match(std::uint32_t vendor, std::uint32_t product,
                                         std::uint32_t revision) const;
    /// Why no device matches: names the slave's identity, the file and what the file has.
    [[nodiscard]] std::string mismatch(std::uint32_t vendor, std::uint32_t product,
                                       std::uint32_t revision) const;
};

/// The CiA 301 type of an ESI base type name (ETG.2000 §5.4.3 Table 42: BOOL, SINT, UINT,
/// UDINT, REAL, STRING(n), ...); none for a name that is not a base type.
[[nodiscard]] std::optional<DataType> esi_base_type(std::string_view name);
/// The ESI name of a fixed-size CiA 301 type ("UDINT" for UNSIGNED32); empty for strings,
/// domains and types ETG.2000 has no base type for. esi_base_type() reads it back.
[[nodiscard]] std::string_view esi_base_type_name(DataType type);

/// Reads ESI XML text. Errors are one sentence "file:line: ..." naming what is wrong (not XML,
/// no EtherCATInfo/Vendor/Id, a device without ProductCode, an object without Index, a number
/// that is not #xHEX or decimal, ...).
[[nodiscard]] tl::expected<EsiFile, std::string> parse_esi(std::string_view text,
                                                           const std::string& file);
/// Reads the ESI file at `path` (errors as parse_esi(), or "path: cannot read: ...").
[[nodiscard]] tl::expected<EsiFile, std::string> load_esi(const std::string& path);

} // namespace codrive::ethercat
