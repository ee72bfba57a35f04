// SPDX-License-Identifier: Apache-2.0
// PDO configuration checks (CiA 301 §7.2.2, §7.4.7.1, §7.5.2.35–38 plus device quirks).
#include <codrive/pdo/validate.hpp>

#include <fmt/format.h>

#include <map>

namespace codrive::pdo {
namespace {

struct Problem {
    PdoErrc code;
    std::string text;
};

std::string object_text(const MappingEntry& e) {
    return fmt::format("0x{:04X}:{:02X}", e.index, e.subindex);
}

void check_comm(NodeId node, const PdoConfig& pdo, const PdoQuirks& q, const std::string& who,
                std::vector<Problem>& out) {
    const unsigned count = pdo.dir == PdoDir::Rpdo ? q.rpdo_count : q.tpdo_count;
    if (pdo.number < 1 || pdo.number > kMaxPdoNumber || pdo.number > count) {
        out.push_back({PdoErrc::InvalidCommunication,
                       fmt::format("{}: {} does not exist ({} has {} {}s)", who, pdo.name(),
                                   q.device, count, to_string(pdo.dir))});
        return;
    }
    const std::uint8_t t = pdo.comm.transmission_type;
    if (is_reserved_type(t)) {
        out.push_back({PdoErrc::InvalidCommunication,
                       fmt::format("{}: {} transmission type {} is reserved (CiA 301 Table 72)",
                                   who, pdo.name(), t)});
    } else if (is_rtr_only(t) && pdo.dir == PdoDir::Rpdo) {
        out.push_back(
            {PdoErrc::InvalidCommunication,
             fmt::format("{}: {} transmission type {} is for TPDOs only", who, pdo.name(), t)});
    } else if (is_rtr_only(t) && !q.rtr_supported) {
        out.push_back({PdoErrc::UnsupportedByDevice,
                       fmt::format("{}: {} transmission type {} needs RTR, which {} does not "
                                   "support",
                                   who, pdo.name(), t, q.device)});
    } else if (t == transmission::kEventManufacturer && !q.type_254_supported) {
        out.push_back({PdoErrc::UnsupportedByDevice,
                       fmt::format("{}: {} transmission type 254 is not supported by {}", who,
                                   pdo.name(), q.device)});
    }
    if (pdo.comm.rtr_allowed && !q.rtr_supported) {
        out.push_back({PdoErrc::UnsupportedByDevice,
                       fmt::format("{}: {} allows RTR but {} does not support RTR", who, pdo.name(),
                                   q.device)});
    }
    if (pdo.comm.sync_start != 0 && (!q.has_sync_start || pdo.dir == PdoDir::Rpdo)) {
        out.push_back(
            {PdoErrc::UnsupportedByDevice,
             fmt::format("{}: {} has a SYNC start value but {} has no sub-index 06h", who,
                         pdo.name(), pdo.dir == PdoDir::Rpdo ? std::string("an RPDO") : q.device)});
    }
    if (q.cob_id_read_only && pdo.comm.can_id != 0 &&
        pdo.comm.can_id != PdoConfig{pdo.dir, pdo.number, true, {}, {}}.can_id_for(node)) {
        out.push_back({PdoErrc::UnsupportedByDevice,
                       fmt::format("{}: {} COB-ID 0x{:X} cannot be set: {} PDO COB-IDs are "
                                   "read-only",
                                   who, pdo.name(), pdo.comm.can_id, q.device)});
    }
    const std::uint32_t id = pdo.can_id_for(node);
    if (pdo.comm.extended) {
        if (!q.extended_ids_supported) {
            out.push_back({PdoErrc::UnsupportedByDevice,
                           fmt::format("{}: {} uses a 29-bit COB-ID, which {} does not support",
                                       who, pdo.name(), q.device)});
        } else if (id > 0x1FFFFFFF) {
            out.push_back(
                {PdoErrc::InvalidCommunication,
                 fmt::format("{}: {} COB-ID 0x{:X} does not fit 29 bits", who, pdo.name(), id)});
        }
    } else if (id == 0) {
        out.push_back(
            {PdoErrc::InvalidCommunication,
             fmt::format("{}: {} has no COB-ID (no default beyond PDO 4)", who, pdo.name())});
    } else if (id > 0x7FF) {
        out.push_back(
            {PdoErrc::InvalidCommunication,
             fmt::format("{}: {} COB-ID 0x{:X} does not fit 11 bits", who, pdo.name(), id)});
    } else if (is_restricted_can_id(id)) {
        out.push_back({PdoErrc::InvalidCommunication,
                       fmt::format("{}: {} COB-ID 0x{:03X} is restricted by CiA 301 (Table 41)",
                                   who, pdo.name(), id)});
    }
}

void check_entry(const PdoConfig& pdo, const MappingEntry& e, unsigned bit_pos,
                 const DeviceModel& dev, const std::string& who, std::vector<Problem>& out) {
    const PdoQuirks& q = dev.quirks;
    const std::string head = fmt::format("{}: {} maps {}", who, pdo.name(), object_text(e));
    if (e.bits == 0) {
        out.push_back({PdoErrc::InvalidMapping, head + " with length 0"});
        return;
    }
    if (q.byte_aligned && (e.bits % 8 != 0 || bit_pos % 8 != 0)) {
        out.push_back({PdoErrc::InvalidMapping,
                       fmt::format("{} with {} bits at bit {}, but {} PDOs are byte aligned", head,
                                   e.bits, bit_pos, q.device)});
        return;
    }
    if (e.is_zero_padding()) {
        if (!q.zero_index_padding) {
            out.push_back({PdoErrc::InvalidMapping,
                           head + ", but index 0000h is not an object (use a dummy 0002h..0007h "
                                  "for padding)"});
        }
        return;
    }
    if (e.is_dummy()) {
        const DataType t = static_cast<DataType>(e.index);
        if (pdo.dir == PdoDir::Tpdo) {
            out.push_back(
                {PdoErrc::InvalidMapping,
                 fmt::format("{} ({} dummy), but dummies are only for RPDOs", head, to_string(t))});
        } else if (!q.dummy_mapping ||
                   (dev.dummy_usage != nullptr && !dev.dummy_usage->supported(t))) {
            out.push_back({PdoErrc::InvalidMapping,
                           fmt::format("{} ({} dummy), but the device does not support that "
                                       "dummy ([DummyUsage])",
                                       head, to_string(t))});
        } else if (data_type_size(t) * 8 != e.bits) {
            out.push_back({PdoErrc::InvalidMapping,
                           fmt::format("{} with {} bits, but a {} dummy has {}", head, e.bits,
                                       to_string(t), data_type_size(t) * 8)});
        }
        return;
    }
    if (dev.od == nullptr) {
        return;
    }
    const Object* obj = dev.od->find(e.index);
    if (obj == nullptr) {
        out.push_back(
            {PdoErrc::InvalidMapping, head + ", which does not exist in the object dictionary"});
        return;
    }
    const SubObject* sub = obj->find(e.subindex);
    if (sub == nullptr) {
        out.push_back(
            {PdoErrc::InvalidMapping,
             fmt::format("{}, but 0x{:04X} has no sub-index {:02X}h", head, e.index, e.subindex)});
        return;
    }
    const std::string typed = fmt::format("{} ({})", head, to_string(sub->type));
    if (!sub->mappable(pdo.dir)) {
        const PdoDir other = pdo.dir == PdoDir::Rpdo ? PdoDir::Tpdo : PdoDir::Rpdo;
        if (sub->mappable(other)) {
            out.push_back({PdoErrc::InvalidMapping,
                           fmt::format("{} but it is only {}-mappable", typed, to_string(other))});
        } else {
            out.push_back({PdoErrc::InvalidMapping, typed + " but it is not PDO-mappable"});
        }
        return;
    }
    const std::size_t size = data_type_size(sub->type);
    if (size != 0 && size * 8 != e.bits) {
        out.push_back(
            {PdoErrc::InvalidMapping,
             fmt::format("{} with {} bits, but the object has {}", typed, e.bits, size * 8)});
    }
}

void check_pdo(NodeId node, const PdoConfig& pdo, const DeviceModel& dev,
               std::vector<Problem>& out) {
    const std::string who = fmt::format("node {}", node);
    check_comm(node, pdo, dev.quirks, who, out);
    const unsigned max_entries = std::min(dev.quirks.max_entries, kMaxMapEntries);
    if (pdo.mapping.size() > max_entries) {
        out.push_back(
            {PdoErrc::LengthExceeded,
             fmt::format("{}: {} maps {} entries, more than the {} {} allows", who, pdo.name(),
                         pdo.mapping.size(), max_entries, dev.quirks.device)});
    }
    unsigned bit_pos = 0;
    for (const auto& e : pdo.mapping) {
        check_entry(pdo, e, bit_pos, dev, who, out);
        bit_pos += e.bits;
    }
    if (bit_pos > kMaxCanPdoBits) {
        out.push_back({PdoErrc::LengthExceeded,
                       fmt::format("{}: {} maps {} bits, more than the {} bits of a CAN frame", who,
                                   pdo.name(), bit_pos, kMaxCanPdoBits)});
    }
}

void check_duplicates(NodeId node, std::span<const PdoConfig> pdos, std::vector<Problem>& out) {
    std::map<std::uint32_t, const PdoConfig*> seen;
    std::map<std::pair<int, unsigned>, bool> numbers;
    for (const auto& p : pdos) {
        if (numbers[{static_cast<int>(p.dir), p.number}]) {
            out.push_back({PdoErrc::InvalidCommunication,
                           fmt::format("node {}: {} is configured twice", node, p.name())});
        }
        numbers[{static_cast<int>(p.dir), p.number}] = true;
        if (!p.enabled) {
            continue;
        }
        const std::uint32_t id = p.can_id_for(node) | (p.comm.extended ? cob::kFrameBit : 0U);
        auto [it, inserted] = seen.emplace(id, &p);
        if (!inserted) {
            out.push_back({PdoErrc::InvalidCommunication,
                           fmt::format("node {}: {} and {} both use COB-ID 0x{:X}", node,
                                       it->second->name(), p.name(), p.can_id_for(node))});
        }
    }
}

} // namespace

DeviceModel device_model(const DeviceDescription& eds, PdoQuirks base) {
    DeviceModel m;
    m.od = &eds.od;
    m.dummy_usage = &eds.dummy_usage;
    m.quirks = std::move(base);
    const DeviceInfo& info = eds.device_info;
    if (m.quirks.device == PdoQuirks{}.device && !info.product_name.empty()) {
        m.quirks.device = info.product_name; // messages name the product
    }
    if (info.nr_of_rx_pdo != 0) {
        m.quirks.rpdo_count = info.nr_of_rx_pdo;
    }
    if (info.nr_of_tx_pdo != 0) {
        m.quirks.tpdo_count = info.nr_of_tx_pdo;
    }
    // CiA 306 §4.3: Granularity is the mapping granularity in bits; 8 means whole bytes.
    if (info.granularity == 8) {
        m.quirks.byte_aligned = true;
    }
    return m;
}

PdoResult<void> validate(NodeId node, const PdoConfig& pdo, const DeviceModel& dev) {
    std::vector<Problem> problems;
    check_pdo(node, pdo, dev, problems);
    if (!problems.empty()) {
        return pdo_fail(problems.front().code, std::move(problems.front().text));
    }
    return {};
}

PdoResult<void> validate_all(NodeId node, std::span<const PdoConfig> pdos, const DeviceModel& dev) {
    std::vector<Problem> problems;
    for (const auto& p : pdos) {
        check_pdo(node, p, dev, problems);
        if (!problems.empty()) {
            return pdo_fail(problems.front().code, std::move(problems.front().text));
        }
    }
    check_duplicates(node, pdos, problems);
    if (!problems.empty()) {
        return pdo_fail(problems.front().code, std::move(problems.front().text));
    }
    return {};
}

std::vector<std::string> find_problems(NodeId node, std::span<const PdoConfig> pdos,
                                       const DeviceModel& dev) {
    std::vector<Problem> problems;
    for (const auto& p : pdos) {
        check_pdo(node, p, dev, problems);
    }
    check_duplicates(node, pdos, problems);
    std::vector<std::string> out;
    out.reserve(problems.size());
    for (auto& p : problems) {
        out.push_back(std::move(p.text));
    }
    return out;
}

} // namespace codrive::pdo
