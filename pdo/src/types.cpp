// SPDX-License-Identifier: Apache-2.0
// PDO model helpers: names, COB-ID values and transmission type text.
#include <codrive/pdo/types.hpp>

#include <fmt/format.h>

namespace codrive::pdo {

std::string_view to_string(PdoDir dir) {
    return dir == PdoDir::Rpdo ? "RPDO" : "TPDO";
}

std::string pdo_name(PdoDir dir, unsigned number) {
    return fmt::format("{}{}", to_string(dir), number);
}

std::string describe_transmission(std::uint8_t type) {
    if (type == transmission::kSyncAcyclic) {
        return "0 (acyclic synchronous)";
    }
    if (type == 1) {
        return "1 (every SYNC)";
    }
    if (is_cyclic_sync(type)) {
        const unsigned n = type;
        const char* suffix = (n % 100 >= 11 && n % 100 <= 13) ? "th"
                             : n % 10 == 1                    ? "st"
                             : n % 10 == 2                    ? "nd"
                             : n % 10 == 3                    ? "rd"
                                                              : "th";
        return fmt::format("{} (every {}{} SYNC)", n, n, suffix);
    }
    switch (type) {
    case transmission::kRtrSync:
        return "252 (RTR, sampled at SYNC)";
    case transmission::kRtrEvent:
        return "253 (RTR only)";
    case transmission::kEventManufacturer:
        return "254 (event, manufacturer)";
    case transmission::kEventProfile:
        return "255 (event, profile)";
    default:
        return fmt::format("{} (reserved)", type);
    }
}

std::string to_string(const MappingEntry& e) {
    return fmt::format("0x{:04X}:{:02X}/{}", e.index, e.subindex, e.bits);
}

unsigned PdoConfig::total_bits() const {
    unsigned bits = 0;
    for (const auto& e : mapping) {
        bits += e.bits;
    }
    return bits;
}

std::uint32_t PdoConfig::can_id_for(NodeId node) const {
    if (comm.can_id != 0) {
        return comm.can_id;
    }
    if (number < 1 || number > 4) {
        return 0;
    }
    return dir == PdoDir::Rpdo ? cob::rpdo(number, node) : cob::tpdo(number, node);
}

std::uint32_t PdoConfig::cob_id_value(NodeId node, bool invalid) const {
    std::uint32_t v = can_id_for(node);
    if (comm.extended) {
        v |= cob::kFrameBit;
    }
    // Bit 30 is "no RTR allowed"; CiA 301 defines it for TPDOs, RPDOs keep it clear.
    if (dir == PdoDir::Tpdo && !comm.rtr_allowed) {
        v |= cob::kRtrBit;
    }
    if (invalid) {
        v |= cob::kInvalidBit;
    }
    return v;
}

PdoConfig rpdo(unsigned number, std::vector<MappingEntry> mapping, std::uint8_t transmission_type) {
    PdoConfig c;
    c.dir = PdoDir::Rpdo;
    c.number = number;
    c.comm.transmission_type = transmission_type;
    c.mapping = std::move(mapping);
    return c;
}

PdoConfig tpdo(unsigned number, std::vector<MappingEntry> mapping, std::uint8_t transmission_type) {
    PdoConfig c;
    c.dir = PdoDir::Tpdo;
    c.number = number;
    c.comm.transmission_type = transmission_type;
    c.mapping = std::move(mapping);
    return c;
}

bool is_restricted_can_id(std::uint32_t id) {
    return id <= 0x07F || (id >= 0x101 && id <= 0x180) || (id >= 0x581 && id <= 0x5FF) ||
           (id >= 0x601 && id <= 0x67F) || (id >= 0x6E0 && id <= 0x6FF) ||
           (id >= 0x701 && id <= 0x7FF);
}

} // namespace codrive::pdo
