// SPDX-License-Identifier: Apache-2.0
// A simulated CANopen drive: services around the object dictionary and the CiA 402 axes.
#include <codrive/sim/sim_device.hpp>

#include "error_history.hpp"
#include "parameter_store.hpp"

#include <codrive/emcy/producer.hpp>
#include <codrive/nmt/heartbeat_consumer.hpp>
#include <codrive/nmt/heartbeat_producer.hpp>
#include <codrive/nmt/node_guarding.hpp>
#include <codrive/nmt/slave.hpp>
#include <codrive/pdo/device.hpp>
#include <codrive/pdo/quirks.hpp>
#include <codrive/sdo/server.hpp>
#include <codrive/sync/consumer.hpp>

#include <fmt/format.h>

#include <algorithm>

namespace codrive::sim {

pdo::PdoQuirks sim_pdo_quirks(const SimProfile& p); // sim_device_objects.cpp

namespace {

using WriteResult = tl::expected<void, SdoAbort>;

} // namespace

SimDevice::SimDevice(ICanBus& bus, SimDeviceConfig config) : bus_(bus), config_(config) {
    assemble();
    // The node-ID the command line gave is the one the drive was commissioned to (DS-BVS
    // §6.2.74: 5000h, default 1): a saved value, so a restore of the defaults brings back 1.
    const drives::Commissioning& com = config_.profile->drive->commissioning;
    if (com.node_id_object != 0 && od_.set<std::uint8_t>(com.node_id_object, 0, config_.node)) {
        store_->keep(com.node_id_object, 0);
    }
    if (com.bit_rate_object != 0) {
        bit_rate_code_ = od_.get<std::uint8_t>(com.bit_rate_object, 0).value_or(0);
    }
}

void SimDevice::assemble() {
    const SimProfile& p = *config_.profile;
    store_ = std::make_unique<ParameterStore>(od_, *p.drive);
    unsigned n = config_.axes == 0 ? p.default_axes : config_.axes;
    n = std::clamp(n, 1U, p.max_axes());
    for (unsigned a = 0; a < n; ++a) {
        axes_.push_back(std::make_unique<DriveCore>(od_, p, a, config_.machine));
        axes_.back()->set_event_handler([this](const AxisEvent& e) { on_axis_event(e); });
    }
    build_objects();
    store_->snapshot_factory();

    sdo::ServerConfig sc;
    sc.node = config_.node;
    server_ = std::make_unique<sdo::SdoServer>(od_, bus_, sc);
    nmt_ = std::make_unique<nmt::NmtSlave>(config_.node);
    heartbeat_ = std::make_unique<nmt::HeartbeatProducer>(bus_, config_.node);
    consumer_ = std::make_unique<nmt::HeartbeatConsumer>();
    if (p.node_guarding) {
        guarding_ = std::make_unique<nmt::NodeGuardingResponder>(bus_, config_.node);
    }
    sync_ = std::make_unique<sync::SyncConsumer>();
    emcy_ = std::make_unique<emcy::EmcyProducer>(bus_, config_.node);
    pdo::DevicePdoOptions po;
    po.node = config_.node;
    po.quirks = sim_pdo_quirks(p);
    po.sync_id = 0;             // SYNC arrives through the SYNC consumer's hook
    po.write_through_od = true; // controlword writes run the state machine at once
    pdo_ = std::make_unique<pdo::DevicePdo>(od_, bus_, po);
    install_hooks();
}

SimDevice::~SimDevice() = default;

nmt::NmtState SimDevice::nmt_state() const {
    return nmt_->state();
}

std::string SimDevice::summary() const {
    return fmt::format("node {} {} ({} {})", config_.node, config_.profile->name(), axes_.size(),
                       axes_.size() == 1 ? "axis" : "axes");
}

void SimDevice::log(const std::string& text) {
    if (log_) {
        log_(text);
    }
}

void SimDevice::install_hooks() {
    const SimProfile& p = *config_.profile;
    nmt_->set_state_handler([this](nmt::NmtState, nmt::NmtState to) {
        heartbeat_->set_state(to);
        if (guarding_) {
            guarding_->set_state(to);
        }
        pdo_->set_operational(to == nmt::NmtState::Operational, now_);
        log(fmt::format("node {}: NMT {}", config_.node, nmt::to_string(to)));
    });
    nmt_->set_reset_handler([this](nmt::NmtCommand c) {
        // Handled after the frame: restore parameters, then boot-up (CiA 301 §7.3.2.2).
        store_->load(c == nmt::NmtCommand::ResetCommunication);
        if (c == nmt::NmtCommand::ResetNode && take_commissioning()) {
            return; // boots at its new node-ID on the next tick
        }
        if (c == nmt::NmtCommand::ResetNode) {
            for (auto& a : axes_) {
                a->power_on();
            }
            errors_.reset();
        }
        start(now_);
    });
    consumer_->set_handler([this](const nmt::ErrorControlEvent& e) {
        if (e.kind == nmt::ErrorControlEventKind::HeartbeatLost) {
            log(fmt::format("node {}: {}", config_.node, e.text));
            heartbeat_lost();
        } else if (e.kind == nmt::ErrorControlEventKind::HeartbeatRecovered) {
            heartbeat_recovered();
        }
    });
    if (guarding_) {
        guarding_->set_handler([this](const nmt::ErrorControlEvent& e) {
            if (e.kind == nmt::ErrorControlEventKind::LifeGuardLost) {
                log(fmt::format("node {}: {}", config_.node, e.text));
                heartbeat_lost();
            }
        });
    }
    sync_->set_hook([this](const sync::SyncReception& r) { pdo_->on_sync(r.counter, r.time); });

    od_.on_write(
        0x1017,
        [this](std::uint16_t, std::uint8_t, std::span<const std::uint8_t> d) -> WriteResult {
            heartbeat_->set_period(milliseconds(get_le<std::uint16_t>(d.data())), now_);
            return {};
        });
    od_.on_write(
        0x1016,
        [this](std::uint16_t, std::uint8_t sub, std::span<const std::uint8_t> d) -> WriteResult {
            if (sub != 1 || d.size() < 4) {
                return {};
            }
            const auto v = get_le<std::uint32_t>(d.data());
            const auto producer = static_cast<NodeId>((v >> 16) & 0xFF);
            if ((v >> 24) != 0) {
                return tl::unexpected(SdoAbort::InvalidValue);
            }
            if (consumer_node_ != 0) {
                consumer_->remove(consumer_node_);
            }
            consumer_node_ = 0;
            if (producer != 0 && (v & 0xFFFF) != 0) {
                if (!consumer_->configure_from_1016(v)) {
                    return tl::unexpected(SdoAbort::InvalidValue);
                }
                consumer_node_ = producer;
            }
            return {};
        });
    od_.on_write(
        0x1014,
        [this](std::uint16_t, std::uint8_t, std::span<const std::uint8_t> d) -> WriteResult {
            const auto v = get_le<std::uint32_t>(d.data());
            emcy_enabled_ = (v & cob::kInvalidBit) == 0;
            emcy_->set_cob_id(v & Frame::kStdMask);
            return {};
        });
    if (guarding_) {
        const auto guard = [this](std::uint16_t index, std::uint8_t,
                                  std::span<const std::uint8_t> d) -> WriteResult {
            auto gt = od_.get<std::uint16_t>(0x100C, 0).value_or(0);
            auto lf = od_.get<std::uint8_t>(0x100D, 0).value_or(0);
            if (index == 0x100C) {
                gt = get_le<std::uint16_t>(d.data());
            } else {
                lf = d[0];
            }
            guarding_->set_life_guarding(milliseconds(gt), lf);
            return {};
        };
        od_.on_write(0x100C, guard);
        od_.on_write(0x100D, guard);
    }
    if (p.has_sync_objects) {
        const auto sync = [this](std::uint16_t index, std::uint8_t,
                                 std::span<const std::uint8_t> d) -> WriteResult {
            sync::SyncConsumerConfig sc;
            sc.node = config_.node;
            std::uint32_t id = od_.get<std::uint32_t>(0x1005, 0).value_or(cob::kSync);
            std::uint32_t period = od_.get<std::uint32_t>(0x1006, 0).value_or(0);
            (index == 0x1005 ? id : period) = get_le<std::uint32_t>(d.data());
            if (index == 0x1005 && (id & (cob::kFrameBit | cob::kRtrBit)) != 0) {
                return tl::unexpected(SdoAbort::InvalidValue); // 11-bit consumer only
            }
            sc.cob_id = id & Frame::kStdMask;
            sc.cycle_period = microseconds(period);
            if (!sync_->configure(sc)) {
                return tl::unexpected(SdoAbort::InvalidValue);
            }
            return {};
        };
        od_.on_write(0x1005, sync);
        od_.on_write(0x1006, sync);
    }
    store_->install_hooks(
        [this]() -> WriteResult {
            if (!config_.profile->drive->quirks.restore_needs_preop_power_disabled) {
                return {};
            }
            // DS-BVS §6.2.7: NMT pre-operational and every axis power disabled (CiA 402: not
            // ready to switch on, switch on disabled or ready to switch on).
            const bool power_disabled = std::all_of(axes_.begin(), axes_.end(), [](auto& a) {
                const auto st = a->state();
                return st == drives::cia402::State::NotReadyToSwitchOn ||
                       st == drives::cia402::State::SwitchOnDisabled ||
                       st == drives::cia402::State::ReadyToSwitchOn;
            });
            if (nmt_->state() != nmt::NmtState::PreOperational || !power_disabled) {
                return tl::unexpected(SdoAbort::DataTransferState);
            }
            return {};
        },
        nullptr);
    for (unsigned a = 0; a < axes_.size(); ++a) {
        const auto index = static_cast<std::uint16_t>(kControlObject + a);
        od_.on_write(index,
                     [this, a](std::uint16_t, std::uint8_t sub,
                               std::span<const std::uint8_t> d) -> WriteResult {
                         const bool on = !d.empty() && d[0] != 0;
                         switch (sub) {
                         case kControlSto:
                             axes_[a]->set_sto(on);
                             break;
                         case kControlOverCurrent:
                             if (on) {
                                 inject(a, FaultKind::OverCurrent, now_);
                             }
                             break;
                         case kControlFollowingError:
                             if (on) {
                                 inject(a, FaultKind::FollowingError, now_);
                             }
                             break;
                         case kControlHeartbeatLoss:
                             if (on) {
                                 inject(a, FaultKind::HeartbeatLoss, now_);
                             }
                             break;
                         case kControlNodeReset:
                             // After the SDO response has gone out (next tick).
                             reset_pending_ = on;
                             break;
                         case kControlProbe1Input:
                         case kControlProbe2Input:
                             if (auto* tp = axes_[a]->touch_probe()) {
                                 const unsigned probe = sub == kControlProbe1Input ? 1 : 2;
                                 tp->set_trigger_position(probe, std::nullopt);
                                 tp->set_input(probe, on, axes_[a]->position_actual());
                             }
                             break;
                         case kControlProbe1At:
                         case kControlProbe2At:
                             if (auto* tp = axes_[a]->touch_probe(); tp && d.size() >= 4) {
                                 tp->set_trigger_position(sub == kControlProbe1At ? 1 : 2,
                                                          get_le<std::int32_t>(d.data()));
                             }
                             break;
                         default:
                             break;
                         }
                         return {};
                     });
        od_.on_read(index, [this, a](std::uint16_t, std::uint8_t sub, SubObject& s) {
            if (sub == kControlProbe1Input || sub == kControlProbe2Input) {
                const auto* tp = axes_[a]->touch_probe();
                const bool level = tp != nullptr && tp->input(sub == kControlProbe1Input ? 1 : 2);
                s.value = *Value::from_uint(DataType::Unsigned8, level ? 1 : 0);
                return;
            }
            const std::uint8_t v = sub == kControlSto && axes_[a]->sto() ? 1 : 0;
            if (sub != 0 && sub <= kControlNodeReset) {
                s.value = *Value::from_uint(DataType::Unsigned8, v);
            }
        });
    }
}

tl::expected<void, SdoAbort> SimDevice::store_parameter(std::uint16_t index, std::uint8_t subindex,
                                                        std::span<const std::uint8_t> data) {
    auto r = od_.write(index, subindex, data, true);
    if (r) {
        store_->keep(index, subindex);
    }
    return r;
}

void SimDevice::apply_comm_parameters(TimePoint now) {
    heartbeat_->set_period(milliseconds(od_.get<std::uint16_t>(0x1017, 0).value_or(0)), now);
    const auto emcy_id = od_.get<std::uint32_t>(0x1014, 0).value_or(cob::emcy(config_.node));
    emcy_enabled_ = (emcy_id & cob::kInvalidBit) == 0;
    emcy_->set_cob_id(emcy_id & Frame::kStdMask);
    if (consumer_node_ != 0) {
        consumer_->remove(consumer_node_);
        consumer_node_ = 0;
    }
    const auto hb = od_.get<std::uint32_t>(0x1016, 1).value_or(0);
    if (((hb >> 16) & 0xFF) != 0 && (hb & 0xFFFF) != 0 && consumer_->configure_from_1016(hb)) {
        consumer_node_ = static_cast<std::uint8_t>((hb >> 16) & 0xFF);
    }
    sync::SyncConsumerConfig sc;
    sc.node = config_.node;
    sc.cob_id = od_.get<std::uint32_t>(0x1005, 0).value_or(cob::kSync) & Frame::kStdMask;
    sc.cycle_period = microseconds(od_.get<std::uint32_t>(0x1006, 0).value_or(0));
    (void)sync_->configure(sc);
    if (guarding_) {
        guarding_->reset_toggle();
        guarding_->set_life_guarding(milliseconds(od_.get<std::uint16_t>(0x100C, 0).value_or(0)),
                                     od_.get<std::uint8_t>(0x100D, 0).value_or(0));
    }
    pdo_->reload();
}

void SimDevice::start(TimePoint now) {
    now_ = now;
    started_ = true;
    apply_comm_parameters(now);
    // Boot-up (CiA 301 §7.2.8.3.3): one frame 700h+node, data 00h, then pre-operational.
    (void)heartbeat_->send_boot_up();
    ++stats_.boot_ups;
    nmt_->boot_up();
    heartbeat_->set_state(nmt_->state());
    if (next_step_ == kNever) {
        next_step_ = now + config_.step;
    }
    log(fmt::format("node {}: boot-up", config_.node));
}

void SimDevice::reset_node(TimePoint now) {
    now_ = std::max(now_, now);
    // Exactly what an NMT reset node command does (the reset handler restores and boots).
    const Frame f = Frame::make(
        cob::kNmt, {static_cast<std::uint8_t>(nmt::NmtCommand::ResetNode), config_.node});
    if (started_) {
        nmt_->on_frame(f, now);
    }
}

void SimDevice::on_frame(const Frame& frame, TimePoint now) {
    now_ = std::max(now_, now);
    if (!started_ || frame.error()) {
        return;
    }
    if (frame.id == cob::kNmt && !frame.extended()) {
        nmt_->on_frame(frame, now);
        return;
    }
    const bool sdo_ok = nmt_->sdo_allowed();
    if (sdo_ok && server_->on_frame(frame, now)) {
        return;
    }
    consumer_->on_frame(frame, now);
    if (guarding_) {
        guarding_->on_frame(frame, now);
    }
    if (nmt_->state() != nmt::NmtState::Stopped) {
        sync_->on_frame(frame, now);
        pdo_->on_frame(frame, now);
    }
}

TimePoint SimDevice::next_deadline() const {
    if (!started_) {
        return kNever;
    }
    TimePoint t = next_step_;
    if (reset_pending_ || restart_as_) {
        t = now_;
    }
    for (const ITimed* s :
         std::initializer_list<const ITimed*>{server_.get(), heartbeat_.get(), consumer_.get(),
                                              sync_.get(), emcy_.get(), pdo_.get()}) {
        t = std::min(t, s->next_deadline());
    }
    if (guarding_) {
        t = std::min(t, guarding_->next_deadline());
    }
    return t;
}

void SimDevice::on_tick(TimePoint now) {
    now_ = std::max(now_, now);
    if (!started_) {
        return;
    }
    if (restart_as_) {
        const NodeId node = *restart_as_;
        restart_as_.reset();
        restart_as(node, now);
        return;
    }
    if (reset_pending_) {
        reset_pending_ = false;
        log(fmt::format("node {}: reset node (simulation control)", config_.node));
        reset_node(now);
    }
    // Motion: fixed steps; a long stall (debugger, overloaded host) is not replayed.
    if (next_step_ != kNever && now >= next_step_) {
        if (now - next_step_ > config_.step * 100) {
            next_step_ = now;
        }
        const double dt = std::chrono::duration<double>(config_.step).count();
        while (next_step_ <= now) {
            for (auto& a : axes_) {
                a->step(dt);
            }
            ++stats_.steps;
            next_step_ += config_.step;
        }
        pdo_->notify_changed();
    }
    for (ITimed* s :
         std::initializer_list<ITimed*>{server_.get(), heartbeat_.get(), consumer_.get(),
                                        sync_.get(), emcy_.get(), pdo_.get()}) {
        if (s->next_deadline() <= now) {
            s->on_tick(now);
        }
    }
    if (guarding_ && guarding_->next_deadline() <= now) {
        guarding_->on_tick(now);
    }
}

bool SimDevice::take_commissioning() {
    // DS-BVS §6.2.74/§6.2.76: node-ID and bit rate take effect at a restart.
    const drives::Commissioning& com = config_.profile->drive->commissioning;
    if (com.bit_rate_object != 0) {
        const auto code = od_.get<std::uint8_t>(com.bit_rate_object, 0).value_or(bit_rate_code_);
        if (code != bit_rate_code_) {
            bit_rate_code_ = code;
            unsigned kbit = 0;
            for (const drives::BitRateCode& b : com.bit_rates) {
                kbit = b.code == code ? b.kbit : kbit;
            }
            // A virtual CAN bus has no bit rate: the change is recorded and reported only.
            log(fmt::format("node {}: CAN bit rate now {} kbit/s (5002h = {}; recorded only, "
                            "the virtual bus has no bit rate)",
                            config_.node, kbit, code));
        }
    }
    if (com.node_id_object == 0) {
        return false;
    }
    const auto id = od_.get<std::uint8_t>(com.node_id_object, 0).value_or(config_.node);
    if (id == config_.node || !valid_node_id(id)) {
        return false;
    }
    restart_as_ = id;
    return true;
}

void SimDevice::restart_as(NodeId node, TimePoint now) {
    // A restart at a new node-ID: a fresh dictionary and services built for `node` (COB-IDs
    // of the predefined connection set follow it), the same non-volatile memory.
    log(fmt::format("node {}: restarting as node {}", config_.node, node));
    const auto saved = store_->changes();
    pdo_.reset();
    emcy_.reset();
    sync_.reset();
    guarding_.reset();
    consumer_.reset();
    heartbeat_.reset();
    nmt_.reset();
    server_.reset();
    axes_.clear();
    od_ = ObjectDictionary{};
    consumer_node_ = 0;
    config_.node = node;
    assemble();
    errors_.reset();
    store_->adopt(saved);
    store_->load(false);
    start(now);
}

void SimDevice::inject(unsigned axis, FaultKind kind, TimePoint now) {
    now_ = std::max(now_, now);
    log(fmt::format("node {}: inject {} on axis {}", config_.node, to_string(kind), axis + 1));
    switch (kind) {
    case FaultKind::NodeReset:
        reset_node(now);
        return;
    case FaultKind::HeartbeatLoss:
        heartbeat_lost();
        return;
    default:
        if (axis < axes_.size()) {
            axes_[axis]->inject(kind);
        }
        return;
    }
}

void SimDevice::heartbeat_lost() {
    const SimProfile& p = *config_.profile;
    if (p.heartbeat_loss_is_fault) {
        // AKD2G: F7002 "Fieldbus Heartbeat lost" (EMCY 8130h) faults the axes.
        for (auto& a : axes_) {
            a->raise_fault(p.code_for(FaultKind::HeartbeatLoss));
        }
        return;
    }
    // DS-BVS: EMCY 8130h with 1001h bit 4, NMT reaction 1029h:01, drive reaction 6007h.
    const FaultCode lost = p.code_for(FaultKind::HeartbeatLoss);
    log(fmt::format("node {}: fault 0x{:04X} {}", config_.node, lost.emcy, lost.text));
    send_emcy(errors_.raise(lost, -1, false));
    const auto behaviour = od_.get<std::uint8_t>(0x1029, 1).value_or(1);
    if (behaviour == 0 && nmt_->state() == nmt::NmtState::Operational) {
        nmt_->enter(nmt::NmtState::PreOperational);
    } else if (behaviour == 2) {
        nmt_->enter(nmt::NmtState::Stopped);
    }
    const auto option = od_.get<std::int16_t>(0x6007, 0).value_or(0);
    for (auto& a : axes_) {
        a->abort_connection(option);
    }
}

void SimDevice::heartbeat_recovered() {
    if (!config_.profile->heartbeat_loss_is_fault) {
        if (const auto m = errors_.clear(-1, false, config_.profile->heartbeat_loss_code)) {
            send_emcy(*m);
        }
    }
}

void SimDevice::on_axis_event(const AxisEvent& e) {
    const bool raised =
        e.kind == AxisEvent::Kind::FaultRaised || e.kind == AxisEvent::Kind::WarningRaised;
    if (raised) {
        log(fmt::format("node {}: {} 0x{:04X} {} (axis {})", config_.node,
                        e.kind == AxisEvent::Kind::WarningRaised ? "warning" : "fault", e.code.emcy,
                        e.code.text, e.axis + 1));
    }
    if (const auto m = errors_.on_axis_event(e)) {
        send_emcy(*m);
    }
}

void SimDevice::send_emcy(const emcy::EmcyMessage& m) {
    if (!started_ || !emcy_enabled_ || !nmt_->sync_emcy_allowed()) {
        return;
    }
    if (emcy_->send(m.error_code, m.error_register, m.manufacturer, now_)) {
        ++stats_.emcy_sent;
    }
}

} // namespace codrive::sim
