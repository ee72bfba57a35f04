// SPDX-License-Identifier: Apache-2.0
// Master process data: PDO assignment over CoE (1C12h/1C13h, ETG.1000.6 §5.6.7.4), SM2/SM3 and
// FMMU set-up, cyclic LRW with working-counter supervision.
#include <codrive/ethercat/error.hpp>
#include <codrive/ethercat/master.hpp>
#include <codrive/ethercat/registers.hpp>

#include <fmt/format.h>

#include <algorithm>

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
        for (std::uint8_t i = 1; i <= *n; ++i) {
            auto idx = sdo_read<std::uint16_t>(slave, assign_index, i);
            if (!idx) {
                return fail(idx.error());
            }
            PdoMapping p;
            p.index = *idx;
            auto count = sdo_read<std::uint8_t>(slave, p.index, 0);
            if (!count) {
                return fail(count.error());
            }
            for (std::uint8_t e = 1; e <= *count; ++e) {
                auto v = sdo_read<std::uint32_t>(slave, p.index, e);
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
        const SlaveInfo& s = slaves_[i];
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
        if (auto w = write_registers(i, reg::sm(2), smb); !w) {
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
        if (auto w = write_registers(i, reg::fmmu(0), fb); !w) {
            return w;
        }
    }
    logical_base_ = logical_base;
    output_size_ = out_total;
    image_.assign(out_total + in_total, 0);
    cyclic_[0] = Datagram::logical(Command::Lrw, logical_base, image_.size());
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
    Datagram& d = cyclic_[0];
    std::copy(image_.begin(), image_.end(), d.data.begin());
    d.wkc = 0;
    d.index = next_index();
    auto n = encode_frame(cyclic_, tx_buffer_);
    if (!n) {
        return fail(n.error());
    }
    cyclic_index_ = d.index;
    return link_.send(std::span<const std::uint8_t>(tx_buffer_).first(*n));
}

Result<std::uint16_t> Master::receive_process_data(TimePoint deadline) {
    if (!cyclic_index_) {
        return fail(EcatErrc::NotConfigured);
    }
    while (true) {
        auto r = link_.receive(rx_buffer_, deadline);
        if (!r) {
            if (r.error() == CoreErrc::Timeout) {
                ++stats_.lost_frames;
                last_wkc_mismatch_.reset();
                cyclic_index_.reset();
                last_error_ =
                    fmt::format("cyclic LRW frame lost on {}: no answer in time", link_.name());
                return fail(EcatErrc::NoResponse);
            }
            return fail(r.error());
        }
        const auto frame = std::span<const std::uint8_t>(rx_buffer_).first(*r);
        const auto fi = frame_index(frame);
        if (!fi || *fi != *cyclic_index_ || !decode_frame_into(frame, cyclic_)) {
            ++stats_.stale_frames;
            continue;
        }
        cyclic_index_.reset();
        ++stats_.cycles;
        const std::uint16_t wkc = cyclic_[0].wkc;
        if (wkc != expected_wkc_) {
            ++stats_.wkc_errors;
            last_wkc_mismatch_ = wkc;
            last_error_ =
                fmt::format("cyclic LRW working counter {}, expected {}", wkc, expected_wkc_);
            return fail(EcatErrc::WorkingCounter);
        }
        last_wkc_mismatch_.reset();
        std::copy(cyclic_[0].data.begin() + static_cast<long>(output_size_), cyclic_[0].data.end(),
                  image_.begin() + static_cast<long>(output_size_));
        return wkc;
    }
}

Result<std::uint16_t> Master::exchange_process_data() {
    if (auto s = send_process_data(); !s) {
        return fail(s.error());
    }
    return receive_process_data(clock_.now() + config_.frame_timeout);
}

std::string Master::diagnose_wkc(std::uint16_t wkc) {
    std::vector<Datagram> probes;
    for (const auto& s : slaves_) {
        probes.push_back(Datagram::physical(Command::Fprd, s.station_address, reg::kAlStatus, 6));
    }
    std::string head =
        fmt::format("cyclic LRW working counter {}, expected {}", wkc, expected_wkc_);
    if (probes.empty() || !exchange(probes)) {
        return head + ": no slave answers any more (cable or segment lost?)";
    }
    std::vector<std::string> causes;
    for (std::size_t i = 0; i < probes.size(); ++i) {
        if (probes[i].wkc != 1) {
            causes.push_back(fmt::format("{} does not answer", slave_label(i)));
            continue;
        }
        const AlStatus st = AlStatus::decode(probes[i].data);
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
    last_error_ = out;
    return out;
}

} // namespace codrive::ethercat
