// SPDX-License-Identifier: Apache-2.0
// CoE DriveTransport: SDO over the mailbox, process data from the LRW image.
#include <codrive/ethercat/coe_transport.hpp>

#include <fmt/format.h>

namespace codrive::ethercat {

CoeTransport::CoeTransport(Master& master, std::size_t slave, Drive drive)
    : master_(master), slave_(slave), drive_(drive) {}

std::string CoeTransport::name() const {
    return master_.slave_label(slave_);
}

void CoeTransport::submitted(VoidResult r, Completion c) {
    ++in_flight_;
    if (!r) { // refused at once (no such slave, no CoE): completes on the next poll()
        c.outcome.error = r.error();
        c.outcome.sentence = master_.last_error();
        completed_->push_back(std::move(c));
    }
}

void CoeTransport::submit(Completion c, const std::function<VoidResult(CoeDone)>& launch) {
    // The master calls back from its mailbox state machine; the completion waits in the sink
    // until poll() delivers it on the caller's thread.
    auto sink = completed_;
    auto pending = std::make_shared<Completion>(std::move(c));
    auto r = launch([sink, pending](CoeOutcome o) {
        pending->outcome = std::move(o);
        sink->push_back(std::move(*pending));
    });
    if (!r) {
        submitted(r, std::move(*pending));
        return;
    }
    submitted(r, {});
}

void CoeTransport::read(std::uint16_t index, std::uint8_t subindex, ReadDone done) {
    Completion c;
    c.read_done = std::move(done);
    submit(std::move(c), [&](CoeDone d) {
        return master_.sdo_upload_async(slave_, index, subindex, std::move(d));
    });
}

void CoeTransport::write(std::uint16_t index, std::uint8_t subindex, drives::Bytes data,
                         WriteDone done) {
    Completion c;
    c.write_done = std::move(done);
    submit(std::move(c), [&](CoeDone d) {
        return master_.sdo_download_async(slave_, index, subindex,
                                          std::vector<std::uint8_t>(data.begin(), data.end()),
                                          std::move(d));
    });
}

std::size_t CoeTransport::poll() {
    if (drive_ == Drive::Blocking && master_.mailbox_transfers(slave_) > 0) {
        master_.run_mailbox_until_idle(slave_);
    }
    std::size_t n = 0;
    // Callbacks may start more accesses: deliver only those complete now.
    for (std::size_t todo = completed_->size(); todo > 0; --todo) {
        Completion c = std::move(completed_->front());
        completed_->pop_front();
        --in_flight_;
        ++n;
        const bool ok = !c.outcome.error;
        if (c.write_done) {
            c.write_done(ok ? drives::DriveVoid{}
                            : drives::drive_fail(drives::DriveErrc::Transport, c.outcome.sentence));
        } else if (c.read_done) {
            if (ok) {
                c.read_done(std::move(c.outcome.data));
            } else {
                c.read_done(drives::drive_fail(drives::DriveErrc::Transport, c.outcome.sentence));
            }
        }
    }
    return n;
}

drives::CyclicHandle CoeTransport::resolve(std::uint16_t index, std::uint8_t subindex,
                                           bool output) const {
    if (!master_.process_data_mapped() || slave_ >= master_.slaves().size()) {
        return {};
    }
    const SlaveInfo& s = master_.slaves()[slave_];
    const auto& layout = output ? s.outputs_layout : s.inputs_layout;
    for (const auto& f : layout) {
        if (f.entry.index == index && f.entry.subindex == subindex && f.entry.bits % 8 == 0 &&
            f.entry.bits <= 64) {
            slots_.push_back({f.byte_offset, f.entry.bits / 8U, output});
            return drives::CyclicHandle{static_cast<std::int32_t>(slots_.size() - 1)};
        }
    }
    return {};
}

drives::CyclicHandle CoeTransport::output(std::uint16_t index, std::uint8_t subindex) const {
    return resolve(index, subindex, true);
}

drives::CyclicHandle CoeTransport::input(std::uint16_t index, std::uint8_t subindex) const {
    return resolve(index, subindex, false);
}

void CoeTransport::set_raw(drives::CyclicHandle h, std::uint64_t raw) {
    if (!h.valid() || static_cast<std::size_t>(h.slot) >= slots_.size()) {
        return;
    }
    const Slot& s = slots_[static_cast<std::size_t>(h.slot)];
    auto out = master_.outputs(slave_);
    if (!s.output || s.offset + s.bytes > out.size()) {
        return;
    }
    put_le_n(out.data() + s.offset, raw, s.bytes);
}

std::optional<std::uint64_t> CoeTransport::get_raw(drives::CyclicHandle h) const {
    if (!h.valid() || static_cast<std::size_t>(h.slot) >= slots_.size() ||
        master_.stats().cycles == 0) {
        return std::nullopt;
    }
    const Slot& s = slots_[static_cast<std::size_t>(h.slot)];
    // An input counts only once a frame brought the inputs in (the expected working counter,
    // ProcessDataStats::input_frames): until then the image holds its initial zeros, not the
    // slave's values. Frames short of OP's working counter (a slave still in SAFE-OP, the two
    // frames set_state_all() sends before OP) bring none, and an Axis that took the zeros for a
    // statusword (NOT READY TO SWITCH ON) ended a fault reset at once ("ok") on a drive still
    // in FAULT. The CANopen transport waits for the first TPDO the same way.
    if (!s.output && input_count(h).value_or(0) == 0) {
        return std::nullopt;
    }
    const auto in =
        s.output ? std::span<const std::uint8_t>(const_cast<Master&>(master_).outputs(slave_))
                 : master_.inputs(slave_);
    if (s.offset + s.bytes > in.size()) {
        return std::nullopt;
    }
    return get_le_n(in.data() + s.offset, s.bytes);
}

std::optional<std::uint64_t> CoeTransport::input_count(drives::CyclicHandle h) const {
    if (!h.valid() || static_cast<std::size_t>(h.slot) >= slots_.size() ||
        slots_[static_cast<std::size_t>(h.slot)].output) {
        return std::nullopt;
    }
    return master_.stats().input_frames;
}

} // namespace codrive::ethercat
