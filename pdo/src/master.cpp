// SPDX-License-Identifier: Apache-2.0
// The master PDO engine: RPDO production, TPDO consumption and monitoring.
#include <codrive/pdo/master.hpp>

#include <fmt/format.h>

#include <algorithm>

namespace codrive::pdo {

std::string_view to_string(PdoEventKind k) {
    switch (k) {
    case PdoEventKind::TpdoMissing:
        return "TPDO missing";
    case PdoEventKind::TpdoSilent:
        return "TPDO silent";
    case PdoEventKind::TpdoRecovered:
        return "TPDO recovered";
    case PdoEventKind::TpdoTooShort:
        return "TPDO too short";
    case PdoEventKind::RpdoSendFailed:
        return "RPDO send failed";
    }
    return "PDO event";
}

std::string to_string(const PdoEvent& e) {
    const std::string head =
        fmt::format("node {}: {} (0x{:X})", e.node, pdo_name(e.dir, e.number), e.can_id);
    switch (e.kind) {
    case PdoEventKind::TpdoMissing: {
        std::string every = describe_transmission(e.transmission_type);
        // "3 (every 3rd SYNC)" → "every 3rd SYNC"
        const auto open = every.find('(');
        if (open != std::string::npos) {
            every = every.substr(open + 1, every.size() - open - 2);
        }
        return fmt::format("{} missing after SYNC {} (expected {})", head, e.sync, every);
    }
    case PdoEventKind::TpdoSilent:
        return fmt::format("{} silent for {} ms (event timer {} ms)", head, to_ms(e.silent_for),
                           to_ms(e.event_timer));
    case PdoEventKind::TpdoRecovered:
        return fmt::format("{} received again", head);
    case PdoEventKind::TpdoTooShort:
        return fmt::format("{} has {} bytes but its mapping needs {} (frame ignored)", head,
                           e.got_len, e.want_len);
    case PdoEventKind::RpdoSendFailed:
        return fmt::format("{} not sent: {}", head, e.error.message());
    }
    return head;
}

std::string event_key(const PdoEvent& e) {
    const char* what = "event";
    switch (e.kind) {
    case PdoEventKind::TpdoMissing:
        what = "missing after SYNC";
        break;
    case PdoEventKind::TpdoSilent:
        what = "silent";
        break;
    case PdoEventKind::TpdoRecovered:
        what = "received again";
        break;
    case PdoEventKind::TpdoTooShort:
        what = "too short";
        break;
    case PdoEventKind::RpdoSendFailed:
        what = "not sent";
        break;
    }
    return fmt::format("node {}: {} (0x{:X}) {}", e.node, pdo_name(e.dir, e.number), e.can_id,
                       what);
}

PdoMaster::PdoMaster(ICanBus& bus, PdoMasterOptions options) : bus_(bus), options_(options) {}

PdoMaster::~PdoMaster() = default;

PdoResult<ProcessImage*> PdoMaster::add_node(NodeId node, std::span<const PdoConfig> pdos) {
    if (!valid_node_id(node)) {
        return pdo_fail(PdoErrc::UnknownNode, fmt::format("node {}: not a valid node-ID", node));
    }
    if (images_[node]) {
        return pdo_fail(PdoErrc::AlreadyConfigured,
                        fmt::format("node {}: PDOs are already configured", node));
    }
    auto image = std::make_unique<ProcessImage>();
    image->node_ = node;
    image->changed_ = &changed_;
    for (const auto& cfg : pdos) {
        if (!cfg.enabled) {
            continue;
        }
        if (image->pdos_.size() >= Slot::kNone) {
            return pdo_fail(PdoErrc::TooManyPdos, fmt::format("node {}: too many PDOs", node));
        }
        if (cfg.total_bits() > kMaxCanPdoBits) {
            return pdo_fail(PdoErrc::LengthExceeded,
                            fmt::format("node {}: {} maps {} bits, more than the {} bits of a "
                                        "CAN frame",
                                        node, cfg.name(), cfg.total_bits(), kMaxCanPdoBits));
        }
        const std::uint32_t id = cfg.can_id_for(node);
        if (id == 0 || (!cfg.comm.extended && id > 0x7FF)) {
            return pdo_fail(PdoErrc::InvalidCommunication,
                            fmt::format("node {}: {} has no usable COB-ID", node, cfg.name()));
        }
        if (cfg.dir == PdoDir::Tpdo) {
            const bool taken = cfg.comm.extended
                                   ? std::any_of(extended_tpdos_.begin(), extended_tpdos_.end(),
                                                 [id](const auto* p) { return p->can_id == id; })
                                   : by_id_[id] != nullptr;
            const bool taken_here =
                std::any_of(image->pdos_.begin(), image->pdos_.end(), [&](const auto& p) {
                    return p.dir == PdoDir::Tpdo && p.can_id == id &&
                           p.extended == cfg.comm.extended;
                });
            if (taken || taken_here) {
                return pdo_fail(PdoErrc::InvalidCommunication,
                                fmt::format("node {}: {} COB-ID 0x{:X} is already used by "
                                            "another TPDO",
                                            node, cfg.name(), id));
            }
        }
        detail::PdoChannel ch;
        ch.config = cfg;
        ch.node = node;
        ch.dir = cfg.dir;
        ch.number = static_cast<std::uint8_t>(cfg.number);
        ch.type = cfg.comm.transmission_type;
        ch.every = is_cyclic_sync(ch.type) ? ch.type : 1;
        ch.sync_div = static_cast<std::uint8_t>(ch.every - 1); // first SYNC sends
        ch.len = static_cast<std::uint8_t>(cfg.byte_length());
        ch.extended = cfg.comm.extended;
        ch.can_id = id;
        ch.inhibit = cfg.comm.inhibit();
        ch.event_period = cfg.comm.event_period();
        image->pdos_.push_back(std::move(ch));
    }
    images_[node] = std::move(image);
    rebuild_lists();
    return images_[node].get();
}

bool PdoMaster::remove_node(NodeId node) {
    if (!valid_node_id(node) || !images_[node]) {
        return false;
    }
    images_[node].reset();
    rebuild_lists();
    return true;
}

ProcessImage* PdoMaster::image(NodeId node) {
    return valid_node_id(node) ? images_[node].get() : nullptr;
}

const ProcessImage* PdoMaster::image(NodeId node) const {
    return valid_node_id(node) ? images_[node].get() : nullptr;
}

void PdoMaster::rebuild_lists() {
    rpdos_.clear();
    tpdos_.clear();
    event_rpdos_.clear();
    timed_tpdos_.clear();
    extended_tpdos_.clear();
    by_id_.fill(nullptr);
    for (auto& image : images_) {
        if (!image) {
            continue;
        }
        for (auto& p : image->pdos_) {
            if (p.dir == PdoDir::Rpdo) {
                rpdos_.push_back(&p);
                if (is_event_driven(p.type)) {
                    event_rpdos_.push_back(&p);
                }
            } else {
                tpdos_.push_back(&p);
                if (is_event_driven(p.type) && p.event_period.count() > 0) {
                    timed_tpdos_.push_back(&p);
                }
                if (p.extended) {
                    extended_tpdos_.push_back(&p);
                } else {
                    by_id_[p.can_id] = &p;
                }
            }
        }
    }
    // Event-driven work needs a tick soon after setup.
    next_timer_ = (event_rpdos_.empty() && timed_tpdos_.empty()) ? kNever : TimePoint{};
}

void PdoMaster::emit(const PdoEvent& e) {
    if (handler_) {
        handler_(e);
    }
}

Frame PdoMaster::frame_of(const detail::PdoChannel& p) {
    Frame f;
    f.id = p.can_id;
    f.flags = p.extended ? std::uint8_t{Frame::kExtended} : std::uint8_t{0};
    f.len = p.len;
    std::memcpy(f.data.data(), p.data.data(), 8);
    return f;
}

void PdoMaster::leaving(detail::PdoChannel& p, TimePoint now) {
    p.dirty = false;
    p.last_tx = now;
    p.sent_once = true;
}

void PdoMaster::sent(detail::PdoChannel& p) {
    ++p.tx_count;
    ++stats_.rpdos_sent;
}

void PdoMaster::send(detail::PdoChannel& p, TimePoint now) {
    const Frame f = frame_of(p);
    leaving(p, now);
    if (auto ok = bus_.send(f); !ok) {
        ++p.send_errors;
        ++stats_.send_errors;
        PdoEvent e;
        e.kind = PdoEventKind::RpdoSendFailed;
        e.node = p.node;
        e.dir = p.dir;
        e.number = p.number;
        e.can_id = p.can_id;
        e.time = now;
        e.error = ok.error();
        emit(e);
        return;
    }
    sent(p);
}

void PdoMaster::queue_send(detail::PdoChannel& p, TimePoint now) {
    if (batch_size_ == batch_.size()) {
        flush_sends(now);
    }
    batch_[batch_size_] = frame_of(p);
    batch_channels_[batch_size_] = &p;
    ++batch_size_;
    leaving(p, now);
}

void PdoMaster::flush_sends(TimePoint now) {
    const std::size_t n = batch_size_;
    if (n == 0) {
        return;
    }
    batch_size_ = 0;
    const std::size_t accepted = bus_.send_many(std::span<const Frame>(batch_.data(), n));
    for (std::size_t i = 0; i < accepted && i < n; ++i) {
        if (batch_channels_[i] != nullptr) {
            sent(*batch_channels_[i]);
        }
    }
    // What the bus would not take, one by one: each refusal with its own error and event.
    for (std::size_t i = accepted; i < n; ++i) {
        if (batch_channels_[i] != nullptr) {
            send(*batch_channels_[i], now);
        } else {
            lead_refused_ = true; // the SYNC: its producer counts the failure
        }
    }
}

void PdoMaster::check_window(detail::PdoChannel& p, std::uint64_t cycle, TimePoint now) {
    if (!p.window_open) {
        p.window_open = true;
        p.window_start = cycle;
        p.received_in_window = false;
        return;
    }
    if (cycle - p.window_start < p.every) {
        return;
    }
    if (!p.received_in_window) {
        ++p.owed;
    }
    // Windows are closed in order and frames arrive in order, so the owed windows are the last
    // `owed` ones: report the oldest once the tolerance is used up.
    while (p.owed > options_.missing_tolerance) {
        const std::uint64_t oldest = p.window_start - std::uint64_t{p.every} * (p.owed - 1);
        --p.owed;
        ++p.missing;
        ++stats_.tpdos_missing;
        p.silent = true;
        PdoEvent e;
        e.kind = PdoEventKind::TpdoMissing;
        e.node = p.node;
        e.dir = p.dir;
        e.number = p.number;
        e.can_id = p.can_id;
        e.transmission_type = p.type;
        e.sync = oldest;
        e.time = now;
        emit(e);
    }
    p.window_start = cycle;
    p.received_in_window = false;
}

bool PdoMaster::on_sync(std::uint64_t cycle, TimePoint now, const Frame& sync) {
    flush_sends(now); // nothing is pending between cycles; keeps the SYNC first regardless
    batch_[0] = sync;
    batch_channels_[0] = nullptr;
    batch_size_ = 1;
    lead_refused_ = false;
    on_sync(cycle, now);
    return !lead_refused_;
}

void PdoMaster::on_sync(std::uint64_t cycle, TimePoint now) {
    ++stats_.syncs;
    for (detail::PdoChannel* p : tpdos_) {
        if (is_cyclic_sync(p->type)) {
            check_window(*p, cycle, now);
        }
    }
    for (detail::PdoChannel* p : rpdos_) {
        if (p->type == transmission::kSyncAcyclic) {
            if (p->dirty) {
                queue_send(*p, now);
            }
        } else if (is_cyclic_sync(p->type)) {
            if (++p->sync_div >= p->every) {
                p->sync_div = 0;
                queue_send(*p, now);
            }
        }
    }
    flush_sends(now);
}

bool PdoMaster::on_frame(const Frame& frame, TimePoint now) {
    if (frame.error()) {
        return false;
    }
    detail::PdoChannel* p = nullptr;
    if (!frame.extended()) {
        if (frame.id < by_id_.size()) {
            p = by_id_[frame.id];
        }
    } else {
        for (auto* c : extended_tpdos_) {
            if (c->can_id == frame.id) {
                p = c;
                break;
            }
        }
    }
    if (p == nullptr) {
        return false;
    }
    if (frame.rtr()) {
        return true; // a request for this TPDO (ours or another master's); the node answers it
    }
    if (frame.len < p->len) {
        ++p->length_errors;
        ++stats_.tpdos_too_short;
        PdoEvent e;
        e.kind = PdoEventKind::TpdoTooShort;
        e.node = p->node;
        e.dir = p->dir;
        e.number = p->number;
        e.can_id = p->can_id;
        e.got_len = frame.len;
        e.want_len = p->len;
        e.time = now;
        emit(e);
        return true;
    }
    std::memcpy(p->data.data(), frame.data.data(), 8);
    p->last_rx = now;
    ++p->rx_count;
    ++stats_.tpdos_received;
    if (p->owed > 0) {
        --p->owed; // the late answer to an already closed window
        ++stats_.tpdos_late;
    } else {
        p->received_in_window = true;
    }
    if (p->silent) {
        p->silent = false;
        PdoEvent e;
        e.kind = PdoEventKind::TpdoRecovered;
        e.node = p->node;
        e.dir = p->dir;
        e.number = p->number;
        e.can_id = p->can_id;
        e.time = now;
        emit(e);
    }
    return true;
}

void PdoMaster::flush(TimePoint now) {
    changed_ = false;
    TimePoint next = kNever;
    for (detail::PdoChannel* p : event_rpdos_) {
        const bool inhibited = p->sent_once && now < p->last_tx + p->inhibit;
        const bool timer_due =
            p->event_period.count() > 0 && (!p->sent_once || now >= p->last_tx + p->event_period);
        if ((p->dirty && !inhibited) || timer_due) {
            send(*p, now);
        }
        if (p->dirty) {
            next = std::min(next, p->last_tx + p->inhibit);
        }
        if (p->event_period.count() > 0) {
            next = std::min(next, p->last_tx + p->event_period);
        }
    }
    for (detail::PdoChannel* p : timed_tpdos_) {
        if (p->watch_from == TimePoint{}) {
            p->watch_from = now;
        }
        const TimePoint ref = p->rx_count > 0 ? p->last_rx : p->watch_from;
        const auto limit =
            std::chrono::duration_cast<Duration>(p->event_period * options_.event_timeout_factor);
        if (!p->silent && now >= ref + limit) {
            p->silent = true;
            ++p->missing;
            ++stats_.tpdos_missing;
            PdoEvent e;
            e.kind = PdoEventKind::TpdoSilent;
            e.node = p->node;
            e.dir = p->dir;
            e.number = p->number;
            e.can_id = p->can_id;
            e.transmission_type = p->type;
            e.silent_for = now - ref;
            e.event_timer = p->event_period;
            e.time = now;
            emit(e);
        }
        if (!p->silent) {
            next = std::min(next, ref + limit);
        } else {
            // Re-arm once it is heard again (on_frame clears `silent`); poll at the timer rate.
            next = std::min(next, now + p->event_period);
        }
    }
    next_timer_ = next;
}

VoidResult PdoMaster::request(NodeId node, unsigned tpdo_number) {
    ProcessImage* img = image(node);
    if (img == nullptr) {
        return fail(PdoErrc::UnknownNode);
    }
    for (auto& p : img->pdos_) {
        if (p.dir == PdoDir::Tpdo && p.number == tpdo_number) {
            Frame f = Frame::make_rtr(p.can_id, p.len);
            if (p.extended) {
                f.flags = static_cast<std::uint8_t>(f.flags | Frame::kExtended);
            }
            return bus_.send(f);
        }
    }
    return fail(PdoErrc::UnknownObject);
}

TimePoint PdoMaster::next_deadline() const {
    if (changed_ && !event_rpdos_.empty()) {
        return TimePoint{};
    }
    return next_timer_;
}

void PdoMaster::on_tick(TimePoint now) {
    flush(now);
}

} // namespace codrive::pdo
