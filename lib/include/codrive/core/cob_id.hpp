// SPDX-License-Identifier: Apache-2.0
// CiA 301 predefined connection set: function codes, COB-IDs and node ids.
#pragma once

#include <cstdint>
#include <optional>
#include <string_view>

namespace codrive {

using NodeId = std::uint8_t; ///< 1..127; 0 means "all nodes" in NMT commands

inline constexpr NodeId kMaxNodeId = 127;
[[nodiscard]] constexpr bool valid_node_id(unsigned id) {
    return id >= 1 && id <= kMaxNodeId;
}

/// Communication objects of the CiA 301 predefined connection set.
enum class CobType : std::uint8_t {
    Nmt,       ///< 000h
    Sync,      ///< 080h
    Emcy,      ///< 081h..0FFh
    Time,      ///< 100h
    Tpdo1,     ///< 180h + node
    Rpdo1,     ///< 200h + node
    Tpdo2,     ///< 280h + node
    Rpdo2,     ///< 300h + node
    Tpdo3,     ///< 380h + node
    Rpdo3,     ///< 400h + node
    Tpdo4,     ///< 480h + node
    Rpdo4,     ///< 500h + node
    SdoTx,     ///< 580h + node (server → client response)
    SdoRx,     ///< 600h + node (client → server request)
    Heartbeat, ///< 700h + node (boot-up, heartbeat, node guarding reply)
    LssSlave,  ///< 7E4h
    LssMaster, ///< 7E5h
    Unknown,
};

namespace cob {
inline constexpr std::uint32_t kNmt = 0x000;
inline constexpr std::uint32_t kSync = 0x080;
inline constexpr std::uint32_t kEmcy = 0x080;
inline constexpr std::uint32_t kTime = 0x100;
inline constexpr std::uint32_t kTpdo1 = 0x180;
inline constexpr std::uint32_t kRpdo1 = 0x200;
inline constexpr std::uint32_t kSdoTx = 0x580;
inline constexpr std::uint32_t kSdoRx = 0x600;
inline constexpr std::uint32_t kHeartbeat = 0x700;
inline constexpr std::uint32_t kLssSlave = 0x7E4;
inline constexpr std::uint32_t kLssMaster = 0x7E5;

/// COB-ID object bits (CiA 301 §7.5.2.x): bit 31 invalid, bit 30 RTR not allowed / producer,
/// bit 29 29-bit frame.
inline constexpr std::uint32_t kInvalidBit = 1U << 31;
inline constexpr std::uint32_t kRtrBit = 1U << 30;
inline constexpr std::uint32_t kFrameBit = 1U << 29;

constexpr std::uint32_t tpdo(unsigned n, NodeId node) {
    return 0x180U + 0x100U * (n - 1) + node;
}
constexpr std::uint32_t rpdo(unsigned n, NodeId node) {
    return 0x200U + 0x100U * (n - 1) + node;
}
constexpr std::uint32_t sdo_tx(NodeId node) {
    return kSdoTx + node;
}
constexpr std::uint32_t sdo_rx(NodeId node) {
    return kSdoRx + node;
}
constexpr std::uint32_t emcy(NodeId node) {
    return kEmcy + node;
}
constexpr std::uint32_t heartbeat(NodeId node) {
    return kHeartbeat + node;
}
} // namespace cob

/// What an 11-bit identifier means in the predefined connection set.
struct CobInfo {
    CobType type = CobType::Unknown;
    NodeId node = 0; ///< 0 for broadcast objects (NMT, SYNC, TIME, LSS)
    /// PDO number 1..4 for PDO types, 0 otherwise.
    [[nodiscard]] unsigned pdo_number() const;
    [[nodiscard]] bool is_tpdo() const;
    [[nodiscard]] bool is_rpdo() const;
};

/// Classifies an 11-bit COB-ID by the predefined connection set.
[[nodiscard]] CobInfo classify_cob_id(std::uint32_t id);

/// Short name: "NMT", "SYNC", "EMCY", "TIME", "TPDO1", ..., "SDO-tx", "SDO-rx", "HB", "LSS".
[[nodiscard]] std::string_view to_string(CobType t);

} // namespace codrive
