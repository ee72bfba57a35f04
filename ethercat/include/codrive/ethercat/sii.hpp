// SPDX-License-Identifier: Apache-2.0
// The slave information interface (SII) EEPROM (ETG.2010): fixed header words and categories.
#pragma once

#include <codrive/core/error.hpp>

#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <vector>

namespace codrive::ethercat {

/// Word addresses of the SII header (ETG.2010 Table 2).
namespace sii_addr {
inline constexpr std::uint16_t kConfiguredAlias = 0x0004;
inline constexpr std::uint16_t kChecksum = 0x0007;
inline constexpr std::uint16_t kVendorId = 0x0008;
inline constexpr std::uint16_t kProductCode = 0x000A;
inline constexpr std::uint16_t kRevision = 0x000C;
inline constexpr std::uint16_t kSerial = 0x000E;
inline constexpr std::uint16_t kStdRxMailboxOffset = 0x0018; ///< master → slave (SM0)
inline constexpr std::uint16_t kStdRxMailboxSize = 0x0019;
inline constexpr std::uint16_t kStdTxMailboxOffset = 0x001A; ///< slave → master (SM1)
inline constexpr std::uint16_t kStdTxMailboxSize = 0x001B;
inline constexpr std::uint16_t kMailboxProtocol = 0x001C;
inline constexpr std::uint16_t kSize = 0x003E;
inline constexpr std::uint16_t kVersion = 0x003F;
inline constexpr std::uint16_t kFirstCategory = 0x0040;
} // namespace sii_addr

/// Category types (ETG.2010 Table 3).
namespace sii_cat {
inline constexpr std::uint16_t kStrings = 10;
inline constexpr std::uint16_t kGeneral = 30;
inline constexpr std::uint16_t kFmmu = 40;
inline constexpr std::uint16_t kSyncManager = 41;
inline constexpr std::uint16_t kTxPdo = 50;
inline constexpr std::uint16_t kRxPdo = 51;
inline constexpr std::uint16_t kDc = 60;
inline constexpr std::uint16_t kEnd = 0xFFFF;
} // namespace sii_cat

/// Mailbox protocol bits (SII word 0x1C).
namespace mbx_proto {
inline constexpr std::uint16_t kAoe = 0x01;
inline constexpr std::uint16_t kEoe = 0x02;
inline constexpr std::uint16_t kCoe = 0x04;
inline constexpr std::uint16_t kFoe = 0x08;
inline constexpr std::uint16_t kSoe = 0x10;
inline constexpr std::uint16_t kVoe = 0x20;
} // namespace mbx_proto

/// Sync manager types in the SyncM category.
enum class SmType : std::uint8_t {
    Unused = 0,
    MailboxOut = 1, ///< master → slave
    MailboxIn = 2,  ///< slave → master
    Outputs = 3,    ///< process data master → slave
    Inputs = 4,     ///< process data slave → master
};

/// A sync manager default from the SyncM category (8 bytes each).
struct SiiSyncManager {
    std::uint16_t start = 0;
    std::uint16_t length = 0;
    std::uint8_t control = 0;
    std::uint8_t enable = 0;
    SmType type = SmType::Unused;
};

/// What the master needs from the EEPROM.
struct SiiInfo {
    std::uint16_t alias = 0;
    std::uint32_t vendor_id = 0;
    std::uint32_t product_code = 0;
    std::uint32_t revision = 0;
    std::uint32_t serial = 0;
    std::uint16_t rx_mailbox_offset = 0; ///< SM0 start
    std::uint16_t rx_mailbox_size = 0;
    std::uint16_t tx_mailbox_offset = 0; ///< SM1 start
    std::uint16_t tx_mailbox_size = 0;
    std::uint16_t mailbox_protocols = 0;
    std::string name;                 ///< device name from the General category
    std::vector<std::string> strings; ///< the Strings category (index 1 = strings[0])
    std::vector<SiiSyncManager> sync_managers;
    std::vector<std::uint8_t> fmmu_usage; ///< FMMU category: 1 outputs, 2 inputs, 3 mailbox
    bool checksum_ok = true;              ///< CRC of the ESC configuration area (word 7)

    [[nodiscard]] bool has_mailbox() const { return rx_mailbox_size != 0 && tx_mailbox_size != 0; }
    [[nodiscard]] bool has_coe() const { return (mailbox_protocols & mbx_proto::kCoe) != 0; }
    [[nodiscard]] bool has_foe() const { return (mailbox_protocols & mbx_proto::kFoe) != 0; }
};

/// CRC-8 (polynomial x^8+x^2+x+1, initial 0xFF) over bytes 0..13 of the EEPROM, stored in the
/// low byte of word 7 (ETG.2010 §2.1).
[[nodiscard]] std::uint8_t sii_checksum(std::span<const std::uint8_t> first_14_bytes);

/// Parses an EEPROM image (little-endian words from address 0). Errors: SiiError if the image
/// is shorter than the header or a category runs past the end.
[[nodiscard]] Result<SiiInfo> parse_sii(std::span<const std::uint8_t> eeprom);

/// Size in bytes the categories occupy from `kFirstCategory`, or nullopt if the End marker is
/// not inside `eeprom` (the master reads categories incrementally with this).
[[nodiscard]] std::optional<std::size_t> sii_categories_end(std::span<const std::uint8_t> eeprom);

/// Builds an EEPROM image for a simulated slave: header, Strings (name first), General, FMMU,
/// SyncM categories, End.
[[nodiscard]] std::vector<std::uint8_t> build_sii(const SiiInfo& info);

} // namespace codrive::ethercat
