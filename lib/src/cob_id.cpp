// SPDX-License-Identifier: Apache-2.0
// Classification of 11-bit identifiers by the CiA 301 predefined connection set (§7.3.3).
#include <codrive/core/cob_id.hpp>

namespace codrive {

unsigned CobInfo::pdo_number() const {
    switch (type) {
    case CobType::Tpdo1:
    case CobType::Rpdo1:
        return 1;
    case CobType::Tpdo2:
    case CobType::Rpdo2:
        return 2;
    case CobType::Tpdo3:
    case CobType::Rpdo3:
        return 3;
    case CobType::Tpdo4:
    case CobType::Rpdo4:
        return 4;
    default:
        return 0;
    }
}

bool CobInfo::is_tpdo() const {
    return type == CobType::Tpdo1 || type == CobType::Tpdo2 || type == CobType::Tpdo3 ||
           type == CobType::Tpdo4;
}

bool CobInfo::is_rpdo() const {
    return type == CobType::Rpdo1 || type == CobType::Rpdo2 || type == CobType::Rpdo3 ||
           type == CobType::Rpdo4;
}

CobInfo classify_cob_id(std::uint32_t id) {
    if (id > 0x7FF) {
        return {};
    }
    if (id == cob::kNmt) {
        return {CobType::Nmt, 0};
    }
    if (id == cob::kSync) {
        return {CobType::Sync, 0};
    }
    if (id == cob::kTime) {
        return {CobType::Time, 0};
    }
    if (id == cob::kLssSlave) {
        return {CobType::LssSlave, 0};
    }
    if (id == cob::kLssMaster) {
        return {CobType::LssMaster, 0};
    }
    const auto node = static_cast<NodeId>(id & 0x7F);
    if (node == 0) {
        return {};
    }
    static constexpr CobType kByFunction[16] = {
        CobType::Unknown, CobType::Emcy,    CobType::Unknown,   CobType::Tpdo1,
        CobType::Rpdo1,   CobType::Tpdo2,   CobType::Rpdo2,     CobType::Tpdo3,
        CobType::Rpdo3,   CobType::Tpdo4,   CobType::Rpdo4,     CobType::SdoTx,
        CobType::SdoRx,   CobType::Unknown, CobType::Heartbeat, CobType::Unknown};
    const CobType type = kByFunction[(id >> 7) & 0x0F];
    if (type == CobType::Unknown) {
        return {};
    }
    return {type, node};
}

std::string_view to_string(CobType t) {
    switch (t) {
    case CobType::Nmt:
        return "NMT";
    case CobType::Sync:
        return "SYNC";
    case CobType::Emcy:
        return "EMCY";
    case CobType::Time:
        return "TIME";
    case CobType::Tpdo1:
        return "TPDO1";
    case CobType::Rpdo1:
        return "RPDO1";
    case CobType::Tpdo2:
        return "TPDO2";
    case CobType::Rpdo2:
        return "RPDO2";
    case CobType::Tpdo3:
        return "TPDO3";
    case CobType::Rpdo3:
        return "RPDO3";
    case CobType::Tpdo4:
        return "TPDO4";
    case CobType::Rpdo4:
        return "RPDO4";
    case CobType::SdoTx:
        return "SDO-tx";
    case CobType::SdoRx:
        return "SDO-rx";
    case CobType::Heartbeat:
        return "HB";
    case CobType::LssSlave:
        return "LSS-slave";
    case CobType::LssMaster:
        return "LSS-master";
    case CobType::Unknown:
        break;
    }
    return "?";
}

} // namespace codrive
