// SPDX-License-Identifier: Apache-2.0
// One EtherCAT segment in the controller: ESM to OP with the profiles' PDO layouts, axes over
// the CoE transport, one LRW per cycle.
#include "ecat_segment.hpp"

#include <codrive/drives/canopen_transport.hpp>
#include <codrive/drives/profile.hpp>

#include <codrive/ethercat/drive_layout.hpp>
#include <codrive/ethercat/error.hpp>
#include <codrive/ethercat/esi_pdos.hpp>

#include <fmt/format.h>

#include <algorithm>

namespace codrive::controller {
namespace {

tl::unexpected<ControllerError> segment_failed(std::string sentence, std::error_code cause = {}) {
    return tl::unexpected(
        ControllerError(ControllerErrc::SegmentFailed, std::move(sentence), cause));
}

} // namespace

EcatSegment::EcatSegment(EcatSegmentConfig config, std::size_t bus_index, Emit emit)
    : config_(std::move(config)), bus_index_(bus_index), emit_(std::move(emit)),
      period_(microseconds(config_.cycle_us)) {}

EcatSegment::~EcatSegment() = default;

tl::expected<void, ControllerError> EcatSegment::bring_up(ethercat::IEcatLink* link,
                                                          bool dedicated) {
    const std::string where = fmt::format("EtherCAT segment on {}", config_.iface);
    if (link == nullptr) {
        auto l = ethercat::RawSocketLink::open(config_.iface);
        if (!l) {
            return segment_failed(
                ethercat::RawSocketLink::describe_open_error(config_.iface, l.error()), l.error());
        }
        own_link_ = std::move(*l);
        link = own_link_.get();
    }
    master_ = std::make_unique<ethercat::Master>(*link, RealClock::instance());
    if (auto r = master_->scan(); !r) {
        return segment_failed(fmt::format("{}: scan failed: {}", where, master_->last_error()),
                              r.error());
    }
    const std::size_t found = master_->slaves().size();
    for (const auto& e : config_.slaves) {
        if (e.position >= found) {
            return segment_failed(fmt::format("{}:{}: slave {} ({}) is configured but the segment "
                                              "has only {} slave(s)",
                                              config_.file, e.line, e.position, e.profile, found));
        }
        auto s = std::make_unique<Slave>();
        s->entry = e;
        s->index = e.position;
        s->profile = drives::find_profile(e.profile);
        s->emcy_text = drives::emcy_text_provider(*s->profile);
        const auto& sii = master_->slaves()[e.position].sii;
        const auto& id = s->profile->identity;
        if (id.vendor_id != 0 &&
            (sii.vendor_id != id.vendor_id || (sii.product_code & id.product_code_mask) !=
                                                  (id.product_code & id.product_code_mask))) {
            return segment_failed(fmt::format(
                "{}: {} is configured as {} (vendor 0x{:08X} product 0x{:08X}) but answers with "
                "vendor 0x{:08X} product 0x{:08X}",
                where, master_->slave_label(e.position), s->profile->title, id.vendor_id,
                id.product_code, sii.vendor_id, sii.product_code));
        }
        if (e.esi) {
            // The ESI device is the one whose identity the slave's SII states (ETG.2000
            // §5.3.1 Type: ProductCode, RevisionNo under the file's Vendor/Id).
            s->esi_device = e.esi->match(sii.vendor_id, sii.product_code, sii.revision);
            if (s->esi_device == nullptr) {
                return segment_failed(fmt::format(
                    "{}:{}: {}: {}", config_.file, e.line, master_->slave_label(e.position),
                    e.esi->mismatch(sii.vendor_id, sii.product_code, sii.revision)));
            }
        }
        slaves_.push_back(std::move(s));
    }
    if (auto r = master_->set_state_all(ethercat::AlState::PreOp); !r) {
        return segment_failed(fmt::format("{}: PRE-OP: {}", where, master_->last_error()),
                              r.error());
    }
    // ETG.1020 §21.1.3.1: DC SYNC0 needs the segment's clocks set up first (delays, offsets,
    // static drift compensation), once for the segment.
    if (std::any_of(slaves_.begin(), slaves_.end(),
                    [&](const auto& s) { return slave_dc(config_, s->entry); })) {
        if (auto r = master_->configure_dc(); !r) {
            return segment_failed(
                fmt::format("{}: distributed clocks: {}", where, master_->last_error()), r.error());
        }
    }
    for (auto& s : slaves_) {
        if (auto r = configure_slave(*s); !r) {
            return r;
        }
        if (auto r = synchronise_slave(*s); !r) {
            return r;
        }
    }
    if (auto r = master_->set_state_all(ethercat::AlState::Op); !r) {
        return segment_failed(fmt::format("{}: OP: {}", where, master_->last_error()), r.error());
    }
    // Emergencies arrive inside the cyclic exchange: the handler only queues them (no
    // formatting, no I/O there); acyclic() turns them into sentences.
    master_->on_emergency([this](std::size_t slave, const emcy::EmcyMessage& m) {
        EmcyEvent e{slave, m};
        (void)emcy_.push(e);
        for (auto& s : slaves_) {
            if (s->index == slave) {
                s->emcy_code.store(m.error_code);
            }
        }
    });
    probes_.assign(master_->slaves().size(), ethercat::Master::AlProbe{});
    for (auto& s : slaves_) {
        // The cyclic frame carries the CoE transfers: the axes use the transport on whichever
        // thread runs cycle() (the dedicated cyclic thread too); nothing there blocks.
        s->transport = std::make_unique<ethercat::CoeTransport>(
            *master_, s->index, ethercat::CoeTransport::Drive::Cyclic);
        drives::DriveTransport* axis_transport = s->transport.get();
        if (dedicated) {
            s->loop_access = std::make_unique<HandoffTransport>(*s->transport, "cyclic thread");
        }
        for (const auto& a : s->entry.axes) {
            drives::AxisConfig ac;
            ac.axis = a.axis;
            ac.profile = s->profile;
            ac.name =
                fmt::format("slave {} axis {}{}", s->index, a.axis,
                            s->entry.name.empty() ? std::string() : " (" + s->entry.name + ")");
            auto axis = std::make_unique<drives::Axis>(*axis_transport, ac);
            axis->bind();
            s->axes.push_back(std::move(axis));
        }
        emit_(fmt::format("{}: OP, {} axis(es), {} output / {} input bytes",
                          master_->slave_label(s->index), s->axes.size(),
                          master_->slaves()[s->index].output_bytes,
                          master_->slaves()[s->index].input_bytes));
    }
    return {};
}

tl::expected<void, ControllerError> EcatSegment::configure_slave(Slave& s) {
    const std::string who = master_->slave_label(s.index);
    if (s.entry.axes.empty()) {
        if (s.esi_device == nullptr) {
            return {}; // keep the slave's own PDO assignment
        }
        // The default layout the vendor's ESI states (the PDOs with an Sm attribute).
        const auto pdos = ethercat::esi_default_pdos(*s.esi_device);
        if (!pdos) {
            emit_(fmt::format("{}: {} states no PDO assignment (CoE PdoAssign); keeping the "
                              "slave's own",
                              who, s.entry.esi->file));
            return {};
        }
        if (!master_->configure_pdos(s.index, pdos->rx, pdos->tx)) {
            return segment_failed(fmt::format("{}: the default PDO assignment of {} failed: {}",
                                              who, s.entry.esi->file, master_->last_error()));
        }
        emit_(fmt::format("{}: default PDO assignment of {} ({} RxPDO, {} TxPDO)", who,
                          s.entry.esi->file, pdos->rx.size(), pdos->tx.size()));
        return {};
    }
    // The profile's layouts put axis n into RxPDO/TxPDO n (AKD2G manual §3.11.2: 1600h/1A00h
    // axis 1, 1601h/1A01h axis 2), so the modes go in axis order and the axes must be 1..n.
    std::vector<EcatAxisEntry> axes = s.entry.axes;
    std::sort(axes.begin(), axes.end(),
              [](const EcatAxisEntry& x, const EcatAxisEntry& y) { return x.axis < y.axis; });
    for (std::size_t i = 0; i < axes.size(); ++i) {
        if (axes[i].axis != i + 1) {
            return segment_failed(fmt::format(
                "{}:{}: {}: the axes of a slave must be numbered 1..n without gaps (axis {} is "
                "configured, axis {} is not); the PDO layout puts axis n into RxPDO/TxPDO n",
                config_.file, s.entry.line, who, axes[i].axis, i + 1));
        }
    }
    std::vector<drives::cia402::Mode> modes;
    for (const auto& a : axes) {
        const std::int8_t mode = a.mode.value_or(8);
        modes.push_back(static_cast<drives::cia402::Mode>(mode));
        const std::uint16_t index = s.profile->axis_index(0x6060, a.axis);
        if (auto r = master_->sdo_write<std::int8_t>(s.index, index, 0, mode); !r) {
            return segment_failed(fmt::format("{}: cannot set mode {} (0x{:04X}:00): {}", who, mode,
                                              index, master_->last_error()),
                                  r.error());
        }
    }
    auto configs = drives::mode_pdo_configs(*s.profile, modes);
    if (!configs) {
        emit_(fmt::format("{}: no PDO layout for the configured modes ({}); keeping the slave's "
                          "own assignment",
                          who, configs.error().message));
        return {};
    }
    std::vector<ethercat::PdoMapping> rx;
    std::vector<ethercat::PdoMapping> tx;
    ethercat::to_ecat_pdos(*configs, rx, tx);
    if (auto r = master_->configure_pdos(s.index, rx, tx); !r) {
        return segment_failed(
            fmt::format("{}: PDO configuration failed: {}", who, master_->last_error()), r.error());
    }
    return {};
}

tl::expected<void, ControllerError> EcatSegment::synchronise_slave(Slave& s) {
    // The same 1C32h/1C33h writes and SYNC0 set-up as `codrive drive --ethercat`, before
    // SAFE-OP; a cycle below the slave's minimum (1C32h:05) is refused here, never in OP.
    ethercat::SyncSettings sync;
    sync.cycle = period_;
    sync.mode = slave_sync(config_, s.entry);
    sync.shift = microseconds(slave_sync0_shift_us(config_, s.entry));
    sync.name = s.entry.name;
    auto r = ethercat::configure_sync(*master_, s.index, sync);
    if (!r) {
        return segment_failed(fmt::format("{}:{}: {}", config_.file, s.entry.line, r.error()));
    }
    for (const auto& note : r->notes) {
        emit_(note);
    }
    emit_(
        fmt::format("{}: sync mode {} ({}), cycle {} µs{}", master_->slave_label(s.index), r->mode,
                    ethercat::sync_mode_name(r->mode), config_.cycle_us,
                    sync.mode == ethercat::SyncMode::DcSync0
                        ? fmt::format(", SYNC0 shift {} µs", slave_sync0_shift_us(config_, s.entry))
                        : std::string()));
    return {};
}

void EcatSegment::start_cycles(TimePoint first, CycleHook hook) {
    hook_ = std::move(hook);
    next_ = first;
    next_ns_.store(first.time_since_epoch().count(), std::memory_order_relaxed);
}

void EcatSegment::cycle(TimePoint now) {
    const TimePoint ideal = next_;
    period_error_.add(now - ideal);
    next_ += period_;
    while (next_ <= now) { // a late cycle skips the slots it missed
        next_ += period_;
        ++overruns_;
    }
    next_ns_.store(next_.time_since_epoch().count(), std::memory_order_relaxed);
    // The frame (process data plus the mailbox datagrams riding in it) may take until the next
    // cycle is due, never longer: a lost one is counted and the cycle goes on; it never waits
    // for the mailbox.
    const TimePoint deadline = next_;
    // AL control writes the acyclic side asked for (recovery of a slave that left OP) ride in
    // this frame; nothing waits for them.
    for (auto& s : slaves_) {
        if (const std::uint16_t v = s->al_request.exchange(0, std::memory_order_acquire); v != 0) {
            (void)master_->queue_al_control(s->index, v);
        }
        // The loop thread's object accesses join the slave's CoE queue; their mailbox
        // datagrams ride in this frame and the next ones, one step per cycle, like the axes'.
        if (s->loop_access) {
            (void)s->loop_access->pump_requests();
        }
    }
    bool ok = false;
    LinkFailure failure;
    const std::uint64_t late_before = master_->stats().late_frames;
    if (auto sent = master_->send_process_data(); sent) {
        auto r = master_->receive_process_data(deadline);
        ok = r.has_value();
        if (!r && r.error() == ethercat::EcatErrc::NoResponse) {
            lost_frames_.store(master_->stats().lost_frames, std::memory_order_relaxed);
            const std::uint64_t run = master_->stats().consecutive_lost;
            if (run == config_.lost_frames_event) {
                lost_run_.store(run, std::memory_order_release);
            }
        } else if (!r && r.error() != ethercat::EcatErrc::WorkingCounter) {
            failure.error = r.error(); // the frame was given up (Master::receive_process_data)
        }
    } else {
        failure = {true, sent.error()};
    }
    if (failure.error && !link_failure_ready_.load(std::memory_order_acquire)) {
        link_failure_ = failure;
        link_failure_ready_.store(true, std::memory_order_release);
    }
    if (!ok) {
        frame_errors_.fetch_add(1, std::memory_order_relaxed);
    }
    // Frames of earlier cycles that this one read and dropped: they came back, late.
    late_frames_.fetch_add(master_->stats().late_frames - late_before, std::memory_order_relaxed);
    last_cycle_ok_.store(ok, std::memory_order_relaxed);
    // A short working counter: the next frame asked every slave for its AL status; hand the
    // answers to the acyclic side, which names the slaves.
    if (master_->take_al_probes() && !probes_ready_.load(std::memory_order_acquire)) {
        const auto& p = master_->al_probes();
        std::copy_n(p.begin(), std::min(p.size(), probes_.size()), probes_.begin());
        probes_wkc_ = master_->probed_wkc();
        probes_ready_.store(true, std::memory_order_release);
    }
    for (auto& s : slaves_) {
        if (s->transport) {
            s->transport->poll(); // completions of object accesses (no link access)
        }
    }
    ++cycles_;
    if (hook_) {
        hook_(CycleInfo{cycles_, ideal, now, bus_index_});
    }
    for (auto& s : slaves_) {
        if (const std::uint16_t code = s->emcy_code.exchange(0); code != 0) {
            for (auto& a : s->axes) {
                a->note_error_code(code);
            }
        }
        for (auto& a : s->axes) {
            a->on_cycle(now);
            if (a->next_deadline() <= now) {
                a->on_tick(now); // operation timeouts
            }
        }
    }
}

void EcatSegment::acyclic(TimePoint now) {
    for (auto& s : slaves_) {
        if (s->loop_access) {
            (void)s->loop_access->deliver_completions();
        }
    }
    EmcyEvent e;
    while (emcy_.pop(e)) {
        // With the drive profile's text (AKD2G "F2002 Output over current"), as the CAN side
        // describes the same EMCY (controller.cpp sets the node's text provider).
        const emcy::IEmcyTextProvider* vendor = nullptr;
        for (const auto& s : slaves_) {
            if (s->index == e.slave) {
                vendor = s->emcy_text.get();
            }
        }
        emit_(master_->describe_emergency(e.slave, e.message, vendor));
    }
    const std::string where = fmt::format("EtherCAT segment on {}", config_.iface);
    if (probes_ready_.load(std::memory_order_acquire)) {
        if (!frame_error_reported_) {
            frame_error_reported_ = true;
            failed_at_report_ = frame_errors_.load(std::memory_order_relaxed);
            emit_(fmt::format("{}: cyclic exchange failed: {}", where,
                              master_->describe_wkc(probes_wkc_, probes_)));
        }
        recover_slaves(now);
        probes_ready_.store(false, std::memory_order_release);
    }
    if (link_failure_ready_.load(std::memory_order_acquire)) {
        // Reported once per run of failed cycles, as the other causes; the cycles go on trying
        // (an interface brought up again carries the next frame).
        if (!frame_error_reported_) {
            frame_error_reported_ = true;
            failed_at_report_ = frame_errors_.load(std::memory_order_relaxed);
            emit_(fmt::format("{}: cyclic exchange failed: cannot {} the cyclic frame: {}", where,
                              link_failure_.sending ? "send" : "receive",
                              link_failure_.error.message()));
        }
        link_failure_ready_.store(false, std::memory_order_release);
    }
    if (const std::uint64_t run = lost_run_.exchange(0, std::memory_order_acquire); run != 0) {
        if (!frame_error_reported_) {
            frame_error_reported_ = true;
            failed_at_report_ = frame_errors_.load(std::memory_order_relaxed);
        }
        emit_(fmt::format("{}: {} cyclic frames lost in a row (none came back within its {:.1f} ms "
                          "cycle; {} lost in all)",
                          where, run, to_ms(period_),
                          lost_frames_.load(std::memory_order_relaxed)));
    }
    if (last_cycle_ok_.load(std::memory_order_relaxed)) {
        // A full working counter: every slave is back in OP.
        for (auto& s : slaves_) {
            report_back_in_op(*s, now);
        }
    }
    if (frame_error_reported_ && last_cycle_ok_.load(std::memory_order_relaxed)) {
        frame_error_reported_ = false;
        emit_(fmt::format("{}: cyclic exchange works again ({} failed cycles)", where,
                          frame_errors_.load(std::memory_order_relaxed) - failed_at_report_ + 1));
    }
}

void EcatSegment::report_back_in_op(Slave& s, TimePoint now) {
    if (!s.left_op) {
        return;
    }
    s.left_op = false;
    emit_(
        fmt::format("{}: back in OP after {} OP request(s), {:.0f} ms after it was seen outside OP",
                    master_->slave_label(s.index), s.op_requests, to_ms(now - s.left_at)));
}

void EcatSegment::recover_slaves(TimePoint now) {
    // ETG.1000.6 §6.4.1: a slave that left OP by itself (SAFE-OP with an error: 0x001B SM
    // watchdog, 0x001A synchronisation lost...) keeps its sync managers and FMMUs, so the
    // master can bring it back while the cycle runs: acknowledge the error (AL control SAFE-OP
    // with bit 4), then request OP. Requests repeat with back-off (100 ms doubling to 5 s) while
    // the slave refuses; the writes ride in the cyclic frame (Master::queue_al_control).
    constexpr Duration kFirstBackoff = milliseconds(100);
    constexpr Duration kMaxBackoff = milliseconds(5000);
    constexpr auto kSafeOp = static_cast<std::uint16_t>(ethercat::AlState::SafeOp);
    constexpr auto kOp = static_cast<std::uint16_t>(ethercat::AlState::Op);
    for (auto& s : slaves_) {
        if (s->index >= probes_.size() || !probes_[s->index].answered) {
            continue; // a slave that does not answer is named by the working-counter report
        }
        const auto& st = probes_[s->index].status;
        if (st.state == ethercat::AlState::Op) {
            report_back_in_op(*s, now); // another slave keeps the working counter short
            continue;
        }
        const std::string who = master_->slave_label(s->index);
        if (!s->left_op) {
            s->left_op = true;
            s->stuck_reported = false;
            s->op_requests = 0;
            s->left_at = now;
            s->next_request = now;
            s->backoff = kFirstBackoff;
            emit_(
                fmt::format("{}: left OP, now in {}{}{}", who, ethercat::to_string(st.state),
                            st.error ? fmt::format(" with AL status code 0x{:04X} ({})", st.code,
                                                   ethercat::al_status_code_describe(st.code))
                                     : std::string(),
                            st.state == ethercat::AlState::SafeOp ? "; requesting OP again" : ""));
        }
        if (st.state != ethercat::AlState::SafeOp && st.state != ethercat::AlState::Op) {
            // Below SAFE-OP its process data sync managers are gone: only a new bring-up
            // (stop and start) configures them again.
            if (!s->stuck_reported) {
                s->stuck_reported = true;
                emit_(fmt::format("{}: fell to {}, below SAFE-OP: its process data is no longer "
                                  "configured; restart the controller to bring it back",
                                  who, ethercat::to_string(st.state)));
            }
            continue;
        }
        if (now < s->next_request) {
            continue;
        }
        if (st.error) {
            s->al_request.store(static_cast<std::uint16_t>(kSafeOp | ethercat::kAlErrorFlag),
                                std::memory_order_release);
            s->next_request = now + 2 * period_; // OP once the acknowledge is through
            continue;
        }
        s->al_request.store(kOp, std::memory_order_release);
        ++s->op_requests;
        s->next_request = now + s->backoff;
        s->backoff = std::min(s->backoff * 2, kMaxBackoff);
    }
}

void EcatSegment::on_tick(TimePoint now) {
    if (now < next_) {
        return;
    }
    cycle(now);
    acyclic(now);
}

void EcatSegment::cyclic_step(TimePoint now) {
    if (now < next_) {
        return;
    }
    cycle(now); // the master belongs to this thread: no flag, no lock, no wait
}

void EcatSegment::acyclic_step(TimePoint now) {
    acyclic(now); // events only: never touches the link
}

void EcatSegment::stop() {
    next_ = kNever;
    if (master_) {
        if (!master_->set_state_all(ethercat::AlState::PreOp)) {
            emit_(fmt::format("EtherCAT segment on {}: stepping down to PRE-OP failed: {}",
                              config_.iface, master_->last_error()));
        }
    }
}

void EcatSegment::abandon_object_accesses(std::string_view why) {
    for (auto& s : slaves_) {
        if (s->loop_access) {
            (void)s->loop_access->abandon_requests(why); // handed over, never started
        }
        if (master_ && s->transport) {
            master_->cancel_mailbox_transfers(s->index, why);
            (void)s->transport->poll(); // their completions: into the hand-off, or the caller's
        }
        if (s->loop_access) {
            (void)s->loop_access->deliver_completions();
        }
    }
}

drives::Axis* EcatSegment::axis(unsigned position, unsigned number) {
    for (auto& s : slaves_) {
        if (s->index != position) {
            continue;
        }
        for (auto& a : s->axes) {
            if (a->number() == number) {
                return a.get();
            }
        }
    }
    return nullptr;
}

drives::DriveTransport* EcatSegment::loop_transport(unsigned position) {
    for (auto& s : slaves_) {
        if (s->index == position) {
            if (s->loop_access) {
                return s->loop_access.get();
            }
            return s->transport.get();
        }
    }
    return nullptr;
}

void EcatSegment::collect_axes(std::vector<AxisRef>& out) const {
    for (const auto& s : slaves_) {
        for (const auto& a : s->axes) {
            std::optional<std::int8_t> mode;
            for (const auto& e : s->entry.axes) {
                if (e.axis == a->number()) {
                    mode = e.mode;
                }
            }
            out.push_back(AxisRef{bus_index_, static_cast<NodeId>(s->index), a->number(), a.get(),
                                  a->name(), mode});
        }
    }
}

void EcatSegment::for_each_axis(const std::function<void(drives::Axis&)>& fn) {
    for (auto& s : slaves_) {
        for (auto& a : s->axes) {
            fn(*a);
        }
    }
}

} // namespace codrive::controller
