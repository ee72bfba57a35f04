// SPDX-License-Identifier: Apache-2.0
// Master process data: PDO assignment over CoE (1C12h/1C13h, ETG.1000.6 §5.6.7.4), SM2/SM3 and
// FMMU set-up, cyclic LRW with working-counter supervision.
#include "coe_transfer.hpp"

#include <codrive/ethercat/error.hpp>
#include <codrive/ethercat/master.hpp>
#include <codrive/ethercat/registers.hpp>

#include <fmt/format.h>

#include <algorithm>
#include <utility>

namespace codrive::ethercat {
namespace {

constexpr std::uint16_t kRxPdoAssign = 0x1C12;
constexpr std::uint16_t kTxPdoAssign = 0x1C13;
constexpr std::uint16_t kDefaultSm2 = 0x1100;
constexpr std::uint16_t kDefaultSm3 = 0x1180;

std::vector<PdoField> layout_of(const std::vector<PdoMapping>& pdos) {
    std::vector<PdoField> out;
    std::size_t bit = 0;
    for (const auto& p : pdos) {
        for (const auto& e : p.entries) {
            if (e.index != 0) { // index 0 entries are gaps (ETG.1000.6 §5.6.7.4.7)
                out.push_back({e, bit / 8});
            }
            bit += e.bits;
        }
    }
    return out;
}

std::size_t bytes_of(const std::vector<PdoMapping>& pdos) {
    std::size_t bits = 0;
    for (const auto& p : pdos) {
        bits += p.bits();
    }
    return (bits + 7) / 8;
}

} // namespace

VoidResult Master::configure_pdos(std::size_t slave, std::span<const PdoMapping> rx,
                                  std::span<const PdoMapping> tx) {
    const auto assign = [&](std::uint16_t assign_index,
                            std::span<const PdoMapping> pdos) -> VoidResult {
        if (auto r = sdo_write<std::uint8_t>(slave, assign_index, 0, 0); !r) {
            return r;
        }
        for (std::size_t i = 0; i < pdos.size(); ++i) {
            const PdoMapping& p = pdos[i];
            if (!p.entries.empty()) { // empty: keep the slave's (possibly fixed) mapping
                if (auto r = sdo_write<std::uint8_t>(slave, p.index, 0, 0); !r) {
                    return r;
                }
                for (std::size_t e = 0; e < p.entries.size(); ++e) {
                    if (auto r = sdo_write<std::uint32_t>(slave, p.index,
                                                          static_cast<std::uint8_t>(e + 1),
                                                          p.entries[e].encode());
                        !r) {
                        return r;
                    }
                }
                if (auto r = sdo_write<std::uint8_t>(slave, p.index, 0,
                                                     static_cast<std::uint8_t>(p.entries.size()));
                    !r) {
                    return r;
                }
            }
            if (auto r = sdo_write<std::uint16_t>(slave, assign_index,
                                                  static_cast<std::uint8_t>(i + 1), p.index);
                !r) {
                return r;
            }
        }
        return sdo_write<std::uint8_t>(slave, assign_index, 0,
                                       static_cast<std::uint8_t>(pdos.size()));
    };
    if (auto r = assign(kRxPdoAssign, rx); !r) {
        return r;
    }
    return assign(kTxPdoAssign, tx);
}

Result<std::pair<std::vector<PdoMapping>, std::vector<PdoMapping>>>
Master::read_pdo_assignment(std::size_t slave) {
    const auto read = [&](std::uint16_t assign_index) -> Result<std::vector<PdoMapping>> {
        auto n = sdo_read<std::uint8_t>(slave, assign_index, 0);
        if (!n) {
            return fail(n.error());
        }
        std::vector<PdoMapping> out;
        for (unsigned i = 1; i <= *n; ++i) {
            auto idx = sdo_read<std::uint16_t>(slave, assign_index, static_cast<std::uint8_t>(i));
            if (!idx) {
                return fail(idx.error());
            }
            PdoMapping p;
            p.index = *idx;
            auto count = sdo_read<std::uint8_t>(slave, p.index, 0);
            if (!count) {
                return fail(count.error());
            }
            for (unsigned e = 1; e <= *count; ++e) {
                auto v = sdo_read<std::uint32_t>(slave, p.index, static_cast<std::uint8_t>(e));
                if (!v) {
                    return fail(v.error());
                }
                p.entries.push_back(PdoEntry::decode(*v));
            }
            out.push_back(std::move(p));
        }
        return out;
    };
    auto rx = read(kRxPdoAssign);
    if (!rx) {
        return fail(rx.error());
    }
    auto tx = read(kTxPdoAssign);
    if (!tx) {
        return fail(tx.error());
    }
    return std::make_pair(std::move(*rx), std::move(*tx));
}

VoidResult Master::write_process_data_config(std::size_t slave, std::uint32_t logical_base) {
    const SlaveInfo& s = slaves_[slave];
    std::uint16_t sm2_start = kDefaultSm2;
    std::uint16_t sm3_start = kDefaultSm3;
    for (const auto& sm : s.sii.sync_managers) {
        if (sm.type == SmType::Outputs) {
            sm2_start = sm.start;
        } else if (sm.type == SmType::Inputs) {
            sm3_start = sm.start;
        }
    }
    SyncManager sm2;
    sm2.start = sm2_start;
    sm2.length = s.output_bytes;
    sm2.control = SyncManager::kDirWrite | 0x20 | SyncManager::kWatchdog; // 3-buffer
    sm2.activate = s.output_bytes > 0 ? 1 : 0;
    SyncManager sm3;
    sm3.start = sm3_start;
    sm3.length = s.input_bytes;
    sm3.control = 0x20; // 3-buffer, ECAT reads
    sm3.activate = s.input_bytes > 0 ? 1 : 0;
    std::array<std::uint8_t, 16> smb{};
    const auto e2 = sm2.encode();
    const auto e3 = sm3.encode();
    std::copy(e2.begin(), e2.end(), smb.begin());
    std::copy(e3.begin(), e3.end(), smb.begin() + 8);
    if (auto w = write_registers(slave, reg::sm(2), smb); !w) {
        return w;
    }
    Fmmu out;
    out.logical_start = logical_base + static_cast<std::uint32_t>(s.output_offset);
    out.length = s.output_bytes;
    out.physical_start = sm2_start;
    out.type = Fmmu::kWrite;
    out.activate = s.output_bytes > 0 ? 1 : 0;
    Fmmu in;
    in.logical_start = logical_base + static_cast<std::uint32_t>(s.input_offset);
    in.length = s.input_bytes;
    in.physical_start = sm3_start;
    in.type = Fmmu::kRead;
    in.activate = s.input_bytes > 0 ? 1 : 0;
    std::array<std::uint8_t, 32> fb{};
    const auto f0 = out.encode();
    const auto f1 = in.encode();
    std::copy(f0.begin(), f0.end(), fb.begin());
    std::copy(f1.begin(), f1.end(), fb.begin() + 16);
    if (auto w = write_registers(slave, reg::fmmu(0), fb); !w) {
        return w;
    }
    return {};
}

VoidResult Master::remap_slave(std::size_t slave) {
    SlaveInfo& s = slaves_[slave];
    if (s.sii.has_coe()) {
        // After a power cycle the slave may have its default PDO assignment (1C12h/1C13h)
        // again; the image was laid out for the one read at mapping time.
        auto a = read_pdo_assignment(slave);
        if (!a) {
            return fail(a.error());
        }
        if (bytes_of(a->first) != s.output_bytes || bytes_of(a->second) != s.input_bytes) {
            return set_error(make_error_code(EcatErrc::NotConfigured),
                             fmt::format("{}: came back with a different PDO layout ({} output / "
                                         "{} input bytes, mapped {} / {}): configure it in "
                                         "PRE-OP again, then map the process data anew",
                                         slave_label(slave), bytes_of(a->first),
                                         bytes_of(a->second), s.output_bytes, s.input_bytes));
        }
    }
    return write_process_data_config(slave, logical_base_);
}

VoidResult Master::map_process_data(std::uint32_t logical_base) {
    mapped_ = false;
    std::size_t out_total = 0;
    for (std::size_t i = 0; i < slaves_.size(); ++i) {
        SlaveInfo& s = slaves_[i];
        s.rx_pdos.clear();
        s.tx_pdos.clear();
        if (s.sii.has_coe()) {
            auto a = read_pdo_assignment(i);
            if (!a) {
                return fail(a.error());
            }
            s.rx_pdos = std::move(a->first);
            s.tx_pdos = std::move(a->second);
            s.output_bytes = static_cast<std::uint16_t>(bytes_of(s.rx_pdos));
            s.input_bytes = static_cast<std::uint16_t>(bytes_of(s.tx_pdos));
        } else {
            s.output_bytes = 0;
            s.input_bytes = 0;
            for (const auto& sm : s.sii.sync_managers) {
                if (sm.type == SmType::Outputs) {
                    s.output_bytes = sm.length;
                } else if (sm.type == SmType::Inputs) {
                    s.input_bytes = sm.length;
                }
            }
        }
        s.outputs_layout = layout_of(s.rx_pdos);
        s.inputs_layout = layout_of(s.tx_pdos);
        s.output_offset = out_total;
        out_total += s.output_bytes;
    }
    std::size_t in_total = 0;
    expected_wkc_ = 0;
    for (auto& s : slaves_) {
        s.input_offset = out_total + in_total;
        in_total += s.input_bytes;
        expected_wkc_ = static_cast<std::uint16_t>(expected_wkc_ + (s.output_bytes > 0 ? 2 : 0) +
                                                   (s.input_bytes > 0 ? 1 : 0));
    }
    if (out_total + in_total > kMaxDatagramData) {
        return set_error(make_error_code(EcatErrc::FrameTooLarge),
                         fmt::format("the process image ({} bytes) does not fit one frame",
                                     out_total + in_total));
    }
    for (std::size_t i = 0; i < slaves_.size(); ++i) {
        if (auto w = write_process_data_config(i, logical_base); !w) {
            return w;
        }
    }
    logical_base_ = logical_base;
    output_size_ = out_total;
    image_.assign(out_total + in_total, 0);
    al_probes_.assign(slaves_.size(), AlProbe{});
    al_control_.assign(slaves_.size(), 0);
    // Room for the largest frame (LRW, probes, AL control writes, one mailbox datagram per
    // slave) up front, so the cyclic path does not allocate.
    frame_.reserve(2 + 3 * slaves_.size());
    for (std::size_t i = 0; i < slaves_.size(); ++i) {
        channel(i);
    }
    mapped_ = true;
    return {};
}

std::span<std::uint8_t> Master::outputs(std::size_t slave) {
    if (!mapped_ || slave >= slaves_.size()) {
        return {};
    }
    return std::span<std::uint8_t>(image_).subspan(slaves_[slave].output_offset,
                                                   slaves_[slave].output_bytes);
}

std::span<const std::uint8_t> Master::inputs(std::size_t slave) const {
    if (!mapped_ || slave >= slaves_.size()) {
        return {};
    }
    return std::span<const std::uint8_t>(image_).subspan(slaves_[slave].input_offset,
                                                         slaves_[slave].input_bytes);
}

VoidResult Master::send_process_data() {
    if (!mapped_ || image_.empty()) {
        return set_error(make_error_code(EcatErrc::NotConfigured),
                         "process data is not mapped: bring the slaves to SAFE-OP first");
    }
    const TimePoint now = clock_.now();
    frame_used_ = 0;
    Datagram& lrw = add_datagram(Command::Lrw, 0, 0, image_.size());
    lrw.address = logical_base_;
    std::copy(image_.begin(), image_.end(), lrw.data.begin());
    dc_time_add();
    probes_add();
    al_control_add();
    // Mailbox traffic rides in the same frame, as much as fits: one datagram per slave whose
    // channel has something to do (ETG.1000.6 §5.6: mailbox access is plain FPWR/FPRD).
    const std::size_t before = frame_used_;
    mailbox_add(now);
    stats_.mailbox_datagrams += frame_used_ - before;
    const std::uint8_t idx = next_index();
    const auto frame = std::span<Datagram>(frame_.data(), frame_used_);
    for (auto& d : frame) {
        d.index = idx;
    }
    // Transfers mailbox_add() timed out end now even if the frame cannot go out: an interface
    // that stays down must not hold their callbacks back past their own timeout.
    auto n = encode_frame(frame, tx_buffer_);
    if (!n) {
        deliver_finished();
        return fail(n.error());
    }
    if (auto s = link_.send(std::span<const std::uint8_t>(tx_buffer_).first(*n)); !s) {
        ++stats_.send_errors;
        mailbox_unsent();
        deliver_finished(); // the frame never left: nothing in it is lost, it goes again
        // After the callbacks, which may set sentences of their own; put into words by
        // last_error(), as formatting here would allocate on the cyclic path.
        noted_error_ = s.error();
        cyclic_note_ = CyclicNote::SendError;
        return fail(s.error());
    }
    cyclic_index_ = idx;
    return {};
}

void Master::probes_add() {
    probe_first_ = -1;
    if (!probe_pending_ || probe_fresh_) {
        return;
    }
    if (frame_room() < slaves_.size() * (kDatagramOverhead + 6)) {
        return;
    }
    probe_first_ = static_cast<int>(frame_used_);
    for (const auto& s : slaves_) {
        add_datagram(Command::Fprd, s.station_address, reg::kAlStatus, 6);
    }
}

void Master::probes_done(bool lost) {
    if (probe_first_ < 0 || lost) {
        return;
    }
    for (std::size_t i = 0; i < slaves_.size() && i < al_probes_.size(); ++i) {
        const Datagram& d = frame_[static_cast<std::size_t>(probe_first_) + i];
        al_probes_[i].answered = d.wkc == 1;
        al_probes_[i].status = d.wkc == 1 ? AlStatus::decode(d.data) : AlStatus{};
    }
    probed_wkc_ = probe_wkc_;
    probe_pending_ = false;
    probe_fresh_ = true;
    probe_first_ = -1;
}

bool Master::queue_al_control(std::size_t slave, std::uint16_t value) {
    if (!mapped_ || slave >= al_control_.size() || value == 0) {
        return false;
    }
    al_control_[slave] = value;
    return true;
}

void Master::al_control_add() {
    al_control_first_ = -1;
    std::size_t count = 0;
    for (const std::uint16_t v : al_control_) {
        count += v != 0 ? 1U : 0U;
    }
    if (count == 0 || frame_room() < count * (kDatagramOverhead + 2)) {
        return;
    }
    al_control_first_ = static_cast<int>(frame_used_);
    for (std::size_t i = 0; i < al_control_.size(); ++i) {
        if (al_control_[i] != 0) {
            Datagram& d =
                add_datagram(Command::Fpwr, slaves_[i].station_address, reg::kAlControl, 2);
            put_le<std::uint16_t>(d.data.data(), al_control_[i]);
        }
    }
}

void Master::al_control_done(bool lost) {
    if (al_control_first_ < 0 || lost) {
        return; // still queued: the next frame carries it again
    }
    auto at = static_cast<std::size_t>(al_control_first_);
    for (auto& v : al_control_) {
        if (v != 0) {
            if (frame_[at].wkc == 1) {
                v = 0;
            }
            ++at;
        }
    }
    al_control_first_ = -1;
}

bool Master::take_al_probes() {
    const bool fresh = probe_fresh_;
    probe_fresh_ = false;
    return fresh;
}

void Master::give_up_cyclic_frame(bool counted_lost) {
    mark_overdue(*cyclic_index_, counted_lost);
    cyclic_index_.reset();
    // The datagrams that rode in it are lost with it: mailbox writes go again, reads that may
    // have emptied SM1 ask for a repeat, AL control writes stay queued, probes ask again.
    // Nothing waits here for them.
    mailbox_done(true, clock_.now());
    probes_done(true);
    al_control_done(true);
    deliver_finished();
}

Result<std::uint16_t> Master::receive_process_data(TimePoint deadline) {
    if (!cyclic_index_) {
        return fail(EcatErrc::NotConfigured);
    }
    const auto frame = std::span<Datagram>(frame_.data(), frame_used_);
    while (true) {
        auto r = link_.receive(rx_buffer_, deadline);
        if (!r) {
            const bool timeout = r.error() == CoreErrc::Timeout;
            last_wkc_mismatch_.reset();
            if (timeout) {
                ++stats_.lost_frames;
                ++stats_.consecutive_lost;
                stats_.max_consecutive_lost =
                    std::max(stats_.max_consecutive_lost, stats_.consecutive_lost);
            } else {
                // The link failed (the interface went down, say): whether the frame came back
                // is unknown. Not counted lost, so not late either; given up all the same.
                ++stats_.receive_errors;
            }
            give_up_cyclic_frame(timeout);
            // After the callbacks give_up_cyclic_frame() ran, which may set sentences of their
            // own: this call's failure is the one last_error() puts into words.
            noted_error_ = r.error();
            cyclic_note_ = timeout ? CyclicNote::FrameLost : CyclicNote::ReceiveError;
            return fail(timeout ? make_error_code(EcatErrc::NoResponse) : r.error());
        }
        const auto got = std::span<const std::uint8_t>(rx_buffer_).first(*r);
        const auto fi = frame_index(got);
        if (!fi || *fi != *cyclic_index_ || !decode_frame_into(got, frame)) {
            count_unawaited(fi);
            continue;
        }
        cyclic_index_.reset();
        ++stats_.cycles;
        stats_.consecutive_lost = 0;
        mailbox_done(false, clock_.now());
        probes_done(false);
        al_control_done(false);
        const std::uint16_t wkc = frame_[0].wkc;
        if (wkc != expected_wkc_) {
            ++stats_.wkc_errors;
            last_wkc_mismatch_ = wkc;
            if (!probe_pending_ && !probe_fresh_) {
                probe_pending_ = true; // the next frame asks every slave for its AL status
                probe_wkc_ = wkc;
            }
            deliver_finished();
            cyclic_note_ = CyclicNote::WorkingCounter; // put into words by last_error()
            noted_wkc_ = wkc;
            return fail(EcatErrc::WorkingCounter);
        }
        last_wkc_mismatch_.reset();
        ++stats_.input_frames;
        std::copy(frame_[0].data.begin() + static_cast<long>(output_size_), frame_[0].data.end(),
                  image_.begin() + static_cast<long>(output_size_));
        deliver_finished();
        return wkc;
    }
}

Result<std::uint16_t> Master::exchange_process_data() {
    if (auto s = send_process_data(); !s) {
        return fail(s.error());
    }
    return receive_process_data(clock_.now() + config_.frame_timeout);
}

const std::string& Master::last_error() const {
    switch (std::exchange(cyclic_note_, CyclicNote::None)) {
    case CyclicNote::FrameLost:
        last_error_ = fmt::format("cyclic LRW frame lost on {}: no answer in time", link_.name());
        break;
    case CyclicNote::ReceiveError:
        last_error_ = fmt::format("cyclic LRW frame given up on {}: cannot receive: {}",
                                  link_.name(), noted_error_.message());
        break;
    case CyclicNote::SendError:
        last_error_ = fmt::format("cyclic LRW frame not sent on {}: cannot send: {}", link_.name(),
                                  noted_error_.message());
        break;
    case CyclicNote::WorkingCounter:
        last_error_ =
            fmt::format("cyclic LRW working counter {}, expected {}", noted_wkc_, expected_wkc_);
        break;
    case CyclicNote::None:
        break;
    }
    return last_error_;
}

std::string Master::describe_wkc(std::uint16_t wkc, std::span<const AlProbe> probes) const {
    std::string head =
        fmt::format("cyclic LRW working counter {}, expected {}", wkc, expected_wkc_);
    std::vector<std::string> causes;
    for (std::size_t i = 0; i < probes.size(); ++i) {
        if (!probes[i].answered) {
            causes.push_back(fmt::format("{} does not answer", slave_label(i)));
            continue;
        }
        const AlStatus& st = probes[i].status;
        // The state and, with the error flag, why the slave left OP (0x001B: its SM watchdog
        // saw no process data in time; 0x001A: synchronisation lost).
        const std::string why = st.error ? fmt::format(" with AL status code 0x{:04X} ({})",
                                                       st.code, al_status_code_describe(st.code))
                                         : std::string();
        if (st.state != AlState::Op || st.error) {
            causes.push_back(
                fmt::format("{} is in {}{}", slave_label(i), to_string(st.state), why));
        }
    }
    if (causes.empty()) {
        return head + ": every slave answers now (a transient loss)";
    }
    std::string out = head + ": ";
    for (std::size_t i = 0; i < causes.size(); ++i) {
        out += (i == 0 ? "" : "; ") + causes[i];
    }
    return out;
}

std::string Master::diagnose_wkc(std::uint16_t wkc) {
    std::vector<Datagram> probes;
    for (const auto& s : slaves_) {
        probes.push_back(Datagram::physical(Command::Fprd, s.station_address, reg::kAlStatus, 6));
    }
    if (probes.empty() || !exchange(probes)) {
        return fmt::format("cyclic LRW working counter {}, expected {}", wkc, expected_wkc_) +
               ": no slave answers any more (cable or segment lost?)";
    }
    std::vector<AlProbe> results(probes.size());
    for (std::size_t i = 0; i < probes.size(); ++i) {
        results[i].answered = probes[i].wkc == 1;
        if (results[i].answered) {
            results[i].status = AlStatus::decode(probes[i].data);
        }
    }
    error_text() = describe_wkc(wkc, results);
    return last_error_;
}

} // namespace codrive::ethercat
