// SPDX-License-Identifier: Apache-2.0
// Built-in CiA 301 / CiA 402 object names and types, and EDS-backed lookup.
#include <codrive/dump/object_catalog.hpp>

#include <codrive/dump/text_append.hpp>

#include <algorithm>
#include <iterator>

namespace codrive::dump {
namespace {

using DT = DataType;
constexpr std::uint16_t kAny = 0x100;

// CiA 301 §7.5 (communication profile area) and CiA 402-2 §6-8 (drive profile objects).
constexpr BuiltinObject kBuiltin[] = {
    {0x1000, 0x1000, 0, "Device type", "", DT::Unsigned32, true},
    {0x1001, 0x1001, 0, "Error register", "", DT::Unsigned8, true},
    {0x1002, 0x1002, 0, "Manufacturer status register", "", DT::Unsigned32, true},
    {0x1003, 0x1003, 0, "Pre-defined error field", "Number of errors", DT::Unsigned8, false},
    {0x1003, 0x1003, kAny, "Pre-defined error field", "Standard error field", DT::Unsigned32, true},
    {0x1005, 0x1005, 0, "COB-ID SYNC", "", DT::Unsigned32, true},
    {0x1006, 0x1006, 0, "Communication cycle period", "", DT::Unsigned32, false},
    {0x1007, 0x1007, 0, "Synchronous window length", "", DT::Unsigned32, false},
    {0x1008, 0x1008, 0, "Manufacturer device name", "", DT::VisibleString, false},
    {0x1009, 0x1009, 0, "Manufacturer hardware version", "", DT::VisibleString, false},
    {0x100A, 0x100A, 0, "Manufacturer software version", "", DT::VisibleString, false},
    {0x100C, 0x100C, 0, "Guard time", "", DT::Unsigned16, false},
    {0x100D, 0x100D, 0, "Life time factor", "", DT::Unsigned8, false},
    {0x1010, 0x1010, 0, "Store parameters", "Highest sub-index supported", DT::Unsigned8, false},
    {0x1010, 0x1010, kAny, "Store parameters", "Save parameters", DT::Unsigned32, true},
    {0x1011, 0x1011, 0, "Restore default parameters", "Highest sub-index supported", DT::Unsigned8,
     false},
    {0x1011, 0x1011, kAny, "Restore default parameters", "Restore parameters", DT::Unsigned32,
     true},
    {0x1012, 0x1012, 0, "COB-ID time stamp", "", DT::Unsigned32, true},
    {0x1013, 0x1013, 0, "High resolution time stamp", "", DT::Unsigned32, false},
    {0x1014, 0x1014, 0, "COB-ID EMCY", "", DT::Unsigned32, true},
    {0x1015, 0x1015, 0, "Inhibit time EMCY", "", DT::Unsigned16, false},
    {0x1016, 0x1016, 0, "Consumer heartbeat time", "Highest sub-index supported", DT::Unsigned8,
     false},
    {0x1016, 0x1016, kAny, "Consumer heartbeat time", "Consumer heartbeat time", DT::Unsigned32,
     true},
    {0x1017, 0x1017, 0, "Producer heartbeat time", "", DT::Unsigned16, false},
    {0x1018, 0x1018, 0, "Identity object", "Highest sub-index supported", DT::Unsigned8, false},
    {0x1018, 0x1018, 1, "Identity object", "Vendor-ID", DT::Unsigned32, true},
    {0x1018, 0x1018, 2, "Identity object", "Product code", DT::Unsigned32, true},
    {0x1018, 0x1018, 3, "Identity object", "Revision number", DT::Unsigned32, true},
    {0x1018, 0x1018, 4, "Identity object", "Serial number", DT::Unsigned32, true},
    {0x1019, 0x1019, 0, "Synchronous counter overflow value", "", DT::Unsigned8, false},
    {0x1029, 0x1029, 0, "Error behavior", "Highest sub-index supported", DT::Unsigned8, false},
    {0x1029, 0x1029, kAny, "Error behavior", "Error class", DT::Unsigned8, false},
    {0x1200, 0x127F, 0, "SDO server parameter", "Highest sub-index supported", DT::Unsigned8,
     false},
    {0x1200, 0x127F, 1, "SDO server parameter", "COB-ID client to server", DT::Unsigned32, true},
    {0x1200, 0x127F, 2, "SDO server parameter", "COB-ID server to client", DT::Unsigned32, true},
    {0x1200, 0x127F, 3, "SDO server parameter", "Node-ID of the SDO client", DT::Unsigned8, false},
    {0x1280, 0x12FF, 0, "SDO client parameter", "Highest sub-index supported", DT::Unsigned8,
     false},
    {0x1280, 0x12FF, 1, "SDO client parameter", "COB-ID client to server", DT::Unsigned32, true},
    {0x1280, 0x12FF, 2, "SDO client parameter", "COB-ID server to client", DT::Unsigned32, true},
    {0x1280, 0x12FF, 3, "SDO client parameter", "Node-ID of the SDO server", DT::Unsigned8, false},
    {0x1400, 0x15FF, 0, "RPDO communication parameter", "Highest sub-index supported",
     DT::Unsigned8, false},
    {0x1400, 0x15FF, 1, "RPDO communication parameter", "COB-ID used by RPDO", DT::Unsigned32,
     true},
    {0x1400, 0x15FF, 2, "RPDO communication parameter", "Transmission type", DT::Unsigned8, false},
    {0x1400, 0x15FF, 3, "RPDO communication parameter", "Inhibit time", DT::Unsigned16, false},
    {0x1400, 0x15FF, 5, "RPDO communication parameter", "Event timer", DT::Unsigned16, false},
    {0x1400, 0x15FF, 6, "RPDO communication parameter", "SYNC start value", DT::Unsigned8, false},
    {0x1600, 0x17FF, 0, "RPDO mapping parameter", "Number of mapped objects", DT::Unsigned8, false},
    {0x1600, 0x17FF, kAny, "RPDO mapping parameter", "Mapped object", DT::Unsigned32, true},
    {0x1800, 0x19FF, 0, "TPDO communication parameter", "Highest sub-index supported",
     DT::Unsigned8, false},
    {0x1800, 0x19FF, 1, "TPDO communication parameter", "COB-ID used by TPDO", DT::Unsigned32,
     true},
    {0x1800, 0x19FF, 2, "TPDO communication parameter", "Transmission type", DT::Unsigned8, false},
    {0x1800, 0x19FF, 3, "TPDO communication parameter", "Inhibit time", DT::Unsigned16, false},
    {0x1800, 0x19FF, 5, "TPDO communication parameter", "Event timer", DT::Unsigned16, false},
    {0x1800, 0x19FF, 6, "TPDO communication parameter", "SYNC start value", DT::Unsigned8, false},
    {0x1A00, 0x1BFF, 0, "TPDO mapping parameter", "Number of mapped objects", DT::Unsigned8, false},
    {0x1A00, 0x1BFF, kAny, "TPDO mapping parameter", "Mapped object", DT::Unsigned32, true},
    {0x1F80, 0x1F80, 0, "NMT startup", "", DT::Unsigned32, true},
    {0x603F, 0x603F, 0, "Error code", "", DT::Unsigned16, true},
    {0x6040, 0x6040, 0, "Controlword", "", DT::Unsigned16, true},
    {0x6041, 0x6041, 0, "Statusword", "", DT::Unsigned16, true},
    {0x605A, 0x605A, 0, "Quick stop option code", "", DT::Integer16, false},
    {0x605B, 0x605B, 0, "Shutdown option code", "", DT::Integer16, false},
    {0x605C, 0x605C, 0, "Disable operation option code", "", DT::Integer16, false},
    {0x605D, 0x605D, 0, "Halt option code", "", DT::Integer16, false},
    {0x605E, 0x605E, 0, "Fault reaction option code", "", DT::Integer16, false},
    {0x6060, 0x6060, 0, "Modes of operation", "", DT::Integer8, false},
    {0x6061, 0x6061, 0, "Modes of operation display", "", DT::Integer8, false},
    {0x6062, 0x6062, 0, "Position demand value", "", DT::Integer32, false},
    {0x6063, 0x6063, 0, "Position actual internal value", "", DT::Integer32, false},
    {0x6064, 0x6064, 0, "Position actual value", "", DT::Integer32, false},
    {0x6065, 0x6065, 0, "Following error window", "", DT::Unsigned32, false},
    {0x6066, 0x6066, 0, "Following error time out", "", DT::Unsigned16, false},
    {0x6067, 0x6067, 0, "Position window", "", DT::Unsigned32, false},
    {0x6068, 0x6068, 0, "Position window time", "", DT::Unsigned16, false},
    {0x606B, 0x606B, 0, "Velocity demand value", "", DT::Integer32, false},
    {0x606C, 0x606C, 0, "Velocity actual value", "", DT::Integer32, false},
    {0x6071, 0x6071, 0, "Target torque", "", DT::Integer16, false},
    {0x6072, 0x6072, 0, "Max torque", "", DT::Unsigned16, false},
    {0x6073, 0x6073, 0, "Max current", "", DT::Unsigned16, false},
    {0x6074, 0x6074, 0, "Torque demand", "", DT::Integer16, false},
    {0x6077, 0x6077, 0, "Torque actual value", "", DT::Integer16, false},
    {0x6078, 0x6078, 0, "Current actual value", "", DT::Integer16, false},
    {0x607A, 0x607A, 0, "Target position", "", DT::Integer32, false},
    {0x607C, 0x607C, 0, "Home offset", "", DT::Integer32, false},
    {0x607D, 0x607D, 0, "Software position limit", "Highest sub-index supported", DT::Unsigned8,
     false},
    {0x607D, 0x607D, 1, "Software position limit", "Min position limit", DT::Integer32, false},
    {0x607D, 0x607D, 2, "Software position limit", "Max position limit", DT::Integer32, false},
    {0x607E, 0x607E, 0, "Polarity", "", DT::Unsigned8, true},
    {0x607F, 0x607F, 0, "Max profile velocity", "", DT::Unsigned32, false},
    {0x6080, 0x6080, 0, "Max motor speed", "", DT::Unsigned32, false},
    {0x6081, 0x6081, 0, "Profile velocity", "", DT::Unsigned32, false},
    {0x6083, 0x6083, 0, "Profile acceleration", "", DT::Unsigned32, false},
    {0x6084, 0x6084, 0, "Profile deceleration", "", DT::Unsigned32, false},
    {0x6085, 0x6085, 0, "Quick stop deceleration", "", DT::Unsigned32, false},
    {0x6086, 0x6086, 0, "Motion profile type", "", DT::Integer16, false},
    {0x6087, 0x6087, 0, "Torque slope", "", DT::Unsigned32, false},
    {0x608F, 0x608F, 0, "Position encoder resolution", "Highest sub-index supported", DT::Unsigned8,
     false},
    {0x608F, 0x608F, 1, "Position encoder resolution", "Encoder increments", DT::Unsigned32, false},
    {0x608F, 0x608F, 2, "Position encoder resolution", "Motor revolutions", DT::Unsigned32, false},
    {0x6091, 0x6091, 0, "Gear ratio", "Highest sub-index supported", DT::Unsigned8, false},
    {0x6091, 0x6091, 1, "Gear ratio", "Motor revolutions", DT::Unsigned32, false},
    {0x6091, 0x6091, 2, "Gear ratio", "Shaft revolutions", DT::Unsigned32, false},
    {0x6092, 0x6092, 0, "Feed constant", "Highest sub-index supported", DT::Unsigned8, false},
    {0x6092, 0x6092, 1, "Feed constant", "Feed", DT::Unsigned32, false},
    {0x6092, 0x6092, 2, "Feed constant", "Shaft revolutions", DT::Unsigned32, false},
    {0x6098, 0x6098, 0, "Homing method", "", DT::Integer8, false},
    {0x6099, 0x6099, 0, "Homing speeds", "Highest sub-index supported", DT::Unsigned8, false},
    {0x6099, 0x6099, 1, "Homing speeds", "Speed during search for switch", DT::Unsigned32, false},
    {0x6099, 0x6099, 2, "Homing speeds", "Speed during search for zero", DT::Unsigned32, false},
    {0x609A, 0x609A, 0, "Homing acceleration", "", DT::Unsigned32, false},
    {0x60B0, 0x60B0, 0, "Position offset", "", DT::Integer32, false},
    {0x60B1, 0x60B1, 0, "Velocity offset", "", DT::Integer32, false},
    {0x60B2, 0x60B2, 0, "Torque offset", "", DT::Integer16, false},
    {0x60C1, 0x60C1, 0, "Interpolation data record", "Highest sub-index supported", DT::Unsigned8,
     false},
    {0x60C1, 0x60C1, 1, "Interpolation data record", "Data record 1", DT::Integer32, false},
    {0x60C2, 0x60C2, 0, "Interpolation time period", "Highest sub-index supported", DT::Unsigned8,
     false},
    {0x60C2, 0x60C2, 1, "Interpolation time period", "Time period value", DT::Unsigned8, false},
    {0x60C2, 0x60C2, 2, "Interpolation time period", "Time period index", DT::Integer8, false},
    {0x60F4, 0x60F4, 0, "Following error actual value", "", DT::Integer32, false},
    {0x60FD, 0x60FD, 0, "Digital inputs", "", DT::Unsigned32, true},
    {0x60FE, 0x60FE, 0, "Digital outputs", "Highest sub-index supported", DT::Unsigned8, false},
    {0x60FE, 0x60FE, 1, "Digital outputs", "Physical outputs", DT::Unsigned32, true},
    {0x60FE, 0x60FE, 2, "Digital outputs", "Bit mask", DT::Unsigned32, true},
    {0x60FF, 0x60FF, 0, "Target velocity", "", DT::Integer32, false},
    {0x6502, 0x6502, 0, "Supported drive modes", "", DT::Unsigned32, true},
};

const BuiltinObject* find_builtin(std::uint16_t index, std::uint8_t sub) {
    const BuiltinObject* any = nullptr;
    for (const auto& o : kBuiltin) {
        if (index < o.index || index > o.last) {
            continue;
        }
        if (o.sub == sub) {
            return &o;
        }
        if (o.sub == kAny && any == nullptr) {
            any = &o;
        }
    }
    return any;
}

} // namespace

std::span<const BuiltinObject> builtin_objects() {
    return kBuiltin;
}

ObjectCatalog::ObjectCatalog() = default;

void ObjectCatalog::set_description(NodeId node, std::shared_ptr<const DeviceDescription> desc) {
    if (node <= kMaxNodeId) {
        eds_[node] = std::move(desc);
    }
}

const DeviceDescription* ObjectCatalog::description(NodeId node) const {
    return node <= kMaxNodeId ? eds_[node].get() : nullptr;
}

ObjectInfo ObjectCatalog::lookup(NodeId node, std::uint16_t index, std::uint8_t subindex,
                                 fmt::memory_buffer* name_out) const {
    ObjectInfo info;
    if (const auto* d = description(node)) {
        if (const Object* obj = d->od.find(index)) {
            if (const SubObject* sub = obj->find(subindex)) {
                info.known = true;
                info.type = sub->type;
                info.type_known = true;
                const auto* b = find_builtin(index, subindex);
                info.hex = b != nullptr && b->hex;
                if (name_out != nullptr) {
                    text::put(*name_out, obj->name);
                    if (obj->code != ObjectCode::Var && !sub->name.empty()) {
                        name_out->push_back('.');
                        text::put(*name_out, sub->name);
                    }
                }
                return info;
            }
        }
    }
    // Multi-axis CiA 402 devices: logical device n uses 6000h + 800h * (n - 1).
    unsigned axis = 1;
    std::uint16_t base = index;
    if (index >= 0x6800 && index < 0xA000) {
        axis = 1U + (index - 0x6000U) / 0x800U;
        base = static_cast<std::uint16_t>(index - 0x800U * (axis - 1));
    }
    const auto* b = find_builtin(base, subindex);
    if (b == nullptr) {
        return info;
    }
    info.known = true;
    info.type = b->type;
    info.type_known = true;
    info.hex = b->hex;
    if (name_out != nullptr) {
        if (axis > 1) {
            fmt::format_to(std::back_inserter(*name_out), "Axis {} ", axis);
        }
        const bool pdo = b->index >= 0x1400 && b->index < 0x1C00;
        if (pdo) {
            // "RPDO communication parameter" → "RPDO3 communication parameter".
            text::put(*name_out, b->object.substr(0, 4));
            fmt::format_to(std::back_inserter(*name_out), "{}", (index & 0x1FFU) + 1U);
            text::put(*name_out, b->object.substr(4));
        } else if (b->index != b->last) {
            fmt::format_to(std::back_inserter(*name_out), "{} {}", b->object, index - b->index + 1);
        } else {
            text::put(*name_out, b->object);
        }
        if (!b->name.empty()) {
            name_out->push_back('.');
            text::put(*name_out, b->name);
            if (b->sub == kAny) {
                fmt::format_to(std::back_inserter(*name_out), " {}", subindex);
            }
        }
    }
    return info;
}

} // namespace codrive::dump
