// SPDX-License-Identifier: Apache-2.0
// Master: frame exchange with retries, register access, bring-up and SII (ETG.1000.4/.6).
#include "coe_transfer.hpp"

#include <codrive/ethercat/error.hpp>
#include <codrive/ethercat/master.hpp>
#include <codrive/ethercat/registers.hpp>

#include <fmt/format.h>

#include <algorithm>

namespace codrive::ethercat {

std::size_t PdoMapping::bits() const {
    std::size_t n = 0;
    for (const auto& e : entries) {
        n += e.bits;
    }
    return n;
}

std::string SlaveInfo::display_name() const {
    if (!sii.name.empty()) {
        return sii.name;
    }
    return fmt::format("0x{:08X}:0x{:08X}", sii.vendor_id, sii.product_code);
}

Master::Master(IEcatLink& link, IClock& clock, MasterConfig config)
    : link_(link), clock_(clock), config_(config) {}

std::string Master::slave_label(std::size_t slave) const {
    const std::size_t number = slave + config_.slave_label_base;
    if (slave < slaves_.size()) {
        return fmt::format("slave {} ({})", number, slaves_[slave].display_name());
    }
    return fmt::format("slave {}", number);
}

VoidResult Master::set_error(std::error_code ec, std::string sentence) {
    error_text() = std::move(sentence);
    return fail(ec);
}

VoidResult Master::check_slave(std::size_t slave) {
    if (slave >= slaves_.size()) {
        return set_error(make_error_code(EcatErrc::NoSuchSlave),
                         fmt::format("there is no slave at position {} ({} slaves found)", slave,
                                     slaves_.size()));
    }
    return {};
}

std::uint64_t Master::master_time_ns() const {
    // The EtherCAT system time counts from 2000-01-01; the master's monotonic clock gives a
    // stable base for offsets (absolute calendar time does not matter on a simulated segment).
    return static_cast<std::uint64_t>(
        std::chrono::duration_cast<nanoseconds>(clock_.now().time_since_epoch()).count());
}

void Master::count_unawaited(std::optional<std::uint8_t> index) {
    // A frame of ours whose deadline passed is late whatever it carries now; anything else read
    // while waiting (a corrupted frame, the awaited one garbled, one already read) is not.
    if (index && overdue_.test(*index)) {
        ++(overdue_cyclic_.test(*index) ? stats_.late_frames : stats_.late_other_frames);
        overdue_.reset(*index);
        overdue_cyclic_.reset(*index);
    } else {
        ++stats_.unreadable_frames;
    }
}

VoidResult Master::exchange(std::span<Datagram> datagrams) {
    const int attempts = std::max(1, config_.frame_retries);
    last_exchange_lost_ = 0; // attempts whose frame left and did not come back
    std::error_code unsent;  // the last attempt's send found the transmit queue full
    for (int attempt = 0; attempt < attempts; ++attempt) {
        const std::uint8_t idx = next_index();
        for (auto& d : datagrams) {
            d.index = idx;
        }
        auto n = encode_frame(datagrams, tx_buffer_);
        if (!n) {
            return set_error(
                n.error(), fmt::format("cannot build an EtherCAT frame: {}", n.error().message()));
        }
        unsent.clear();
        if (auto s = link_.send(std::span<const std::uint8_t>(tx_buffer_).first(*n)); !s) {
            ++stats_.send_errors;
            if (!transmit_queue_full(s.error())) {
                return set_error(s.error(), fmt::format("cannot send on {}: {}", link_.name(),
                                                        s.error().message()));
            }
            // No room for the frame: the attempt counts as lost. Its time passes (late frames
            // of earlier attempts are read meanwhile) and the next attempt sends again.
            unsent = s.error();
        }
        const TimePoint deadline = clock_.now() + config_.frame_timeout;
        while (true) {
            auto r = link_.receive(rx_buffer_, deadline);
            if (!r) {
                if (!unsent) { // an index that never left cannot come back late
                    mark_overdue(idx, false);
                }
                if (r.error() == CoreErrc::Timeout) {
                    // Only a frame that left can have been taken by a slave on its way (an
                    // SM1 read that emptied the mailbox: mailbox_read_once() asks for a repeat).
                    last_exchange_lost_ += unsent ? 0 : 1;
                    break;
                }
                return set_error(r.error(), fmt::format("cannot receive on {}: {}", link_.name(),
                                                        r.error().message()));
            }
            const auto frame = std::span<const std::uint8_t>(rx_buffer_).first(*r);
            const auto fi = frame_index(frame);
            if (!fi || *fi != idx || !decode_frame_into(frame, datagrams)) {
                count_unawaited(fi);
                continue;
            }
            return {};
        }
    }
    if (unsent) {
        return set_error(unsent, fmt::format("cannot send on {}: {} (the transmit queue was "
                                             "still full at the last of {} attempts of {:.1f} ms)",
                                             link_.name(), unsent.message(), attempts,
                                             to_ms(config_.frame_timeout)));
    }
    return set_error(make_error_code(EcatErrc::NoResponse),
                     fmt::format("no EtherCAT frame came back on {} ({} {} datagram(s), {} "
                                 "attempts of {:.1f} ms): is the segment connected?",
                                 link_.name(), datagrams.size(), to_string(datagrams[0].command),
                                 attempts, to_ms(config_.frame_timeout)));
}

Result<std::vector<std::uint8_t>> Master::read_registers(std::size_t slave, std::uint16_t reg,
                                                         std::size_t size) {
    if (auto c = check_slave(slave); !c) {
        return fail(c.error());
    }
    std::array<Datagram, 1> d{
        Datagram::physical(Command::Fprd, slaves_[slave].station_address, reg, size)};
    if (auto e = exchange(d); !e) {
        return fail(e.error());
    }
    if (d[0].wkc != 1) {
        error_text() = fmt::format("{}: FPRD of register 0x{:04X} returned working counter {}, "
                                   "expected 1: the slave does not answer",
                                   slave_label(slave), reg, d[0].wkc);
        return fail(EcatErrc::WorkingCounter);
    }
    return std::move(d[0].data);
}

VoidResult Master::write_registers(std::size_t slave, std::uint16_t reg,
                                   std::span<const std::uint8_t> data) {
    if (auto c = check_slave(slave); !c) {
        return c;
    }
    std::array<Datagram, 1> d{
        Datagram::physical(Command::Fpwr, slaves_[slave].station_address, reg, data)};
    if (auto e = exchange(d); !e) {
        return e;
    }
    if (d[0].wkc != 1) {
        return set_error(make_error_code(EcatErrc::WorkingCounter),
                         fmt::format("{}: FPWR of register 0x{:04X} returned working counter {}, "
                                     "expected 1: the slave does not answer",
                                     slave_label(slave), reg, d[0].wkc));
    }
    return {};
}

Result<std::uint16_t> Master::count_slaves() {
    std::array<Datagram, 1> d{Datagram::physical(Command::Brd, 0, reg::kType, 2)};
    if (auto e = exchange(d); !e) {
        return fail(e.error());
    }
    return d[0].wkc;
}

VoidResult Master::scan() {
    // Transfers queued for the old slave list end here, with a sentence, not silently.
    const TimePoint now = clock_.now();
    for (std::size_t i = 0; i < channels_.size() && i < slaves_.size(); ++i) {
        auto& ch = *channels_[i];
        while (!ch.queue.empty()) {
            ch.active = true;
            const auto& t = *ch.queue.front();
            mailbox_fail(
                i, make_error_code(EcatErrc::NotConfigured),
                fmt::format("{}: {} cancelled: the segment is scanned again", t.label, t.what),
                now);
        }
    }
    deliver_finished();
    channels_.clear();
    slaves_.clear();
    mapped_ = false;
    dc_reference_.reset();
    auto count = count_slaves();
    if (!count) {
        return fail(count.error());
    }
    if (*count == 0) {
        return set_error(make_error_code(EcatErrc::NoSlaves),
                         fmt::format("no EtherCAT slave answered on {}: the broadcast read came "
                                     "back with working counter 0",
                                     link_.name()));
    }
    if (*count > config_.max_slaves) {
        return set_error(make_error_code(EcatErrc::WorkingCounter),
                         fmt::format("the broadcast read on {} counted {} slaves, more than the "
                                     "{} this master accepts (MasterConfig::max_slaves): a "
                                     "corrupted frame or a device that is not an EtherCAT slave",
                                     link_.name(), *count, config_.max_slaves));
    }
    // Before the reset: the state each slave was left in (by position, all in one frame).
    std::vector<Datagram> found;
    for (std::uint16_t i = 0; i < *count; ++i) {
        found.push_back(Datagram::physical(Command::Aprd, static_cast<std::uint16_t>(0U - i),
                                           reg::kAlStatus, 6));
    }
    std::vector<SlaveInfo> found_info(*count);
    for (std::size_t off = 0; off < found.size(); off += 64) {
        std::span<Datagram> chunk(found.data() + off,
                                  std::min<std::size_t>(64, found.size() - off));
        if (auto e = exchange(chunk); !e) {
            return e;
        }
        for (std::size_t i = 0; i < chunk.size(); ++i) {
            if (chunk[i].wkc == 0) {
                // Positions are contiguous: nothing answers past the end of the segment.
                return set_error(make_error_code(EcatErrc::WorkingCounter),
                                 fmt::format("the broadcast read on {} counted {} slaves, but "
                                             "position {} does not answer: a slave left the "
                                             "segment during the scan or the count was corrupted",
                                             link_.name(), *count, off + i));
            }
            if (chunk[i].wkc == 1 && chunk[i].data.size() >= 6) {
                const AlStatus st = AlStatus::decode(chunk[i].data);
                SlaveInfo& f = found_info[off + i];
                f.found_state = st.state;
                f.found_error = st.error;
                f.found_code = st.code;
            }
        }
    }
    // Reset in one frame: INIT with error acknowledge, FMMUs and SMs cleared, DC SYNC off, EEPROM
    // owned by EtherCAT (ETG.1000.6 §6.4: the master starts every slave from a known INIT).
    const std::array<std::uint8_t, 2> init_ack{static_cast<std::uint8_t>(AlState::Init) | 0x10, 0};
    std::vector<Datagram> reset{
        Datagram::physical(Command::Bwr, 0, reg::kAlControl, init_ack),
        Datagram::physical(Command::Bwr, 0, reg::kFmmu0, 16 * 16),
        Datagram::physical(Command::Bwr, 0, reg::kSm0, 8 * 8),
        Datagram::physical(Command::Bwr, 0, reg::kDcActivation, 1),
        Datagram::physical(Command::Bwr, 0, reg::kSiiConfig, 2),
    };
    if (auto e = exchange(reset); !e) {
        return e;
    }
    // Station addresses by position: every APWR in one frame.
    std::vector<Datagram> addr;
    for (std::uint16_t i = 0; i < *count; ++i) {
        std::array<std::uint8_t, 2> a{};
        put_le<std::uint16_t>(a.data(),
                              static_cast<std::uint16_t>(config_.first_station_address + i));
        addr.push_back(Datagram::physical(Command::Apwr, static_cast<std::uint16_t>(0U - i),
                                          reg::kStationAddress, a));
    }
    for (std::size_t off = 0; off < addr.size(); off += 64) {
        std::span<Datagram> chunk(addr.data() + off, std::min<std::size_t>(64, addr.size() - off));
        if (auto e = exchange(chunk); !e) {
            return e;
        }
        for (std::size_t i = 0; i < chunk.size(); ++i) {
            if (chunk[i].wkc != 1) {
                return set_error(make_error_code(EcatErrc::WorkingCounter),
                                 fmt::format("slave {}: setting the station address returned "
                                             "working counter {}, expected 1",
                                             off + i + config_.slave_label_base, chunk[i].wkc));
            }
        }
    }
    for (std::uint16_t i = 0; i < *count; ++i) {
        SlaveInfo s = found_info[i];
        s.position = i;
        s.station_address = static_cast<std::uint16_t>(config_.first_station_address + i);
        slaves_.push_back(std::move(s));
    }
    for (std::size_t i = 0; i < slaves_.size(); ++i) {
        auto sii = read_sii_info(i);
        if (!sii) {
            return fail(sii.error());
        }
        slaves_[i].sii = std::move(*sii);
        auto features = read_register<std::uint16_t>(i, reg::kFeatures);
        if (!features) {
            return fail(features.error());
        }
        slaves_[i].has_dc = (*features & 0x0004) != 0;
        auto st = read_al_status(i);
        if (!st) {
            return fail(st.error());
        }
        slaves_[i].state = st->state;
    }
    return {};
}

Result<std::vector<std::uint8_t>> Master::read_sii(std::size_t slave, std::uint16_t word_address,
                                                   std::size_t words) {
    if (auto c = check_slave(slave); !c) {
        return fail(c.error());
    }
    std::vector<std::uint8_t> out;
    out.reserve(words * 2);
    std::uint32_t addr = word_address;
    while (out.size() < words * 2) {
        // Command: read at `addr` (0x0502 control + 0x0504 address in one write).
        std::array<std::uint8_t, 6> cmd{};
        put_le<std::uint16_t>(cmd.data(), sii_ctl::kRead);
        put_le<std::uint32_t>(cmd.data() + 2, addr);
        if (auto w = write_registers(slave, reg::kSiiControl, cmd); !w) {
            return fail(w.error());
        }
        const TimePoint deadline = clock_.now() + config_.sii_timeout;
        while (true) {
            // Status, address and data in one read: 0x0502..0x050F.
            auto st = read_registers(slave, reg::kSiiControl, 14);
            if (!st) {
                return fail(st.error());
            }
            const auto status = get_le<std::uint16_t>(st->data());
            if ((status & sii_ctl::kBusy) == 0) {
                if ((status & sii_ctl::kErrorMask) != 0) {
                    error_text() = fmt::format("{}: SII EEPROM read at word 0x{:04X} failed "
                                               "(status 0x{:04X})",
                                               slave_label(slave), addr, status);
                    return fail(EcatErrc::SiiError);
                }
                const std::size_t n = (status & sii_ctl::kReadSize8) != 0 ? 8 : 4;
                out.insert(out.end(), st->begin() + 6, st->begin() + 6 + static_cast<long>(n));
                addr += static_cast<std::uint32_t>(n / 2);
                break;
            }
            if (clock_.now() >= deadline) {
                error_text() = fmt::format("{}: the SII EEPROM stayed busy for {:.0f} ms at word "
                                           "0x{:04X}",
                                           slave_label(slave), to_ms(config_.sii_timeout), addr);
                return fail(EcatErrc::SiiTimeout);
            }
            link_.idle(microseconds(50));
        }
    }
    out.resize(words * 2);
    return out;
}

Result<SiiInfo> Master::read_sii_info(std::size_t slave) {
    auto image = read_sii(slave, 0, sii_addr::kFirstCategory);
    if (!image) {
        return fail(image.error());
    }
    // Categories follow; read them in chunks until the End marker (bounded by 8 KiB EEPROMs).
    constexpr std::size_t kChunkWords = 64;
    while (!sii_categories_end(*image)) {
        if (image->size() >= 8192) {
            error_text() = fmt::format("{}: the SII EEPROM has no end-of-categories marker",
                                       slave_label(slave));
            return fail(EcatErrc::SiiError);
        }
        auto more = read_sii(slave, static_cast<std::uint16_t>(image->size() / 2), kChunkWords);
        if (!more) {
            return fail(more.error());
        }
        image->insert(image->end(), more->begin(), more->end());
    }
    auto info = parse_sii(*image);
    if (!info) {
        error_text() = fmt::format("{}: the SII EEPROM content is malformed", slave_label(slave));
    }
    return info;
}

Result<Master::AlStatus> Master::read_al_status(std::size_t slave) {
    auto d = read_registers(slave, reg::kAlStatus, 6);
    if (!d) {
        return fail(d.error());
    }
    return AlStatus::decode(*d);
}

VoidResult Master::setup_mailbox_sms(std::size_t slave) {
    const SiiInfo& sii = slaves_[slave].sii;
    if (!sii.has_mailbox()) {
        return {};
    }
    SyncManager sm0;
    sm0.start = sii.rx_mailbox_offset;
    sm0.length = sii.rx_mailbox_size;
    sm0.control = SyncManager::kModeMailbox | SyncManager::kDirWrite | 0x20;
    sm0.activate = SyncManager::kActivateEnable;
    SyncManager sm1;
    sm1.start = sii.tx_mailbox_offset;
    sm1.length = sii.tx_mailbox_size;
    sm1.control = SyncManager::kModeMailbox | 0x20;
    sm1.activate = SyncManager::kActivateEnable;
    std::array<std::uint8_t, 16> b{};
    const auto e0 = sm0.encode();
    const auto e1 = sm1.encode();
    std::copy(e0.begin(), e0.end(), b.begin());
    std::copy(e1.begin(), e1.end(), b.begin() + 8);
    return write_registers(slave, reg::sm(0), b);
}

VoidResult Master::request_state(std::size_t slave, AlState target) {
    if (auto c = check_slave(slave); !c) {
        return c;
    }
    auto before = read_al_status(slave);
    if (!before) {
        return fail(before.error());
    }
    if (before->error) {
        // A pending error blocks every request until acknowledged (ETG.1000.6 §6.4.1.3).
        if (auto a = write_register<std::uint16_t>(
                slave, reg::kAlControl,
                static_cast<std::uint16_t>(static_cast<unsigned>(before->state) | kAlErrorFlag));
            !a) {
            return a;
        }
    }
    if (target == AlState::PreOp && before->state == AlState::Init) {
        if (auto m = setup_mailbox_sms(slave); !m) {
            return m;
        }
    }
    if (auto w = write_register<std::uint16_t>(slave, reg::kAlControl,
                                               static_cast<std::uint16_t>(target));
        !w) {
        return w;
    }
    const TimePoint deadline = clock_.now() + config_.state_timeout;
    while (true) {
        auto st = read_al_status(slave);
        if (!st) {
            return fail(st.error());
        }
        if (st->error) {
            write_register<std::uint16_t>(
                slave, reg::kAlControl,
                static_cast<std::uint16_t>(static_cast<unsigned>(st->state) | kAlErrorFlag));
            slaves_[slave].state = st->state;
            return set_error(
                make_error_code(EcatErrc::StateChangeRefused),
                fmt::format("{}: state change {} → {} refused with AL status code 0x{:04X} ({}); "
                            "the slave stays in {}",
                            slave_label(slave), to_string(before->state), to_string(target),
                            st->code, al_status_code_describe(st->code), to_string(st->state)));
        }
        if (st->state == target) {
            slaves_[slave].state = target;
            return {};
        }
        if (clock_.now() >= deadline) {
            slaves_[slave].state = st->state;
            return set_error(make_error_code(EcatErrc::StateChangeTimeout),
                             fmt::format("{}: state change {} → {} not done after {:.0f} ms "
                                         "(still {})",
                                         slave_label(slave), to_string(before->state),
                                         to_string(target), to_ms(config_.state_timeout),
                                         to_string(st->state)));
        }
        link_.idle(microseconds(200));
    }
}

VoidResult Master::set_state_all(AlState target) {
    const auto rank = [](AlState s) {
        switch (s) {
        case AlState::PreOp:
            return 1;
        case AlState::SafeOp:
            return 2;
        case AlState::Op:
            return 3;
        default:
            return 0;
        }
    };
    const std::array<AlState, 3> up{AlState::PreOp, AlState::SafeOp, AlState::Op};
    // The cached states are what this master last set; a slave may have left them by itself
    // (SM watchdog: SAFE-OP + 0x001B; power cycle: INIT). Read each one's AL status first.
    std::vector<bool> fallen(slaves_.size(), false);
    for (std::size_t i = 0; i < slaves_.size(); ++i) {
        auto st = read_al_status(i);
        if (!st) {
            return fail(st.error());
        }
        fallen[i] = mapped_ && rank(st->state) < 2 && rank(slaves_[i].state) >= 2;
        slaves_[i].state = st->state;
    }
    // Down first: any slave above the target goes straight down.
    for (std::size_t i = 0; i < slaves_.size(); ++i) {
        if (rank(slaves_[i].state) > rank(target) || slaves_[i].state == AlState::Boot) {
            if (auto r = request_state(i, target); !r) {
                return r;
            }
            if (rank(target) < 2) {
                mapped_ = false;
            }
        }
    }
    for (AlState step : up) {
        if (rank(step) > rank(target)) {
            break;
        }
        if (step == AlState::SafeOp && !mapped_) {
            if (auto m = map_process_data(); !m) {
                return m;
            }
        } else if (step == AlState::SafeOp) {
            // Back in PRE-OP after a fall below SAFE-OP: its SMs and FMMUs are gone.
            for (std::size_t i = 0; i < slaves_.size(); ++i) {
                if (fallen[i]) {
                    if (auto m = remap_slave(i); !m) {
                        return m;
                    }
                }
            }
        }
        if (step == AlState::Op) {
            // Slaves expect valid outputs before OP (ETG.1000.6 §6.4.2.4: SAFE-OP → OP). In
            // SAFE-OP they do not take them (the output SM is disabled), so the working counter
            // is short by 2 per slave with outputs by design: not an error to count.
            const auto wkc_errors = stats_.wkc_errors;
            for (int i = 0; i < 2; ++i) {
                (void)exchange_process_data();
            }
            stats_.wkc_errors = wkc_errors;
            probe_pending_ = false; // nothing to diagnose: the short WKC was expected
            probe_fresh_ = false;
        }
        for (std::size_t i = 0; i < slaves_.size(); ++i) {
            if (rank(slaves_[i].state) < rank(step)) {
                if (auto r = request_state(i, step); !r) {
                    return r;
                }
            }
        }
    }
    return {};
}

} // namespace codrive::ethercat
