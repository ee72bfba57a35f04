// SPDX-License-Identifier: Apache-2.0
// Node supervision: routes frames to the services, turns their events into master events,
// boots nodes and brings rebooted nodes back to the state they had.
#include <codrive/master/master.hpp>

#include <fmt/format.h>

#include <algorithm>

namespace codrive::master {

std::string_view to_string(MasterEventKind k) {
    switch (k) {
    case MasterEventKind::BootCompleted:
        return "boot completed";
    case MasterEventKind::BootFailed:
        return "boot failed";
    case MasterEventKind::NodeRebooted:
        return "node rebooted";
    case MasterEventKind::Recovered:
        return "recovered";
    case MasterEventKind::RecoveryFailed:
        return "recovery failed";
    case MasterEventKind::HeartbeatLost:
        return "heartbeat lost";
    case MasterEventKind::HeartbeatRecovered:
        return "heartbeat recovered";
    case MasterEventKind::GuardingError:
        return "node guarding error";
    case MasterEventKind::StateChanged:
        return "state changed";
    case MasterEventKind::Emcy:
        return "EMCY";
    case MasterEventKind::EmcyReset:
        return "EMCY reset";
    case MasterEventKind::BusEvent:
        return "bus event";
    }
    return "?";
}

Master::Master(ICanBus& bus, const IClock& clock, MasterConfig config)
    : bus_(bus), clock_(clock), config_(std::move(config)), sdo_(bus, clock, config_.sdo),
      nmt_(bus), guarding_(bus) {
    bus_.set_frame_handler([this](const Frame& f, TimePoint t) { on_frame(f, t); });
    bus_.set_event_handler([this](const BusEvent& e) { on_bus_event(e); });
    heartbeats_.set_handler([this](const nmt::ErrorControlEvent& e) { on_error_control(e); });
    guarding_.set_handler([this](const nmt::ErrorControlEvent& e) { on_error_control(e); });
    emcy_.set_handler([this](const emcy::EmcyEvent& e) { on_emcy(e); });
    if (config_.node_id != 0 && config_.heartbeat_period.count() > 0) {
        producer_ = std::make_unique<nmt::HeartbeatProducer>(bus_, config_.node_id);
        producer_->set_state(nmt::NmtState::Operational);
        producer_->set_period(config_.heartbeat_period, clock_.now());
    }
}

Master::~Master() {
    bus_.set_frame_handler(nullptr);
    bus_.set_event_handler(nullptr);
}

RemoteNode& Master::add_node(NodeConfig config) {
    const NodeId id = config.id;
    nodes_[id].reset(new RemoteNode(std::move(config), sdo_.client(id)));
    return *nodes_[id];
}

RemoteNode* Master::node(NodeId id) {
    return valid_node_id(id) ? nodes_[id].get() : nullptr;
}

std::vector<RemoteNode*> Master::nodes() {
    std::vector<RemoteNode*> out;
    for (auto& n : nodes_) {
        if (n) {
            out.push_back(n.get());
        }
    }
    return out;
}

void Master::emit(NodeId node, MasterEventKind kind, std::string text) {
    if (handler_) {
        handler_(MasterEvent{node, kind, clock_.now(), std::move(text)});
    }
}

void Master::start_monitoring(RemoteNode& n) {
    const NodeConfig& c = n.config_;
    if (c.heartbeat_producer.count() > 0) {
        (void)heartbeats_.configure(c.id, c.consumer_time());
        n.first_heartbeat_due_ = clock_.now() + c.consumer_time();
    } else if (c.guard_time.count() > 0 && c.life_time_factor > 0) {
        (void)guarding_.add(c.id, c.guard_time, c.life_time_factor, clock_.now());
    }
}

void Master::boot(NodeId id, std::function<void(const BootReport&)> done) {
    RemoteNode* n = node(id);
    if (n == nullptr) {
        BootReport r;
        r.node = id;
        r.steps.push_back(
            BootStep{"configuration", false, fmt::format("node {}: not configured", id), {}});
        if (done) {
            done(r);
        }
        return;
    }
    const bool recovery = n->booted_ || n->last_boot_.has_value();
    const bool start = recovery && n->wanted_ != nmt::NmtState::Unknown
                           ? n->wanted_ == nmt::NmtState::Operational
                           : n->config_.start;
    if (n->boot_) {
        retired_.push_back(std::move(n->boot_)); // it may be calling us right now
    }
    n->boot_ = std::make_unique<BootSequence>(n->config_, *n->sdo_, nmt_, clock_);
    n->boot_->run(
        [this, n, start, done = std::move(done)](const BootReport& report) {
            n->last_boot_ = report;
            n->booted_ = report.ok;
            const BootReport& r = *n->last_boot_;
            if (r.ok) {
                n->wanted_ = start ? nmt::NmtState::Operational : nmt::NmtState::PreOperational;
                n->state_ = n->wanted_;
                start_monitoring(*n);
                emit(n->id(),
                     r.recovery ? MasterEventKind::Recovered : MasterEventKind::BootCompleted,
                     r.recovery
                         ? fmt::format("node {}: recovered after reboot: boot-up OK in {:.1f} "
                                       "ms, back to {}",
                                       n->id(), to_ms(r.duration), nmt::to_string(n->wanted_))
                         : fmt::format("node {}: boot-up OK in {:.1f} ms ({} steps)", n->id(),
                                       to_ms(r.duration), r.steps.size()));
            } else {
                emit(n->id(),
                     r.recovery ? MasterEventKind::RecoveryFailed : MasterEventKind::BootFailed,
                     r.error());
            }
            if (done) {
                done(r);
            }
        },
        start, recovery);
}

void Master::boot_all(std::function<void(const std::vector<BootReport>&)> done) {
    auto all = nodes();
    if (all.empty()) {
        if (done) {
            done({});
        }
        return;
    }
    struct Pending {
        std::size_t left;
        std::vector<BootReport> reports;
        std::function<void(const std::vector<BootReport>&)> done;
    };
    auto pending = std::make_shared<Pending>(Pending{all.size(), {}, std::move(done)});
    for (RemoteNode* n : all) {
        boot(n->id(), [pending](const BootReport& r) {
            pending->reports.push_back(r);
            if (--pending->left == 0 && pending->done) {
                std::sort(pending->reports.begin(), pending->reports.end(),
                          [](const BootReport& a, const BootReport& b) { return a.node < b.node; });
                pending->done(pending->reports);
            }
        });
    }
}

void Master::recover(RemoteNode& n) {
    ++n.reboots_;
    emit(n.id(), MasterEventKind::NodeRebooted,
         fmt::format("node {}: rebooted on its own (boot-up message while {}); re-running boot-up",
                     n.id(), nmt::to_string(n.wanted_)));
    emcy_.clear(n.id());
    boot(n.id());
}

void Master::on_error_control(const nmt::ErrorControlEvent& e) {
    RemoteNode* n = node(e.node);
    if (n != nullptr && e.state != nmt::NmtState::Unknown) {
        n->state_ = e.state;
    }
    using K = nmt::ErrorControlEventKind;
    switch (e.kind) {
    case K::BootUp:
    case K::UnexpectedBootUp:
        if (n != nullptr && config_.auto_recover && !n->booting() &&
            (n->booted_ || n->last_boot_.has_value())) {
            recover(*n);
        } else {
            emit(e.node, MasterEventKind::StateChanged, e.text);
        }
        break;
    case K::HeartbeatLost:
        if (n != nullptr) {
            n->heartbeat_lost_ = true;
        }
        emit(e.node, MasterEventKind::HeartbeatLost, e.text);
        break;
    case K::HeartbeatRecovered:
    case K::GuardRecovered:
        if (n != nullptr) {
            n->heartbeat_lost_ = false;
        }
        emit(e.node, MasterEventKind::HeartbeatRecovered, e.text);
        break;
    case K::GuardTimeout:
    case K::GuardToggleError:
        if (n != nullptr && e.kind == K::GuardTimeout) {
            n->heartbeat_lost_ = true;
        }
        emit(e.node, MasterEventKind::GuardingError, e.text);
        break;
    case K::StateChanged:
        emit(e.node, MasterEventKind::StateChanged, e.text);
        break;
    case K::LifeGuardLost:
    case K::LifeGuardRecovered:
        break; // slave-side events; a master does not produce them
    }
}

void Master::on_emcy(const emcy::EmcyEvent& e) {
    if (RemoteNode* n = node(e.message.node); n != nullptr) {
        n->last_emcy_ = e;
    }
    emit(e.message.node, e.reset ? MasterEventKind::EmcyReset : MasterEventKind::Emcy, e.text);
}

void Master::on_bus_event(const BusEvent& event) {
    emit(0, MasterEventKind::BusEvent, fmt::format("{}: {}", bus_.name(), to_string(event)));
}

void Master::on_frame(const Frame& frame, TimePoint now) {
    if (frame.extended() || frame.error()) {
        for (auto& l : listeners_) {
            l(frame, now);
        }
        return;
    }
    const CobInfo info = classify_cob_id(frame.id);
    switch (info.type) {
    case CobType::SdoTx:
        sdo_.on_frame(frame, now);
        return;
    case CobType::Heartbeat:
        if (RemoteNode* n = node(info.node);
            n != nullptr && n->booting() && frame.len >= 1 && !frame.rtr()) {
            // Before the SDO client sees a boot-up message: the boot sequence must know the node
            // rebooted when the request in flight fails because of it.
            if (auto s = nmt::state_from_byte(frame.data[0]); s) {
                n->boot_->on_node_state(*s, now);
            }
        }
        // Boot-up also ends SDO transfers to that node; heartbeats feed the state table.
        sdo_.on_frame(frame, now);
        nmt_.on_frame(frame, now);
        heartbeats_.on_frame(frame, now);
        guarding_.on_frame(frame, now);
        if (RemoteNode* n = node(info.node); n != nullptr && frame.len >= 1 && !frame.rtr()) {
            if (frame.data[0] != 0) { // a heartbeat, not a boot-up
                n->first_heartbeat_due_ = kNever;
                if (n->lost_before_first_heartbeat_) {
                    n->lost_before_first_heartbeat_ = false;
                    n->heartbeat_lost_ = false;
                    emit(n->id(), MasterEventKind::HeartbeatRecovered,
                         fmt::format("node {}: heartbeat received again", n->id()));
                }
            }
            if (auto s = nmt::state_from_byte(frame.data[0]); s) {
                n->state_ = *s == nmt::NmtState::BootUp ? nmt::NmtState::PreOperational : *s;
            }
        }
        break;
    case CobType::Emcy:
        emcy_.on_frame(frame, now);
        break;
    default:
        break;
    }
    for (auto& l : listeners_) {
        l(frame, now);
    }
}

TimePoint Master::next_deadline() const {
    TimePoint t =
        std::min({sdo_.next_deadline(), heartbeats_.next_deadline(), guarding_.next_deadline()});
    if (producer_) {
        t = std::min(t, producer_->next_deadline());
    }
    if (!retired_.empty()) {
        t = std::min(t, clock_.now());
    }
    for (const auto& n : nodes_) {
        if (n) {
            t = std::min(t, n->first_heartbeat_due_);
            if (n->booting()) {
                t = std::min(t, n->boot_->next_deadline());
            }
        }
    }
    return t;
}

void Master::on_tick(TimePoint now) {
    retired_.clear();
    for (auto& n : nodes_) {
        if (n && n->booting() && n->boot_->next_deadline() <= now) {
            n->boot_->on_tick(now); // may finish the boot: runs the completion callback
        }
    }
    for (auto& n : nodes_) {
        if (n && n->first_heartbeat_due_ <= now) {
            n->first_heartbeat_due_ = kNever;
            if (!n->booting()) {
                n->heartbeat_lost_ = true;
                n->lost_before_first_heartbeat_ = true;
                emit(n->id(), MasterEventKind::HeartbeatLost,
                     fmt::format("node {}: heartbeat lost: none received within {} ms after "
                                 "boot-up (producer time {} ms written to 1017h)",
                                 n->id(), n->config_.consumer_time().count(),
                                 n->config_.heartbeat_producer.count()));
            }
        }
    }
    if (sdo_.next_deadline() <= now) {
        sdo_.on_tick(now);
    }
    if (heartbeats_.next_deadline() <= now) {
        heartbeats_.on_tick(now);
    }
    if (guarding_.next_deadline() <= now) {
        guarding_.on_tick(now);
    }
    if (producer_ && producer_->next_deadline() <= now) {
        producer_->on_tick(now);
    }
}

} // namespace codrive::master
