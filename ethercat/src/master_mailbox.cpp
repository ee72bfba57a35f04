// SPDX-License-Identifier: Apache-2.0
// Master mailbox channels: per-slave state machines that carry CoE transfers one datagram per
// frame (write SM0, read SM1, mailbox repeat), in the cyclic frame or in mailbox-only frames,
// with per-step timeouts and emergencies (ETG.1000.4 §6.7, ETG.1000.6 §5.6).
#include "coe_transfer.hpp"

#include <codrive/ethercat/error.hpp>
#include <codrive/ethercat/master.hpp>
#include <codrive/ethercat/registers.hpp>
#include <codrive/sdo/protocol.hpp>

#include <fmt/format.h>

#include <algorithm>

namespace codrive::ethercat {

using detail::MailboxChannel;
using detail::MailboxPhase;

namespace {

/// How a failure sentence names a transfer: "slave 2 (DS-BVS): CoE SDO upload 0x6064:00".
std::string transfer_name(const detail::CoeTransfer& t) {
    return fmt::format("{}: {}{}", t.label, t.mailbox_type() == MailboxType::Coe ? "CoE " : "",
                       t.what);
}

} // namespace

Master::~Master() = default;

MailboxChannel& Master::channel(std::size_t slave) {
    while (channels_.size() <= slave) {
        channels_.push_back(std::make_unique<MailboxChannel>());
    }
    return *channels_[slave];
}

std::size_t Master::mailbox_transfers(std::size_t slave) const {
    return slave < channels_.size() ? channels_[slave]->queue.size() : 0;
}

VoidResult Master::submit(std::size_t slave, std::unique_ptr<detail::CoeTransfer> t) {
    if (auto c = check_slave(slave); !c) {
        return c;
    }
    const SiiInfo& sii = slaves_[slave].sii;
    const bool foe = t->mailbox_type() == MailboxType::Foe;
    if (!sii.has_mailbox() || (foe ? !sii.has_foe() : !sii.has_coe())) {
        return set_error(make_error_code(EcatErrc::MailboxNotSupported),
                         fmt::format("{}: the slave does not support {}", slave_label(slave),
                                     foe ? "FoE (file access over EtherCAT)" : "CoE"));
    }
    t->label = slave_label(slave);
    channel(slave).queue.push_back(std::move(t));
    return {};
}

VoidResult Master::sdo_upload_async(std::size_t slave, std::uint16_t index, std::uint8_t subindex,
                                    CoeDone done, bool complete_access) {
    auto t = detail::make_sdo_upload(index, subindex, complete_access);
    t->done = std::move(done);
    return submit(slave, std::move(t));
}

VoidResult Master::sdo_download_async(std::size_t slave, std::uint16_t index, std::uint8_t subindex,
                                      std::vector<std::uint8_t> data, CoeDone done,
                                      bool complete_access) {
    const std::size_t mbx = slave < slaves_.size() ? slaves_[slave].sii.rx_mailbox_size : 0;
    auto t = detail::make_sdo_download(index, subindex, std::move(data), complete_access, mbx);
    t->done = std::move(done);
    return submit(slave, std::move(t));
}

Datagram& Master::add_datagram(Command c, std::uint16_t adp, std::uint16_t ado, std::size_t size) {
    if (frame_used_ == frame_.size()) {
        frame_.emplace_back();
    }
    Datagram& d = frame_[frame_used_++];
    d.command = c;
    d.address = static_cast<std::uint32_t>(adp) | (static_cast<std::uint32_t>(ado) << 16);
    d.data.resize(size); // keeps its capacity: no allocation once the frame has been this big
    std::fill(d.data.begin(), d.data.end(), std::uint8_t{0});
    d.wkc = 0;
    d.irq = 0;
    d.circulated = false;
    return d;
}

std::size_t Master::frame_room() const {
    std::size_t used = kEthernetHeaderSize + kEcatHeaderSize;
    for (std::size_t i = 0; i < frame_used_; ++i) {
        used += frame_[i].wire_size();
    }
    return used >= kMaxFrameSize ? 0 : kMaxFrameSize - used;
}

void Master::mailbox_start(std::size_t slave, TimePoint now) {
    MailboxChannel& ch = channel(slave);
    ch.active = true;
    auto& t = *ch.queue.front();
    t.first(ch.request);
    if (t.outcome.error) {
        mailbox_finish(slave, now); // it could not start (e.g. an SDO download over 4 GiB)
        return;
    }
    mailbox_send(slave, now);
}

void Master::mailbox_send(std::size_t slave, TimePoint now) {
    MailboxChannel& ch = channel(slave);
    const SiiInfo& sii = slaves_[slave].sii;
    MailboxMessage m;
    m.header.type = ch.queue.front()->mailbox_type();
    m.header.counter = next_counter(slave);
    m.payload = ch.request;
    ch.out = m.encode(sii.rx_mailbox_size);
    ch.started = now;
    ch.deadline = now + config_.mailbox_timeout;
    ch.frames_lost = 0;
    ch.frames_unsent = 0;
    ch.strays = 0;
    ch.sm0_full = false;
    ch.last_write = false;
    if (ch.out.size() > sii.rx_mailbox_size) {
        mailbox_fail(slave, make_error_code(EcatErrc::MailboxError),
                     fmt::format("{}: {}: a {}-byte mailbox message does not fit the {}-byte "
                                 "mailbox",
                                 slave_label(slave), ch.queue.front()->what, ch.out.size(),
                                 sii.rx_mailbox_size),
                     now);
        return;
    }
    ch.phase = MailboxPhase::Write;
}

void Master::mailbox_finish(std::size_t slave, TimePoint now) {
    MailboxChannel& ch = channel(slave);
    finished_.push_back(std::move(ch.queue.front()));
    ch.queue.pop_front();
    ch.active = false;
    ch.phase = MailboxPhase::Idle;
    ch.next_poll = now;
}

void Master::mailbox_fail(std::size_t slave, std::error_code ec, std::string sentence,
                          TimePoint now) {
    MailboxChannel& ch = channel(slave);
    auto& t = *ch.queue.front();
    t.outcome.error = ec;
    t.outcome.sentence = std::move(sentence);
    t.outcome.data.clear();
    mailbox_finish(slave, now);
}

void Master::mailbox_timeout(std::size_t slave, TimePoint now) {
    MailboxChannel& ch = channel(slave);
    auto& t = *ch.queue.front();
    // Only answers of earlier transfers came (they waited in SM1 ahead of this one's): the
    // transfer's own failure, and the abort that tells the slave.
    if (const auto step = t.on_timeout(ch.request); step != detail::CoeTransfer::Step::Wait) {
        mailbox_step(slave, step, now);
        return;
    }
    const bool write_never_left = ch.frames_lost == 0 && ch.frames_unsent > 0;
    std::string why = ch.sm0_full ? "receive mailbox SM0 stayed full"
                      : ch.phase == MailboxPhase::Write
                          ? (write_never_left ? "request not sent" : "request frames lost")
                      : ch.strays > 0 ? fmt::format("no answer to it; {} other message{} read and "
                                                    "dropped",
                                                    ch.strays, ch.strays == 1 ? "" : "s")
                                      : "mailbox silent";
    if (ch.frames_lost > 0 && !ch.sm0_full && ch.phase != MailboxPhase::Write) {
        // Silent as far as the master could see: say how much it could not see, so a
        // mute slave is told from frames that came back late or not at all.
        why += fmt::format("; {} of its frames did not come back in time", ch.frames_lost);
    }
    if (ch.frames_unsent > 0) { // the host's side: the interface down or its queue full
        why += fmt::format("; {} of its frames could not be sent", ch.frames_unsent);
    }
    mailbox_fail(slave, make_error_code(EcatErrc::MailboxTimeout),
                 fmt::format("{} timed out after {:.0f} ms ({})", transfer_name(t),
                             to_ms(config_.mailbox_timeout), why),
                 now);
}

void Master::mailbox_add(TimePoint now) {
    const std::size_t n = slaves_.size();
    for (std::size_t k = 0; k < n; ++k) {
        const std::size_t i = (mailbox_first_ + k) % n;
        MailboxChannel& ch = channel(i);
        ch.datagram = -1;
        const SlaveInfo& s = slaves_[i];
        if (!s.sii.has_mailbox()) {
            continue;
        }
        if (ch.active && now >= ch.deadline) {
            // The transfer's own timeout: only this transfer fails; the frame goes on.
            mailbox_timeout(i, now);
        } else if (!ch.active && ch.phase != MailboxPhase::Idle && now >= ch.deadline) {
            ch.phase = MailboxPhase::Idle; // an emergency poll that could not finish its repeat
        }
        if (!ch.active && !ch.queue.empty()) {
            mailbox_start(i, now);
        }
        if (!ch.active && ch.phase == MailboxPhase::Idle) {
            const bool running =
                s.state == AlState::PreOp || s.state == AlState::SafeOp || s.state == AlState::Op;
            if (!s.sii.has_coe() || !running || now < ch.next_poll) {
                continue;
            }
            ch.phase = MailboxPhase::Read; // emergency poll
            ch.deadline = now + config_.mailbox_timeout;
        }
        const auto sm1 = static_cast<std::uint16_t>(reg::sm(1));
        std::size_t size = 0;
        switch (ch.phase) {
        case MailboxPhase::Write:
            size = ch.out.size();
            break;
        case MailboxPhase::Read:
            size = s.sii.tx_mailbox_size;
            break;
        default:
            size = 1;
            break;
        }
        if (kDatagramOverhead + size > frame_room()) {
            continue; // no room in this frame: next cycle (round robin moves the start)
        }
        ch.datagram = static_cast<int>(frame_used_);
        switch (ch.phase) {
        case MailboxPhase::Write: {
            Datagram& d =
                add_datagram(Command::Fpwr, s.station_address, s.sii.rx_mailbox_offset, size);
            std::copy(ch.out.begin(), ch.out.end(), d.data.begin());
            break;
        }
        case MailboxPhase::Read:
            // Reading the whole SM1 buffer empties it; WKC 0 means nothing was there.
            add_datagram(Command::Fprd, s.station_address, s.sii.tx_mailbox_offset, size);
            break;
        case MailboxPhase::RepeatRead:
            add_datagram(Command::Fprd, s.station_address,
                         static_cast<std::uint16_t>(sm1 + SyncManager::kActivateOffset), 1);
            break;
        case MailboxPhase::RepeatWrite:
            add_datagram(Command::Fpwr, s.station_address,
                         static_cast<std::uint16_t>(sm1 + SyncManager::kActivateOffset), 1)
                .data[0] = ch.repeat_want;
            break;
        case MailboxPhase::RepeatAck:
            add_datagram(Command::Fprd, s.station_address,
                         static_cast<std::uint16_t>(sm1 + SyncManager::kPdiControlOffset), 1);
            break;
        case MailboxPhase::Idle:
            ch.datagram = -1;
            break;
        }
    }
    if (n > 0) {
        mailbox_first_ = (mailbox_first_ + 1) % n;
    }
}

void Master::mailbox_unsent() {
    for (std::size_t i = 0; i < channels_.size() && i < slaves_.size(); ++i) {
        MailboxChannel& ch = *channels_[i];
        if (ch.datagram >= 0) {
            ch.datagram = -1;
            ++ch.frames_unsent;
        }
    }
}

void Master::mailbox_done(bool lost, TimePoint now) {
    for (std::size_t i = 0; i < channels_.size() && i < slaves_.size(); ++i) {
        MailboxChannel& ch = *channels_[i];
        if (ch.datagram < 0) {
            continue;
        }
        const Datagram& d = frame_[static_cast<std::size_t>(ch.datagram)];
        ch.datagram = -1;
        const bool ok = !lost && d.wkc == 1;
        ch.frames_lost += lost ? 1U : 0U;
        switch (ch.phase) {
        case MailboxPhase::Write:
            // Lost: written or not, the same message (same counter) goes again; a slave that got
            // it drops the copy (ETG.1000.6 §5.6.1). WKC 0: SM0 still full.
            if (ok && ch.last_write) {
                mailbox_finish(i, now); // nothing comes back for it (SendLast)
            } else if (ok) {
                ch.phase = MailboxPhase::Read;
            } else if (!lost) {
                ch.sm0_full = true;
            }
            break;
        case MailboxPhase::Read:
            if (lost) {
                // The read may have emptied SM1 on its way: ask the slave to write that message
                // again instead of losing it (ETG.1000.4 §6.7.2), after every lost read. The
                // step's deadline bounds the tries, not a count: on a host that returns one
                // cyclic frame in three late, three repeats per step were not enough and FoE
                // writes timed out "mailbox silent" while the slave answered (docs/ethercat.md).
                ch.phase = MailboxPhase::RepeatRead;
            } else if (d.wkc == 1) {
                mailbox_message(i, d.data, now);
            } else if (!ch.active) {
                ch.phase = MailboxPhase::Idle;
                ch.next_poll = now + config_.emergency_poll;
            }
            break;
        case MailboxPhase::RepeatRead:
            if (ok) {
                ch.repeat_want = SyncManager::repeat_request_after(d.data[0]);
                ch.phase = MailboxPhase::RepeatWrite;
            }
            break;
        case MailboxPhase::RepeatWrite:
            // Taken, or lost on its way back after the slave took it: from now on SM1 may hold
            // a copy of a message already read, whoever reads it next (this channel, a transfer
            // that starts before the acknowledgement is seen, a blocking read).
            ch.repeated = ch.repeated || ok || lost;
            if (ok) { // a lost write goes again with the same absolute value
                ++mailbox_repeats_;
                ch.phase = MailboxPhase::RepeatAck;
            }
            break;
        case MailboxPhase::RepeatAck:
            if (ok && ((d.data[0] & SyncManager::kPdiRepeatAck) != 0) ==
                          ((ch.repeat_want & SyncManager::kActivateRepeatRequest) != 0)) {
                ch.phase = MailboxPhase::Read;
            }
            break;
        case MailboxPhase::Idle:
            break;
        }
    }
}

void Master::dispatch_emergency(std::size_t slave, std::span<const std::uint8_t> coe) {
    if (coe.size() < kCoeHeaderSize + 8) {
        return;
    }
    emcy::EmcyMessage e;
    e.node = static_cast<NodeId>(std::min<std::size_t>(slave + 1, 127));
    e.error_code = get_le<std::uint16_t>(coe.data() + 2);
    e.error_register = coe[4];
    std::copy_n(coe.begin() + 5, 5, e.manufacturer.begin());
    if (emergency_handler_) {
        emergency_handler_(slave, e);
    }
}

void Master::mailbox_message(std::size_t slave, std::span<const std::uint8_t> sm1, TimePoint now) {
    MailboxChannel& ch = channel(slave);
    if (sm1.size() < kMailboxHeaderSize) {
        return;
    }
    const MailboxHeader h = MailboxHeader::decode(sm1.data());
    if (kMailboxHeaderSize + h.length > sm1.size()) {
        if (ch.active) {
            mailbox_fail(slave, make_error_code(EcatErrc::MailboxError),
                         fmt::format("{}: {}: malformed mailbox header (length {} in a {}-byte "
                                     "mailbox)",
                                     slave_label(slave), ch.queue.front()->what, h.length,
                                     sm1.size()),
                         now);
        }
        return;
    }
    const auto payload = sm1.subspan(kMailboxHeaderSize, h.length);
    auto& last = slaves_[slave].mailbox_rx_counter;
    // After a repeat the slave may hand over the message we already have (the lost frame never
    // reached it): same counter, so it is dropped (ETG.1000.6 §5.6.1).
    const bool duplicate = ch.repeated && h.counter != 0 && h.counter == last;
    last = h.counter;
    ch.repeated = false;
    if (duplicate) {
        return;
    }
    if (h.type == MailboxType::Error) {
        const std::uint16_t code =
            payload.size() >= 4 ? get_le<std::uint16_t>(payload.data() + 2) : 0;
        if (ch.active) {
            mailbox_fail(slave, make_error_code(EcatErrc::MailboxError),
                         fmt::format("{}: {}: mailbox error 0x{:04X} ({})", slave_label(slave),
                                     ch.queue.front()->what, code, mailbox_error_text(code)),
                         now);
        }
        return;
    }
    if (h.type == MailboxType::Foe) {
        if (!ch.active || ch.queue.front()->mailbox_type() != MailboxType::Foe) {
            drop_stray(ch);
            return;
        }
        mailbox_step(slave, ch.queue.front()->on_reply(payload, ch.request), now);
        return;
    }
    if (h.type != MailboxType::Coe || payload.size() < kCoeHeaderSize) {
        drop_stray(ch);
        return;
    }
    const CoeService got = coe_service(get_le<std::uint16_t>(payload.data()));
    if (got == CoeService::Emergency) {
        dispatch_emergency(slave, payload);
        return;
    }
    if (!ch.active) {
        drop_stray(ch); // e.g. a late answer to a transfer that timed out
        return;
    }
    auto& t = *ch.queue.front();
    // The server's SDO abort travels as an SDO *request* (ETG.1000.6 §5.6.2.7).
    const bool abort =
        t.service() == CoeService::SdoResponse && got == CoeService::SdoRequest &&
        payload.size() > 2 &&
        sdo::command_bits(payload[2]) == static_cast<std::uint8_t>(sdo::ServerCommand::Abort);
    if ((got != t.service() && !abort) || t.mailbox_type() != MailboxType::Coe) {
        drop_stray(ch);
        return;
    }
    mailbox_step(slave, t.on_reply(payload, ch.request), now);
}

void Master::drop_stray(MailboxChannel& ch) {
    ++stats_.stray_mailbox_messages;
    ++ch.strays; // for the running step's timeout sentence
}

void Master::mailbox_step(std::size_t slave, detail::TransferStep step, TimePoint now) {
    MailboxChannel& ch = channel(slave);
    switch (step) {
    case detail::CoeTransfer::Step::Send:
        mailbox_send(slave, now);
        break;
    case detail::CoeTransfer::Step::SendLast:
        mailbox_send(slave, now);
        ch.last_write = ch.active; // mailbox_send() may have failed the transfer already
        break;
    case detail::CoeTransfer::Step::Wait:
        ch.deadline = now + config_.mailbox_timeout;
        ch.frames_lost = 0;
        ch.frames_unsent = 0;
        ch.strays = 0;
        break;
    case detail::CoeTransfer::Step::Done:
    case detail::CoeTransfer::Step::Failed:
        mailbox_finish(slave, now);
        break;
    case detail::CoeTransfer::Step::Stray:
        drop_stray(ch); // the deadline stays: strays cannot keep it alive
        break;
    }
}

void Master::deliver_finished() {
    if (finished_.empty()) {
        return;
    }
    // Callbacks may queue more transfers: take the list first.
    auto done = std::move(finished_);
    finished_.clear();
    for (auto& t : done) {
        if (t->done) {
            t->done(std::move(t->outcome));
        }
    }
}

VoidResult Master::run_mailbox_cycle() {
    const TimePoint now = clock_.now();
    frame_used_ = 0;
    mailbox_add(now);
    if (frame_used_ == 0) {
        deliver_finished(); // timeouts found by mailbox_add()
        return {};
    }
    const auto frame = std::span<Datagram>(frame_.data(), frame_used_);
    const std::uint8_t idx = next_index();
    for (auto& d : frame) {
        d.index = idx;
    }
    // On a failure the frame never left: nothing in it is lost. Transfers mailbox_add() timed
    // out end first, so that their callbacks cannot overwrite this call's sentence.
    auto n = encode_frame(frame, tx_buffer_);
    if (!n) {
        deliver_finished();
        return set_error(n.error(),
                         fmt::format("cannot build an EtherCAT frame: {}", n.error().message()));
    }
    if (auto s = link_.send(std::span<const std::uint8_t>(tx_buffer_).first(*n)); !s) {
        ++stats_.send_errors;
        mailbox_unsent();
        deliver_finished();
        return set_error(s.error(),
                         fmt::format("cannot send on {}: {}", link_.name(), s.error().message()));
    }
    const TimePoint deadline = clock_.now() + config_.frame_timeout;
    bool lost = true;
    while (true) {
        auto r = link_.receive(rx_buffer_, deadline);
        if (!r) {
            if (r.error() != CoreErrc::Timeout) {
                mark_overdue(idx, false);
                // Every channel whose datagram rode in the frame treats it as lost (a read may
                // have emptied SM1: it asks for a repeat), not only the caller's slave. Then the
                // transfers mailbox_add() timed out end, before this call's sentence is set.
                mailbox_done(true, clock_.now());
                deliver_finished();
                return set_error(r.error(), fmt::format("cannot receive on {}: {}", link_.name(),
                                                        r.error().message()));
            }
            break;
        }
        const auto got = std::span<const std::uint8_t>(rx_buffer_).first(*r);
        const auto fi = frame_index(got);
        if (fi && *fi == idx && decode_frame_into(got, frame)) {
            lost = false;
            break;
        }
        count_unawaited(fi);
    }
    if (lost) {
        mark_overdue(idx, false);
    }
    mailbox_done(lost, clock_.now());
    deliver_finished();
    return {};
}

void Master::cancel_mailbox_transfers(std::size_t slave, std::string_view why) {
    if (slave >= slaves_.size()) {
        return;
    }
    MailboxChannel& ch = channel(slave);
    const TimePoint now = clock_.now();
    // A callback may queue another transfer: cancelled in turn, up to 64 of them (as
    // SdoClient::cancel_all()): a callback that submits again on every failure would otherwise
    // keep this loop going forever. What it queues beyond that runs in the next mailbox cycle.
    constexpr std::size_t kMaxResubmits = 64;
    const std::size_t limit = ch.queue.size() + kMaxResubmits;
    std::size_t ended = 0;
    while (!ch.queue.empty() && ended < limit) {
        while (!ch.queue.empty() && ended < limit) {
            mailbox_fail(slave, make_error_code(EcatErrc::Cancelled),
                         fmt::format("{} cancelled: {}", transfer_name(*ch.queue.front()), why),
                         now);
            ++ended;
        }
        deliver_finished();
    }
}

void Master::run_mailbox_until_idle(std::size_t slave) {
    while (mailbox_transfers(slave) > 0) {
        if (auto r = run_mailbox_cycle(); !r) {
            if (transmit_queue_full(r.error())) {
                // No room for the frame: it goes again after a poll interval. Each transfer's
                // own timeout bounds the wait, its sentence counting the frames not sent.
                link_.idle(config_.mailbox_poll);
                continue;
            }
            // The link itself failed: end the slave's transfers, each sentence naming the
            // slave and the transfer before the link's own words.
            const TimePoint now = clock_.now();
            const std::string why = last_error();
            MailboxChannel& ch = channel(slave);
            while (!ch.queue.empty()) {
                if (!ch.active) {
                    ch.active = true;
                }
                mailbox_fail(slave, r.error(),
                             fmt::format("{} failed: {}", transfer_name(*ch.queue.front()), why),
                             now);
            }
            deliver_finished();
            return;
        }
        if (mailbox_transfers(slave) > 0) {
            link_.idle(config_.mailbox_poll);
        }
    }
}

Result<std::vector<std::uint8_t>> Master::run_transfer(std::size_t slave,
                                                       std::unique_ptr<detail::CoeTransfer> t) {
    std::optional<CoeOutcome> out;
    t->done = [&out](CoeOutcome o) { out = std::move(o); };
    if (auto s = submit(slave, std::move(t)); !s) {
        return fail(s.error());
    }
    while (!out) {
        run_mailbox_until_idle(slave);
    }
    if (out->error) {
        error_text() = out->sentence;
        return fail(out->error);
    }
    return std::move(out->data);
}

} // namespace codrive::ethercat
