// SPDX-License-Identifier: Apache-2.0
// PDO parameter objects for simulated and test devices.
#include <codrive/pdo/od_objects.hpp>

#include <fmt/format.h>

namespace codrive::pdo {
namespace {

template <typename T>
Value value_of(DataType type, T v) {
    std::vector<std::uint8_t> b(sizeof(T));
    put_le<T>(b.data(), v);
    return Value(type, std::move(b));
}

const PdoConfig* preset_for(const PdoObjectDefaults& d, PdoDir dir, unsigned n) {
    for (const auto& p : d.preset) {
        if (p.dir == dir && p.number == n) {
            return &p;
        }
    }
    return nullptr;
}

void add_pdo(ObjectDictionary& od, NodeId node, const PdoQuirks& q, const PdoObjectDefaults& d,
             PdoDir dir, unsigned n) {
    const bool tpdo = dir == PdoDir::Tpdo;
    const PdoConfig* preset = preset_for(d, dir, n);
    PdoConfig cfg;
    cfg.dir = dir;
    cfg.number = n;
    cfg.comm.transmission_type = tpdo ? d.tpdo_transmission_type : d.rpdo_transmission_type;
    cfg.comm.rtr_allowed = q.rtr_supported;
    if (preset != nullptr) {
        cfg = *preset;
    }
    const std::uint16_t comm = comm_index(dir, n);
    const std::uint16_t map = map_index(dir, n);
    const std::string name = fmt::format("{} communication parameter", pdo_name(dir, n));
    const std::uint32_t cob =
        cfg.can_id_for(node) == 0 ? cob::kInvalidBit : cfg.cob_id_value(node, !cfg.enabled);
    std::uint8_t highest = 2;
    if (tpdo && q.has_inhibit_and_timer) {
        highest = q.has_sync_start ? 6 : 5;
    } else if (!tpdo && q.rpdo_has_event_timer) {
        highest = 5;
    }
    od.add_sub(comm,
               SubObject::make(0, "Highest sub-index supported", DataType::Unsigned8, Access::Const,
                               value_of<std::uint8_t>(DataType::Unsigned8, highest)),
               name);
    od.add_sub(comm, SubObject::make(1, "COB-ID", DataType::Unsigned32,
                                     q.cob_id_read_only ? Access::Ro : Access::Rw,
                                     value_of<std::uint32_t>(DataType::Unsigned32, cob)));
    od.add_sub(comm, SubObject::make(
                         2, "Transmission type", DataType::Unsigned8, Access::Rw,
                         value_of<std::uint8_t>(DataType::Unsigned8, cfg.comm.transmission_type)));
    if (highest >= 5) {
        if (tpdo) {
            od.add_sub(comm, SubObject::make(3, "Inhibit time", DataType::Unsigned16, Access::Rw,
                                             value_of<std::uint16_t>(DataType::Unsigned16,
                                                                     cfg.comm.inhibit_time)));
            od.add_sub(comm, SubObject::make(4, "Reserved", DataType::Unsigned8, Access::Rw,
                                             value_of<std::uint8_t>(DataType::Unsigned8, 0)));
        }
        od.add_sub(comm, SubObject::make(
                             5, "Event timer", DataType::Unsigned16, Access::Rw,
                             value_of<std::uint16_t>(DataType::Unsigned16, cfg.comm.event_timer)));
    }
    if (highest >= 6) {
        od.add_sub(comm, SubObject::make(
                             6, "SYNC start value", DataType::Unsigned8, Access::Rw,
                             value_of<std::uint8_t>(DataType::Unsigned8, cfg.comm.sync_start)));
    }
    const std::string map_name = fmt::format("{} mapping parameter", pdo_name(dir, n));
    od.add_sub(
        map,
        SubObject::make(0, "Number of mapped objects", DataType::Unsigned8, Access::Rw,
                        value_of<std::uint8_t>(DataType::Unsigned8,
                                               static_cast<std::uint8_t>(cfg.mapping.size()))),
        map_name);
    const unsigned entries = std::min(q.max_entries, kMaxMapEntries);
    for (unsigned i = 1; i <= entries; ++i) {
        const std::uint32_t raw = i <= cfg.mapping.size() ? cfg.mapping[i - 1].raw() : 0U;
        od.add_sub(map,
                   SubObject::make(static_cast<std::uint8_t>(i), fmt::format("Mapping entry {}", i),
                                   DataType::Unsigned32, Access::Rw,
                                   value_of<std::uint32_t>(DataType::Unsigned32, raw)));
    }
}

} // namespace

void add_pdo_objects(ObjectDictionary& od, NodeId node, const PdoQuirks& quirks,
                     const PdoObjectDefaults& defaults) {
    for (unsigned n = 1; n <= quirks.rpdo_count; ++n) {
        add_pdo(od, node, quirks, defaults, PdoDir::Rpdo, n);
    }
    for (unsigned n = 1; n <= quirks.tpdo_count; ++n) {
        add_pdo(od, node, quirks, defaults, PdoDir::Tpdo, n);
    }
}

} // namespace codrive::pdo
