// SPDX-License-Identifier: Apache-2.0
// Device-side PDO engine: configuration from the OD, write checks, RPDO/TPDO processing.
#include <codrive/pdo/device.hpp>
#include <codrive/pdo/process_image.hpp>

#include <fmt/format.h>

#include <algorithm>
#include <cstring>

namespace codrive::pdo {
namespace {

using Check = tl::expected<void, SdoAbort>;

bool entry_length_ok(DataType type, unsigned bits) {
    const std::size_t size = data_type_size(type);
    // CiA 301 §7.4.7.1 lets a BOOLEAN be mapped as a single bit.
    return size * 8 == bits || (type == DataType::Boolean && bits == 1);
}

} // namespace

std::string to_string(const DevicePdoEvent& e, NodeId node) {
    const std::string head =
        fmt::format("node {}: {} (0x{:X})", node, pdo_name(e.dir, e.number), e.can_id);
    switch (e.kind) {
    case DevicePdoEventKind::RpdoTooShort:
        return fmt::format("{} has {} bytes but its mapping needs {} (frame ignored, EMCY 8210h)",
                           head, e.got_len, e.want_len);
    case DevicePdoEventKind::RpdoTooLong:
        return fmt::format("{} has {} bytes, its mapping only {} (EMCY 8220h)", head, e.got_len,
                           e.want_len);
    case DevicePdoEventKind::TpdoSendFailed:
        return fmt::format("{} could not be sent", head);
    case DevicePdoEventKind::RtrRefused:
        return fmt::format("{} requested by RTR, but its COB-ID forbids RTR (bit 30)", head);
    case DevicePdoEventKind::MappingInvalid:
        return fmt::format("{} mapping in the object dictionary is invalid; PDO disabled", head);
    }
    return head;
}

DevicePdo::DevicePdo(ObjectDictionary& od, ICanBus& bus, DevicePdoOptions options)
    : od_(od), bus_(bus), options_(std::move(options)) {
    for (PdoDir dir : {PdoDir::Rpdo, PdoDir::Tpdo}) {
        for (unsigned n = 1; n <= kMaxPdoNumber; ++n) {
            if (od_.find(comm_index(dir, n)) == nullptr || od_.find(map_index(dir, n)) == nullptr) {
                continue;
            }
            Channel ch;
            ch.config.dir = dir;
            ch.config.number = n;
            channels_.push_back(std::move(ch));
        }
    }
    install_hooks();
    reload();
}

DevicePdo::~DevicePdo() {
    // The OD outlives us: leave hooks that accept everything (an empty std::function would
    // throw when called).
    for (const auto& ch : channels_) {
        auto accept = [](std::uint16_t, std::uint8_t, std::span<const std::uint8_t>) -> Check {
            return {};
        };
        od_.on_write(comm_index(ch.config.dir, ch.config.number), accept);
        od_.on_write(map_index(ch.config.dir, ch.config.number), accept);
    }
}

void DevicePdo::install_hooks() {
    for (std::size_t i = 0; i < channels_.size(); ++i) {
        const PdoDir dir = channels_[i].config.dir;
        const unsigned n = channels_[i].config.number;
        od_.on_write(
            comm_index(dir, n),
            [this, i](std::uint16_t, std::uint8_t sub, std::span<const std::uint8_t> d) -> Check {
                auto ok = check_comm_write(channels_[i], sub, d);
                if (ok) {
                    dirty_ = true;
                }
                return ok;
            });
        od_.on_write(
            map_index(dir, n),
            [this, i](std::uint16_t, std::uint8_t sub, std::span<const std::uint8_t> d) -> Check {
                auto ok = check_map_write(channels_[i], sub, d);
                if (ok) {
                    dirty_ = true;
                }
                return ok;
            });
    }
}

bool DevicePdo::pdo_valid(const Channel& ch) const {
    const std::uint16_t comm = comm_index(ch.config.dir, ch.config.number);
    const auto cob = od_.get<std::uint32_t>(comm, comm_sub::kCobId).value_or(cob::kInvalidBit);
    if ((cob & cob::kInvalidBit) != 0) {
        return false;
    }
    if (options_.quirks.cob_id_read_only) {
        // Such a device is switched off by mapping count 0 (DS-BVS §1.8).
        return od_.get<std::uint8_t>(map_index(ch.config.dir, ch.config.number), 0).value_or(0) !=
               0;
    }
    return true;
}

SdoAbort check_mapping_entry(const ObjectDictionary& od, PdoDir dir, const PdoQuirks& q,
                             MappingEntry e) {
    if (e.bits == 0 || (q.byte_aligned && e.bits % 8 != 0)) {
        return SdoAbort::NotMappable;
    }
    if (e.is_zero_padding()) {
        return q.zero_index_padding && e.subindex == 0 ? SdoAbort{} : SdoAbort::NotMappable;
    }
    if (e.is_dummy()) {
        const auto t = static_cast<DataType>(e.index);
        if (dir != PdoDir::Rpdo || !q.dummy_mapping || data_type_size(t) * 8 != e.bits) {
            return SdoAbort::NotMappable;
        }
        return SdoAbort{};
    }
    const SubObject* sub = od.find(e.index, e.subindex);
    if (sub == nullptr || !sub->mappable(dir) || !entry_length_ok(sub->type, e.bits)) {
        return SdoAbort::NotMappable;
    }
    return SdoAbort{};
}

SdoAbort DevicePdo::check_entry(const Channel& ch, MappingEntry e) const {
    return check_mapping_entry(od_, ch.config.dir, options_.quirks, e);
}

tl::expected<void, SdoAbort> DevicePdo::check_comm_write(Channel& ch, std::uint8_t sub,
                                                         std::span<const std::uint8_t> d) {
    const PdoQuirks& q = options_.quirks;
    const bool tpdo = ch.config.dir == PdoDir::Tpdo;
    const std::uint16_t comm = comm_index(ch.config.dir, ch.config.number);
    const std::uint64_t v = get_le_n(d.data(), d.size());
    const bool valid = pdo_valid(ch);
    switch (sub) {
    case comm_sub::kCobId: {
        if (q.cob_id_read_only) {
            return tl::unexpected(SdoAbort::ReadOnly);
        }
        const auto now_v = decode_cob_id(static_cast<std::uint32_t>(v));
        const auto cur = decode_cob_id(od_.get<std::uint32_t>(comm, sub).value_or(0));
        // CiA 301 §7.5.2.35: bits 0..29 may not change while the PDO exists.
        if (valid && !now_v.invalid &&
            (now_v.can_id != cur.can_id || now_v.extended != cur.extended)) {
            return tl::unexpected(SdoAbort::InvalidValue);
        }
        if (now_v.extended && !q.extended_ids_supported) {
            return tl::unexpected(SdoAbort::InvalidValue);
        }
        if (!now_v.invalid && !now_v.extended && is_restricted_can_id(now_v.can_id)) {
            return tl::unexpected(SdoAbort::InvalidValue);
        }
        return {};
    }
    case comm_sub::kTransmissionType: {
        const auto t = static_cast<std::uint8_t>(v);
        if (is_reserved_type(t) || (is_rtr_only(t) && (!tpdo || !q.rtr_supported)) ||
            (t == transmission::kEventManufacturer && !q.type_254_supported)) {
            return tl::unexpected(SdoAbort::InvalidValue);
        }
        return {};
    }
    case comm_sub::kInhibitTime:
    case comm_sub::kSyncStart:
        // §7.5.2.37: inhibit time and SYNC start value may only change while the PDO is invalid.
        if (tpdo && valid) {
            return tl::unexpected(SdoAbort::InvalidValue);
        }
        return {};
    default:
        return {};
    }
}

tl::expected<void, SdoAbort> DevicePdo::check_map_write(Channel& ch, std::uint8_t sub,
                                                        std::span<const std::uint8_t> d) {
    const PdoQuirks& q = options_.quirks;
    if (q.mapping_only_pre_operational && operational_) {
        return tl::unexpected(SdoAbort::DataTransferState);
    }
    const std::uint16_t map = map_index(ch.config.dir, ch.config.number);
    const std::uint16_t comm = comm_index(ch.config.dir, ch.config.number);
    const bool cob_valid =
        (od_.get<std::uint32_t>(comm, comm_sub::kCobId).value_or(cob::kInvalidBit) &
         cob::kInvalidBit) == 0;
    // §7.5.2.36 step 1: the PDO must be destroyed before its mapping changes. Where the COB-ID
    // is read-only, mapping count 0 plays that role (checked below for the entries).
    if (!q.cob_id_read_only && cob_valid) {
        return tl::unexpected(SdoAbort::DataTransferState);
    }
    const auto count = od_.get<std::uint8_t>(map, 0).value_or(0);
    if (sub != 0) {
        if (count != 0) {
            return tl::unexpected(SdoAbort::DataTransferState);
        }
        const auto raw = static_cast<std::uint32_t>(get_le_n(d.data(), d.size()));
        if (raw != 0 && check_entry(ch, MappingEntry::from_raw(raw)) != SdoAbort{}) {
            return tl::unexpected(SdoAbort::NotMappable);
        }
        return {};
    }
    const unsigned n = d.empty() ? 0U : d[0];
    const Object* obj = od_.find(map);
    unsigned available = 0;
    for (const auto& [si, s] : obj->subs) {
        (void)s;
        if (si != 0) {
            ++available;
        }
    }
    if (n > std::min({available, q.max_entries, kMaxMapEntries})) {
        return tl::unexpected(SdoAbort::InvalidValue);
    }
    unsigned bits = 0;
    for (unsigned i = 1; i <= n; ++i) {
        const auto raw = od_.get<std::uint32_t>(map, static_cast<std::uint8_t>(i)).value_or(0);
        const MappingEntry e = MappingEntry::from_raw(raw);
        if (check_entry(ch, e) != SdoAbort{}) {
            return tl::unexpected(SdoAbort::NotMappable);
        }
        bits += e.bits;
    }
    if (bits > kMaxCanPdoBits) {
        return tl::unexpected(SdoAbort::PdoLengthExceeded);
    }
    return {};
}

void DevicePdo::reload() {
    dirty_ = false;
    for (auto& ch : channels_) {
        load(ch);
    }
    check_changes_ = true;
}

void DevicePdo::load(Channel& ch) {
    const PdoDir dir = ch.config.dir;
    const unsigned n = ch.config.number;
    const std::uint16_t comm = comm_index(dir, n);
    const std::uint16_t map = map_index(dir, n);
    PdoConfig cfg;
    cfg.dir = dir;
    cfg.number = n;
    const auto cob =
        decode_cob_id(od_.get<std::uint32_t>(comm, comm_sub::kCobId).value_or(cob::kInvalidBit));
    cfg.enabled = !cob.invalid;
    cfg.comm.can_id = cob.can_id;
    cfg.comm.extended = cob.extended;
    cfg.comm.rtr_allowed = dir == PdoDir::Tpdo && !cob.no_rtr;
    cfg.comm.transmission_type = od_.get<std::uint8_t>(comm, comm_sub::kTransmissionType)
                                     .value_or(dir == PdoDir::Rpdo ? 255 : 0);
    cfg.comm.inhibit_time = od_.get<std::uint16_t>(comm, comm_sub::kInhibitTime).value_or(0);
    cfg.comm.event_timer = od_.get<std::uint16_t>(comm, comm_sub::kEventTimer).value_or(0);
    cfg.comm.sync_start = od_.get<std::uint8_t>(comm, comm_sub::kSyncStart).value_or(0);
    const unsigned count = od_.get<std::uint8_t>(map, 0).value_or(0);
    std::vector<Mapped> entries;
    bool ok = true;
    unsigned offset = 0;
    for (unsigned i = 1; i <= count; ++i) {
        const MappingEntry e = MappingEntry::from_raw(
            od_.get<std::uint32_t>(map, static_cast<std::uint8_t>(i)).value_or(0));
        cfg.mapping.push_back(e);
        if (check_entry(ch, e) != SdoAbort{}) {
            ok = false;
        }
        Mapped m;
        m.index = e.index;
        m.subindex = e.subindex;
        m.bit_offset = static_cast<std::uint8_t>(std::min(offset, 255U));
        m.bits = e.bits;
        if (!e.is_dummy() && !e.is_zero_padding()) {
            m.sub = od_.find(e.index, e.subindex);
            if (m.sub != nullptr) {
                // Size the value once here so the cyclic path never resizes it.
                const std::size_t size = std::max<std::size_t>(data_type_size(m.sub->type), 1);
                if (m.sub->value.size() < size) {
                    m.sub->value.mutable_bytes().resize(size);
                }
            }
        }
        entries.push_back(m);
        offset += e.bits;
    }
    if (offset > kMaxCanPdoBits) {
        ok = false;
    }
    const bool config_changed = !(cfg == ch.config);
    ch.config = std::move(cfg);
    ch.entries = std::move(entries);
    ch.len = static_cast<std::uint8_t>((offset + 7) / 8);
    const bool was_active = ch.active;
    ch.active = ok && ch.config.enabled && count > 0;
    if (!ok && count > 0) {
        emit(DevicePdoEventKind::MappingInvalid, ch, TimePoint{});
    }
    if (config_changed || was_active != ch.active) {
        ch.sent_once = false;
        ch.started = false;
        ch.rx_pending = false;
        ch.sampled_valid = false;
        ch.event_pending = false;
        const std::uint8_t t = ch.config.comm.transmission_type;
        ch.sync_count = static_cast<std::uint8_t>(is_cyclic_sync(t) ? t - 1 : 0);
    }
}

DevicePdo::Channel* DevicePdo::find(PdoDir dir, unsigned number) {
    for (auto& ch : channels_) {
        if (ch.config.dir == dir && ch.config.number == number) {
            return &ch;
        }
    }
    return nullptr;
}

const PdoConfig* DevicePdo::config(PdoDir dir, unsigned number) {
    refresh();
    const Channel* ch = find(dir, number);
    return ch == nullptr ? nullptr : &ch->config;
}

bool DevicePdo::active(PdoDir dir, unsigned number) {
    refresh();
    const Channel* ch = find(dir, number);
    return ch != nullptr && ch->active;
}

std::uint64_t DevicePdo::sent(unsigned tpdo) const {
    for (const auto& ch : channels_) {
        if (ch.config.dir == PdoDir::Tpdo && ch.config.number == tpdo) {
            return ch.count;
        }
    }
    return 0;
}

std::uint64_t DevicePdo::received(unsigned rpdo) const {
    for (const auto& ch : channels_) {
        if (ch.config.dir == PdoDir::Rpdo && ch.config.number == rpdo) {
            return ch.count;
        }
    }
    return 0;
}

void DevicePdo::set_operational(bool operational, TimePoint /*now*/) {
    refresh();
    if (operational == operational_) {
        return;
    }
    operational_ = operational;
    for (auto& ch : channels_) {
        ch.sent_once = false;
        ch.started = false;
        ch.rx_pending = false;
        ch.sampled_valid = false;
        ch.event_pending = false;
        const std::uint8_t t = ch.config.comm.transmission_type;
        ch.sync_count = static_cast<std::uint8_t>(is_cyclic_sync(t) ? t - 1 : 0);
    }
    check_changes_ = operational;
    next_ = kNever;
}

void DevicePdo::emit(DevicePdoEventKind kind, const Channel& ch, TimePoint now, std::uint8_t got) {
    if (!handler_) {
        return;
    }
    DevicePdoEvent e;
    e.kind = kind;
    e.dir = ch.config.dir;
    e.number = static_cast<std::uint8_t>(ch.config.number);
    e.can_id = ch.config.comm.can_id;
    e.got_len = got;
    e.want_len = ch.len;
    e.time = now;
    handler_(e);
}

void DevicePdo::compose(const Channel& ch, std::array<std::uint8_t, 8>& out) const {
    out.fill(0);
    for (const Mapped& m : ch.entries) {
        if (m.sub == nullptr) {
            continue; // dummies and padding transmit zeros
        }
        const auto bytes = m.sub->value.bytes();
        if (m.bit_offset % 8 == 0 && m.bits % 8 == 0 && bytes.size() >= m.bits / 8U) {
            std::memcpy(out.data() + m.bit_offset / 8, bytes.data(), m.bits / 8U);
        } else {
            detail::write_bits(out.data(), m.bit_offset, m.bits,
                               get_le_n(bytes.data(), bytes.size()));
        }
    }
}

void DevicePdo::apply(Channel& ch, const std::uint8_t* data, TimePoint now) {
    for (const Mapped& m : ch.entries) {
        if (m.sub == nullptr) {
            continue;
        }
        auto& bytes = m.sub->value.mutable_bytes();
        if (m.bit_offset % 8 == 0 && m.bits % 8 == 0 && bytes.size() >= m.bits / 8U) {
            const std::uint8_t* src = data + m.bit_offset / 8;
            if (options_.write_through_od) {
                (void)od_.write(m.index, m.subindex, {src, m.bits / 8U}, true);
            } else {
                std::memcpy(bytes.data(), src, m.bits / 8U);
            }
        } else {
            put_le_n(bytes.data(), detail::read_bits(data, m.bit_offset, m.bits), bytes.size());
        }
    }
    ++ch.count;
    if (rpdo_hook_) {
        rpdo_hook_(ch.config.number, now);
    }
}

void DevicePdo::transmit(Channel& ch, const std::array<std::uint8_t, 8>& data, TimePoint now) {
    Frame f;
    f.id = ch.config.comm.can_id;
    f.flags = ch.config.comm.extended ? std::uint8_t{Frame::kExtended} : std::uint8_t{0};
    f.len = ch.len;
    std::memcpy(f.data.data(), data.data(), 8);
    ch.last = data;
    ch.last_tx = now;
    ch.sent_once = true;
    ch.event_pending = false;
    if (!bus_.send(f)) {
        emit(DevicePdoEventKind::TpdoSendFailed, ch, now);
        return;
    }
    ++ch.count;
}

bool DevicePdo::on_frame(const Frame& frame, TimePoint now) {
    refresh();
    if (frame.error()) {
        return false;
    }
    if (options_.sync_id != 0 && !frame.extended() && !frame.rtr() &&
        frame.id == options_.sync_id) {
        on_sync(frame.len >= 1 ? frame.data[0] : std::uint8_t{0}, now);
        return true;
    }
    for (auto& ch : channels_) {
        if (!ch.active || ch.config.comm.can_id != frame.id ||
            ch.config.comm.extended != frame.extended()) {
            continue;
        }
        if (ch.config.dir == PdoDir::Rpdo) {
            if (frame.rtr() || !operational_) {
                return true;
            }
            if (frame.len < ch.len) {
                emit(DevicePdoEventKind::RpdoTooShort, ch, now, frame.len);
                return true;
            }
            if (frame.len > ch.len) {
                emit(DevicePdoEventKind::RpdoTooLong, ch, now, frame.len);
            }
            if (is_synchronous(ch.config.comm.transmission_type)) {
                std::memcpy(ch.last.data(), frame.data.data(), 8);
                ch.rx_pending = true;
            } else {
                apply(ch, frame.data.data(), now);
                run_events(now);
            }
            return true;
        }
        if (!frame.rtr()) {
            continue; // another producer on our TPDO's id: not ours to consume
        }
        if (!operational_) {
            return true;
        }
        if (!ch.config.comm.rtr_allowed) {
            emit(DevicePdoEventKind::RtrRefused, ch, now);
            return true;
        }
        if (ch.config.comm.transmission_type == transmission::kRtrSync) {
            if (ch.sampled_valid) {
                transmit(ch, ch.sampled, now);
            }
        } else {
            std::array<std::uint8_t, 8> buf{};
            compose(ch, buf);
            transmit(ch, buf, now);
        }
        return true;
    }
    return false;
}

void DevicePdo::on_sync(std::uint8_t counter, TimePoint now) {
    refresh();
    if (!operational_) {
        return;
    }
    // §7.2.2.2: synchronous RPDOs received before this SYNC take effect now.
    for (auto& ch : channels_) {
        if (ch.active && ch.config.dir == PdoDir::Rpdo && ch.rx_pending) {
            ch.rx_pending = false;
            apply(ch, ch.last.data(), now);
        }
    }
    std::array<std::uint8_t, 8> buf{};
    for (auto& ch : channels_) {
        if (!ch.active || ch.config.dir != PdoDir::Tpdo) {
            continue;
        }
        const std::uint8_t t = ch.config.comm.transmission_type;
        if (!is_synchronous(t) && t != transmission::kRtrSync) {
            continue;
        }
        // §7.5.2.37 sub 06h: with a SYNC counter, counting starts at the SYNC whose counter
        // equals the start value.
        if (ch.config.comm.sync_start != 0 && counter != 0 && !ch.started) {
            if (counter != ch.config.comm.sync_start) {
                continue;
            }
            ch.started = true;
            ch.sync_count = static_cast<std::uint8_t>(is_cyclic_sync(t) ? t - 1 : 0);
        }
        if (t == transmission::kSyncAcyclic) {
            compose(ch, buf);
            if (ch.event_pending || !ch.sent_once || buf != ch.last) {
                transmit(ch, buf, now);
            }
        } else if (is_cyclic_sync(t)) {
            if (++ch.sync_count >= t) {
                ch.sync_count = 0;
                compose(ch, buf);
                transmit(ch, buf, now);
            }
        } else {
            compose(ch, ch.sampled);
            ch.sampled_valid = true;
        }
    }
    run_events(now);
}

void DevicePdo::trigger(unsigned number, TimePoint now) {
    refresh();
    Channel* ch = find(PdoDir::Tpdo, number);
    if (ch == nullptr || !ch->active) {
        return;
    }
    ch->event_pending = true;
    if (is_event_driven(ch->config.comm.transmission_type)) {
        run_events(now);
    }
}

void DevicePdo::run_events(TimePoint now) {
    check_changes_ = false;
    next_ = kNever;
    if (!operational_) {
        return;
    }
    std::array<std::uint8_t, 8> buf{};
    for (auto& ch : channels_) {
        if (!ch.active || ch.config.dir != PdoDir::Tpdo ||
            !is_event_driven(ch.config.comm.transmission_type)) {
            continue;
        }
        const Duration inhibit = ch.config.comm.inhibit();
        const Duration period = ch.config.comm.event_period();
        compose(ch, buf);
        const bool changed = !ch.sent_once || ch.event_pending || buf != ch.last;
        const bool inhibited = ch.sent_once && now < ch.last_tx + inhibit;
        const bool timer_due = period.count() > 0 && ch.sent_once && now >= ch.last_tx + period;
        if ((changed && !inhibited) || (timer_due && !inhibited)) {
            transmit(ch, buf, now);
        } else if (changed) {
            ch.event_pending = true; // §7.2.2.1: held back by the inhibit time, sent after it
        }
        if (ch.event_pending) {
            next_ = std::min(next_, ch.last_tx + inhibit);
        }
        if (period.count() > 0) {
            next_ = std::min(next_, ch.last_tx + period);
        }
    }
}

TimePoint DevicePdo::next_deadline() const {
    if (dirty_ || check_changes_) {
        return operational_ ? TimePoint{} : next_;
    }
    return next_;
}

void DevicePdo::on_tick(TimePoint now) {
    refresh();
    run_events(now);
}

} // namespace codrive::pdo
