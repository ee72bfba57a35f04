// SPDX-License-Identifier: Apache-2.0
// PDO mapping learning and PDO frame decoding.
#include <codrive/dump/pdo_tracker.hpp>

#include <codrive/core/endian.hpp>
#include <codrive/core/frame.hpp>
#include <codrive/core/value.hpp>
#include <codrive/dump/text_append.hpp>
#include <codrive/dump/value_format.hpp>

#include <bit>
#include <iterator>

namespace codrive::dump {
namespace {

std::uint32_t key_of(NodeId node, bool tpdo, std::uint16_t number) {
    return (static_cast<std::uint32_t>(node) << 16) | (tpdo ? 0x8000U : 0U) | number;
}

// Default COB-ID of PDO 1..4 in the predefined connection set (CiA 301 §7.3.5).
std::uint32_t default_cob(NodeId node, bool tpdo, std::uint16_t number) {
    if (number < 1 || number > 4 || !valid_node_id(node)) {
        return 0;
    }
    return tpdo ? cob::tpdo(number, node) : cob::rpdo(number, node);
}

// Reads `bits` bits starting at bit `pos` (little-endian bit order, CiA 301 §7.1).
std::uint64_t get_bits(std::span<const std::uint8_t> d, std::size_t pos, std::size_t bits) {
    if (pos % 8 == 0 && bits % 8 == 0) {
        return get_le_n(d.data() + pos / 8, bits / 8);
    }
    std::uint64_t v = 0;
    for (std::size_t i = 0; i < bits; ++i) {
        const std::size_t b = pos + i;
        if (((d[b / 8] >> (b % 8)) & 1U) != 0) {
            v |= std::uint64_t{1} << i;
        }
    }
    return v;
}

} // namespace

PdoTracker::PdoTracker(const ObjectCatalog& catalog) : catalog_(catalog) {
    by_cob_.fill(kNoPdo);
}

PdoTracker::Pdo& PdoTracker::pdo(NodeId node, bool tpdo, std::uint16_t number) {
    const auto key = key_of(node, tpdo, number);
    auto [it, inserted] = pdos_.try_emplace(key);
    Pdo& p = it->second;
    if (inserted) {
        p.node = node;
        p.tpdo = tpdo;
        p.number = number;
        p.label = fmt::format("{}{}", tpdo ? "TPDO" : "RPDO", number);
        p.cob_id = default_cob(node, tpdo, number);
        if (p.cob_id != 0) {
            by_cob_[p.cob_id] = key;
        }
    }
    return p;
}

void PdoTracker::set_cob_id(Pdo& p, std::uint32_t value) {
    const auto key = key_of(p.node, p.tpdo, p.number);
    if (p.cob_id != 0 && by_cob_[p.cob_id] == key) {
        by_cob_[p.cob_id] = kNoPdo;
    }
    p.valid = (value & cob::kInvalidBit) == 0;
    p.cob_id = (value & cob::kFrameBit) != 0 ? 0 : (value & Frame::kStdMask);
    if (p.cob_id != 0) {
        by_cob_[p.cob_id] = key;
    }
}

bool PdoTracker::learn(NodeId node, std::uint16_t index, std::uint8_t sub,
                       std::span<const std::uint8_t> data) {
    if (index < 0x1400 || index > 0x1BFF || !valid_node_id(node) || data.empty()) {
        return false;
    }
    const bool tpdo = index >= 0x1800;
    const bool mapping = (index & 0x200U) != 0;
    const auto number = static_cast<std::uint16_t>((index & 0x1FFU) + 1U);
    Pdo& p = pdo(node, tpdo, number);
    const std::uint64_t v = get_le_n(data.data(), std::min<std::size_t>(data.size(), 4));
    if (!mapping) {
        if (sub == 1) {
            set_cob_id(p, static_cast<std::uint32_t>(v));
            return true;
        }
        return false;
    }
    if (sub == 0) {
        p.count = static_cast<std::uint8_t>(std::min<std::uint64_t>(v, 64));
        p.map_known = true;
        p.dirty = true;
        return true;
    }
    if (sub <= 64) {
        p.raw[sub - 1U] = static_cast<std::uint32_t>(v);
        p.dirty = true;
        return true;
    }
    return false;
}

void PdoTracker::learn_from_description(NodeId node, const DeviceDescription& desc) {
    for (const auto& [index, obj] : desc.od.objects()) {
        if (index < 0x1400 || index > 0x1BFF) {
            continue;
        }
        for (const auto& [sub, so] : obj.subs) {
            if ((index & 0x200U) == 0 && sub != 1) {
                continue;
            }
            (void)learn(node, index, sub, so.value.bytes());
        }
    }
}

void PdoTracker::resolve(Pdo& p) {
    p.entries.clear();
    p.dirty = false;
    fmt::memory_buffer name;
    for (std::size_t i = 0; i < p.count; ++i) {
        const std::uint32_t raw = p.raw[i];
        Entry e;
        e.index = static_cast<std::uint16_t>(raw >> 16);
        e.subindex = static_cast<std::uint8_t>(raw >> 8);
        e.bits = static_cast<std::uint8_t>(raw);
        // Entries pointing at data type indexes (0001h..0007h...) are dummy entries (§7.4.8).
        e.dummy = e.index < 0x1000 || e.bits == 0;
        name.clear();
        const auto info = catalog_.lookup(p.node, e.index, e.subindex, &name);
        if (name.size() == 0) {
            fmt::format_to(std::back_inserter(name), "{:04X}:{:02X}", e.index, e.subindex);
        }
        e.name.assign(name.data(), name.size());
        if (info.type_known && data_type_size(info.type) * 8 == e.bits) {
            e.is_signed = is_signed_integer(info.type);
            e.is_real = is_real(info.type);
            e.hex = info.hex;
        } else if (info.type_known && is_variable_size(info.type) && e.bits % 8 == 0) {
            e.string = info.type == DataType::VisibleString;
        } else {
            e.hex = true;
        }
        p.entries.push_back(std::move(e));
    }
}

PdoTracker::Pdo* PdoTracker::find(std::uint32_t cob_id) {
    if (cob_id >= by_cob_.size()) {
        return nullptr;
    }
    std::uint32_t key = by_cob_[cob_id];
    if (key == kNoPdo) {
        // A default PDO COB-ID nobody has configured yet.
        const auto info = classify_cob_id(cob_id);
        const unsigned n = info.pdo_number();
        if (n == 0 || info.node == 0) {
            return nullptr;
        }
        (void)pdo(info.node, info.is_tpdo(), static_cast<std::uint16_t>(n));
        key = by_cob_[cob_id];
        if (key == kNoPdo) {
            return nullptr; // that PDO was moved to another COB-ID
        }
    }
    return &pdos_.find(key)->second;
}

NodeId PdoTracker::remote_request(std::uint32_t cob_id, fmt::memory_buffer& out) {
    const Pdo* p = find(cob_id);
    if (p == nullptr) {
        return 0;
    }
    fmt::format_to(std::back_inserter(out), "node {} {} remote request", p->node, p->label);
    return p->node;
}

NodeId PdoTracker::decode(std::uint32_t cob_id, std::span<const std::uint8_t> payload,
                          fmt::memory_buffer& out) {
    Pdo* found = find(cob_id);
    if (found == nullptr) {
        return 0;
    }
    Pdo& p = *found;
    auto it = std::back_inserter(out);
    text::put(out, "node ");
    text::put_uint(out, p.node);
    out.push_back(' ');
    text::put(out, p.label);
    if (!p.valid) {
        fmt::format_to(it, " (marked invalid in {:04X}h)",
                       (p.tpdo ? 0x1800U : 0x1400U) + p.number - 1U);
    }
    if (!p.map_known) {
        fmt::format_to(it, " (mapping unknown: give --eds or capture the configuration)");
        return p.node;
    }
    if (p.dirty) {
        resolve(p);
    }
    std::size_t pos = 0;
    const std::size_t avail = payload.size() * 8;
    bool first = true;
    for (const auto& e : p.entries) {
        if (pos + e.bits > avail) {
            std::size_t total = 0;
            for (const auto& r : p.entries) {
                total += r.bits;
            }
            fmt::format_to(it, " (frame has {} bytes, mapping needs {})", payload.size(),
                           (total + 7) / 8);
            return p.node;
        }
        if (e.dummy) {
            pos += e.bits;
            continue;
        }
        out.push_back(first ? ' ' : ',');
        if (!first) {
            out.push_back(' ');
        }
        first = false;
        out.append(e.name.data(), e.name.data() + e.name.size());
        out.push_back('=');
        if (e.string || e.bits > 64) {
            const auto bytes = payload.subspan(pos / 8, e.bits / 8U);
            ObjectInfo info;
            info.type_known = e.string;
            info.type = DataType::VisibleString;
            format_value(out, info, bytes);
            pos += e.bits;
            continue;
        }
        const std::uint64_t raw = get_bits(payload, pos, e.bits);
        pos += e.bits;
        if (e.is_real) {
            if (e.bits == 32) {
                fmt::format_to(it, "{}", std::bit_cast<float>(static_cast<std::uint32_t>(raw)));
            } else {
                fmt::format_to(it, "{}", std::bit_cast<double>(raw));
            }
        } else if (e.is_signed) {
            std::uint64_t v = raw;
            if (e.bits < 64 && ((raw >> (e.bits - 1U)) & 1U) != 0) {
                v |= ~((std::uint64_t{1} << e.bits) - 1U);
            }
            text::put_int(out, static_cast<std::int64_t>(v));
        } else if (e.hex) {
            text::put(out, "0x");
            text::put_hex(out, raw, (e.bits + 3U) / 4U);
        } else {
            text::put_uint(out, raw);
        }
        format_cia402_meaning(out, e.index, raw);
    }
    if (pos + 8 <= avail) {
        fmt::format_to(it, " (+{} bytes not mapped)", (avail - pos) / 8);
    }
    return p.node;
}

} // namespace codrive::dump
