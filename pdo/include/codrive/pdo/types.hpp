// SPDX-License-Identifier: Apache-2.0
// The PDO model: mapping entries, transmission types and the configuration of one PDO.
#pragma once

#include <codrive/core/cob_id.hpp>
#include <codrive/core/object_dictionary.hpp>
#include <codrive/core/time.hpp>

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace codrive::pdo {

using codrive::PdoDir;

/// Object indexes of the PDO parameters (CiA 301 §7.5.2.35–§7.5.2.38): PDO n (1-based) of a
/// direction lives at base + n − 1.
inline constexpr std::uint16_t kRpdoCommBase = 0x1400;
inline constexpr std::uint16_t kRpdoMapBase = 0x1600;
inline constexpr std::uint16_t kTpdoCommBase = 0x1800;
inline constexpr std::uint16_t kTpdoMapBase = 0x1A00;
inline constexpr unsigned kMaxPdoNumber = 512;
/// CiA 301: mapping sub-indexes 01h..40h.
inline constexpr unsigned kMaxMapEntries = 64;
/// A classic CAN frame carries 8 bytes.
inline constexpr unsigned kMaxCanPdoBits = 64;

/// Sub-indexes of the communication parameter record.
namespace comm_sub {
inline constexpr std::uint8_t kCobId = 1;
inline constexpr std::uint8_t kTransmissionType = 2;
inline constexpr std::uint8_t kInhibitTime = 3; ///< TPDO, 100 µs units
inline constexpr std::uint8_t kEventTimer = 5;  ///< ms (RPDO: deadline monitoring)
inline constexpr std::uint8_t kSyncStart = 6;   ///< TPDO SYNC start value
} // namespace comm_sub

[[nodiscard]] constexpr std::uint16_t comm_index(PdoDir dir, unsigned number) {
    return static_cast<std::uint16_t>((dir == PdoDir::Rpdo ? kRpdoCommBase : kTpdoCommBase) +
                                      number - 1);
}
[[nodiscard]] constexpr std::uint16_t map_index(PdoDir dir, unsigned number) {
    return static_cast<std::uint16_t>((dir == PdoDir::Rpdo ? kRpdoMapBase : kTpdoMapBase) + number -
                                      1);
}

/// "RPDO", "TPDO".
[[nodiscard]] std::string_view to_string(PdoDir dir);
/// "RPDO1", "TPDO12".
[[nodiscard]] std::string pdo_name(PdoDir dir, unsigned number);

/// Transmission types (CiA 301 Table 72/73, sub-index 02h).
namespace transmission {
inline constexpr std::uint8_t kSyncAcyclic = 0;    ///< TPDO: on the SYNC after an event
inline constexpr std::uint8_t kSyncMaxEvery = 240; ///< 1..240: every n-th SYNC
inline constexpr std::uint8_t kRtrSync = 252;      ///< TPDO: sampled at SYNC, sent on RTR
inline constexpr std::uint8_t kRtrEvent = 253;     ///< TPDO: sampled and sent on RTR
inline constexpr std::uint8_t kEventManufacturer = 254;
inline constexpr std::uint8_t kEventProfile = 255;
} // namespace transmission

[[nodiscard]] constexpr bool is_synchronous(std::uint8_t t) {
    return t <= transmission::kSyncMaxEvery;
}
[[nodiscard]] constexpr bool is_cyclic_sync(std::uint8_t t) {
    return t >= 1 && t <= transmission::kSyncMaxEvery;
}
[[nodiscard]] constexpr bool is_rtr_only(std::uint8_t t) {
    return t == transmission::kRtrSync || t == transmission::kRtrEvent;
}
[[nodiscard]] constexpr bool is_event_driven(std::uint8_t t) {
    return t >= transmission::kEventManufacturer;
}
[[nodiscard]] constexpr bool is_reserved_type(std::uint8_t t) {
    return t > transmission::kSyncMaxEvery && t < transmission::kRtrSync;
}
/// "1 (every SYNC)", "3 (every 3rd SYNC)", "0 (acyclic synchronous)", "255 (event, profile)".
[[nodiscard]] std::string describe_transmission(std::uint8_t type);

/// One mapping entry (CiA 301 §7.5.2.36): index bits 31..16, sub-index 15..8, length 7..0.
struct MappingEntry {
    std::uint16_t index = 0;
    std::uint8_t subindex = 0;
    std::uint8_t bits = 0;

    [[nodiscard]] constexpr std::uint32_t raw() const {
        return (static_cast<std::uint32_t>(index) << 16) |
               (static_cast<std::uint32_t>(subindex) << 8) | bits;
    }
    [[nodiscard]] static constexpr MappingEntry from_raw(std::uint32_t raw) {
        return {static_cast<std::uint16_t>(raw >> 16), static_cast<std::uint8_t>(raw >> 8),
                static_cast<std::uint8_t>(raw)};
    }
    /// Indexes 0001h..0007h map the DEFTYPEs as dummies (CiA 301 §7.4.7.1).
    [[nodiscard]] constexpr bool is_dummy() const { return index >= 0x0001 && index <= 0x0007; }
    /// Index 0000h with a length: AKD2G padding (not CiA 301).
    [[nodiscard]] constexpr bool is_zero_padding() const { return index == 0; }

    friend constexpr bool operator==(const MappingEntry&, const MappingEntry&) = default;
};
/// "0x6040:00/16".
[[nodiscard]] std::string to_string(const MappingEntry& e);

/// Communication parameters of one PDO (1400h..15FFh / 1800h..19FFh).
struct PdoComm {
    /// CAN identifier (bits 28..0; 11-bit unless `extended`). 0 = the predefined connection set
    /// default for the node (180h/200h + 100h·(n−1) + node, PDOs 1..4 only).
    std::uint32_t can_id = 0;
    bool extended = false;
    bool rtr_allowed = false; ///< TPDO: COB-ID bit 30 clear
    std::uint8_t transmission_type = transmission::kEventProfile;
    std::uint16_t inhibit_time = 0; ///< 100 µs units (TPDO)
    std::uint16_t event_timer = 0;  ///< ms; TPDO: cyclic event, RPDO: deadline monitoring
    std::uint8_t sync_start = 0;    ///< TPDO sub 6; 0 = not used

    [[nodiscard]] Duration inhibit() const { return microseconds(100) * inhibit_time; }
    [[nodiscard]] Duration event_period() const { return milliseconds(event_timer); }
    friend bool operator==(const PdoComm&, const PdoComm&) = default;
};

/// The full configuration of one PDO: the part of 14xx/16xx/18xx/1Axx a master writes.
struct PdoConfig {
    PdoDir dir = PdoDir::Tpdo;
    unsigned number = 1; ///< 1..512
    bool enabled = true; ///< false: COB-ID bit 31 set (or mapping count 0 where it is read-only)
    PdoComm comm;
    std::vector<MappingEntry> mapping;

    /// Sum of the entry lengths.
    [[nodiscard]] unsigned total_bits() const;
    /// Bytes the frame carries: total_bits rounded up.
    [[nodiscard]] unsigned byte_length() const { return (total_bits() + 7) / 8; }
    /// The COB-ID this PDO uses for `node` (the default when comm.can_id is 0).
    [[nodiscard]] std::uint32_t can_id_for(NodeId node) const;
    /// The 32-bit value of sub-index 01h: CAN-ID plus bits 29 (extended), 30 (no RTR) and 31
    /// (invalid) as configured.
    [[nodiscard]] std::uint32_t cob_id_value(NodeId node, bool invalid) const;
    [[nodiscard]] std::string name() const { return pdo_name(dir, number); }

    friend bool operator==(const PdoConfig&, const PdoConfig&) = default;
};

/// Builders for readable test and application code.
[[nodiscard]] PdoConfig rpdo(unsigned number, std::vector<MappingEntry> mapping,
                             std::uint8_t transmission_type = transmission::kEventProfile);
[[nodiscard]] PdoConfig tpdo(unsigned number, std::vector<MappingEntry> mapping,
                             std::uint8_t transmission_type = 1);

/// Splits a COB-ID value: CAN-ID, bit 29, bit 30 and bit 31.
struct CobIdFields {
    std::uint32_t can_id = 0;
    bool extended = false;
    bool no_rtr = false;
    bool invalid = false;
};
[[nodiscard]] constexpr CobIdFields decode_cob_id(std::uint32_t v) {
    const bool ext = (v & cob::kFrameBit) != 0;
    return {v & (ext ? 0x1FFFFFFFU : 0x7FFU), ext, (v & cob::kRtrBit) != 0,
            (v & cob::kInvalidBit) != 0};
}

/// True for identifiers CiA 301 §7.3.5 (Table 41) reserves for other services and forbids
/// for PDOs: 000h, 001h–07Fh, 101h–180h, 581h–5FFh, 601h–67Fh, 6E0h–6FFh, 701h–77Fh, 780h–7FFh.
[[nodiscard]] bool is_restricted_can_id(std::uint32_t can_id);

} // namespace codrive::pdo
