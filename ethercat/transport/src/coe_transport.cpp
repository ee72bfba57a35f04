// SPDX-License-Identifier: Apache-2.0
// CoE DriveTransport: SDO over the mailbox, process data from the LRW image.
#include <codrive/ethercat/coe_transport.hpp>

#include <fmt/format.h>

namespace codrive::ethercat {

CoeTransport::CoeTransport(Master& master, std::size_t slave) : master_(master), slave_(slave) {}

std::string CoeTransport::name() const {
    return master_.slave_label(slave_);
}

void CoeTransport::read(std::uint16_t index, std::uint8_t subindex, ReadDone done) {
    queue_.push_back(Request::read(index, subindex, std::move(done)));
}

void CoeTransport::write(std::uint16_t index, std::uint8_t subindex, drives::Bytes data,
                         WriteDone done) {
    queue_.push_back(Request::write(index, subindex, std::move(data), std::move(done)));
}

std::size_t CoeTransport::poll() {
    std::size_t n = 0;
    // Callbacks may queue more requests; run only those present now.
    for (std::size_t todo = queue_.size(); todo > 0; --todo) {
        Request r = std::move(queue_.front());
        queue_.pop_front();
        if (r.is_write) {
            auto w = master_.sdo_download(slave_, r.index, r.subindex, r.data);
            if (r.write_done) {
                r.write_done(
                    w ? drives::DriveVoid{}
                      : drives::drive_fail(drives::DriveErrc::Transport, master_.last_error()));
            }
        } else {
            auto v = master_.sdo_upload(slave_, r.index, r.subindex);
            if (r.read_done) {
                if (v) {
                    r.read_done(std::move(*v));
                } else {
                    r.read_done(
                        drives::drive_fail(drives::DriveErrc::Transport, master_.last_error()));
                }
            }
        }
        ++n;
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
    const ProcessDataStats& st = master_.stats();
    return st.cycles - st.wkc_errors;
}

} // namespace codrive::ethercat
