// SPDX-License-Identifier: Apache-2.0
// Simulated ESC: datagram processing with working counters (ETG.1000.4 §5.4), sync manager
// mailbox/buffer rules and FMMUs (ET1100 datasheet §2/§8), SII EEPROM interface, DC registers
// (ETG.1000.4 §9) and the process data watchdog. The ESM is in ecat_esc_state_machine.cpp, the
// mailbox queue in ecat_esc_mailbox.cpp.
#include <codrive/sim/ecat/esc_slave.hpp>

#include <codrive/core/endian.hpp>
#include <codrive/ethercat/mailbox.hpp>

#include <algorithm>

namespace codrive::sim::ecat {

using namespace codrive::ethercat;

namespace {

bool read_only_register(std::uint32_t a) {
    return a < 0x0010 || (a >= 0x0110 && a < 0x0112) || (a >= 0x0130 && a < 0x0140) ||
           (a >= 0x0800 && a < 0x0880 && ((a - 0x0800) % 8 == 5 || (a - 0x0800) % 8 == 7)) ||
           (a >= 0x0900 && a < 0x0910) || (a >= 0x0918 && a < 0x0920) ||
           (a >= 0x092C && a < 0x0930);
}

bool overlaps(std::uint32_t a, std::size_t len, std::uint32_t b, std::size_t blen) {
    return a < b + blen && b < a + len;
}

// ET1100 datasheet: process data watchdog status (bit 0) and expiry counter.
constexpr std::uint16_t kWatchdogStatus = 0x0440;
constexpr std::uint16_t kWatchdogCounter = 0x0442;

} // namespace

EscSlave::EscSlave(SiiInfo sii, std::unique_ptr<EcatApplication> app, bool has_dc)
    : sii_(std::move(sii)), eeprom_(build_sii(sii_)), app_(std::move(app)) {
    coe_ = std::make_unique<CoeServer>(app_->od(), sii_.tx_mailbox_size);
    if (sii_.has_foe()) {
        foe_ = std::make_unique<FoeServer>(sii_.rx_mailbox_size, sii_.tx_mailbox_size);
    }
    mem_[reg::kType] = 0x11;
    mem_[reg::kRevision] = 0x02;
    mem_[reg::kFmmuCount] = 8;
    mem_[reg::kSmCount] = 8;
    mem_[reg::kRamSize] = 8;
    mem_[reg::kPortDescriptor] = 0x0F;
    put_le<std::uint16_t>(mem_.data() + reg::kFeatures, has_dc ? 0x0004 : 0x0000);
    put_le<std::uint16_t>(mem_.data() + reg::kStationAlias, sii_.alias);
    // Process data watchdog defaults (ET1100 datasheet): divider 2498+2 ticks of 40 ns = 100 µs,
    // 1000 of those = 100 ms; 0x0440 bit 0 = 1: not expired.
    put_le<std::uint16_t>(mem_.data() + reg::kWatchdogDivider, 2498);
    put_le<std::uint16_t>(mem_.data() + reg::kWatchdogProcessData, 1000);
    mem_[kWatchdogStatus] = 0x01;
    set_al_status(AlState::Init, false, 0);
    // Every simulated clock starts somewhere else, as real free-running ESC clocks do.
    dc_clock_ = DcClock(static_cast<std::int64_t>((sii_.serial % 97) + 1) * 1'000'000'007LL, 0);
    // Mean over 2^4 samples for 0x092C (model default; the loop is described in dc_clock.hpp).
    mem_[reg::kDcSystemTimeDifferenceFilterDepth] = 4;
}

std::uint16_t EscSlave::reg16(std::uint16_t addr) const {
    return get_le<std::uint16_t>(mem_.data() + addr);
}

std::uint16_t EscSlave::station_address() const {
    return reg16(reg::kStationAddress);
}

std::uint16_t EscSlave::al_status_code() const {
    return reg16(reg::kAlStatusCode);
}

SyncManager EscSlave::sm(unsigned n) const {
    return SyncManager::decode(std::span<const std::uint8_t>(mem_).subspan(reg::sm(n), 8));
}

void EscSlave::set_sm_status(unsigned n, std::uint8_t status) {
    mem_[reg::sm(n) + 5U] = status;
}

void EscSlave::set_al_status(AlState s, bool error, std::uint16_t code, bool injected) {
    // The slave's firmware writes the AL status code: a drive reports only the codes its manual
    // lists (AKD2G §3.1). A refusal a test injects keeps the code it asked for.
    if (!injected && code != al_code::kNoError) {
        code = app_->al_status_code(code);
    }
    put_le<std::uint16_t>(
        mem_.data() + reg::kAlStatus,
        static_cast<std::uint16_t>(static_cast<unsigned>(s) | (error ? kAlErrorFlag : 0U)));
    put_le<std::uint16_t>(mem_.data() + reg::kAlStatusCode, code);
}

bool EscSlave::write_allowed_by_sm(std::uint16_t addr, std::size_t len) {
    for (unsigned n = 0; n < 2; ++n) {
        const SyncManager s = sm(n);
        if (!s.enabled() || !s.is_mailbox() || !overlaps(addr, len, s.start, s.length)) {
            continue;
        }
        if (!s.master_writes() || mailbox_in_full_) {
            return false;
        }
    }
    return true;
}

bool EscSlave::read_allowed_by_sm(std::uint16_t addr, std::size_t len) {
    for (unsigned n = 0; n < 2; ++n) {
        const SyncManager s = sm(n);
        if (!s.enabled() || !s.is_mailbox() || !overlaps(addr, len, s.start, s.length)) {
            continue;
        }
        if (s.master_writes() || !mailbox_out_full_) {
            return false;
        }
    }
    return true;
}

void EscSlave::after_sm_write(std::uint16_t addr, std::size_t len) {
    for (unsigned n = 0; n < 4; ++n) {
        const SyncManager s = sm(n);
        if (!s.enabled() || s.length == 0 || !s.master_writes()) {
            continue;
        }
        const std::uint32_t last = s.start + s.length - 1U;
        if (last >= addr && last < addr + len) {
            // Writing the buffer's last byte completes it (ET1100 datasheet §8.2).
            if (s.is_mailbox()) {
                mailbox_in_full_ = true;
                set_sm_status(n, SyncManager::kStatusMailboxFull);
            } else {
                outputs_fresh_ = true;
            }
        }
    }
}

void EscSlave::after_sm_read(std::uint16_t addr, std::size_t len) {
    for (unsigned n = 0; n < 2; ++n) {
        const SyncManager s = sm(n);
        if (!s.enabled() || !s.is_mailbox() || s.master_writes() || s.length == 0) {
            continue;
        }
        const std::uint32_t last = s.start + s.length - 1U;
        if (last >= addr && last < addr + len) {
            mailbox_out_full_ = false;
            last_read_ = std::move(sm1_message_);
            sm1_message_.clear();
            set_sm_status(n, 0);
            load_mailbox_out();
        }
    }
}

bool EscSlave::read_memory(std::uint16_t addr, std::span<std::uint8_t> out, bool or_into,
                           TimePoint now) {
    // As write_memory(): a read that runs past the end of the ESC's memory reads the part inside
    // it and leaves the rest of the datagram as it came; the ESC datasheets and ETG.1000 do not
    // say what an access across 0xFFFF does (docs/conformance.md).
    const auto data = out.first(std::min<std::size_t>(out.size(), mem_.size() - addr));
    if (!read_allowed_by_sm(addr, data.size())) {
        return false;
    }
    if (overlaps(addr, data.size(), reg::kDcSystemTime, 8)) {
        refresh_dc(now);
    }
    for (std::size_t i = 0; i < data.size(); ++i) {
        data[i] = or_into ? static_cast<std::uint8_t>(data[i] | mem_[addr + i]) : mem_[addr + i];
    }
    after_sm_read(addr, data.size());
    return true;
}

void EscSlave::write_memory(std::uint16_t addr, std::span<const std::uint8_t> in, TimePoint now) {
    // Physical addresses are 16 bits: a write that runs past the end of the ESC's memory (an
    // FMMU whose physical start a master put near 0xFFFF, or an ARMW/FRMW datagram) lands only
    // in the part inside it, as sm_end() bounds process data.
    const auto data = in.first(std::min<std::size_t>(in.size(), mem_.size() - addr));
    for (std::size_t i = 0; i < data.size(); ++i) {
        const std::uint32_t a = addr + static_cast<std::uint32_t>(i);
        if (!read_only_register(a)) {
            mem_[a] = data[i];
        }
    }
    after_sm_write(addr, data.size());
    if (overlaps(addr, data.size(), reg::kAlControl, 2)) {
        on_al_control(reg16(reg::kAlControl));
    }
    if (overlaps(addr, data.size(), reg::kSiiControl, 2)) {
        on_sii_control();
    }
    if ((reg16(reg::kFeatures) & 0x0004) == 0) {
        return; // no DC unit
    }
    if (overlaps(addr, data.size(), reg::kDcSystemTimeOffset, 8)) {
        dc_clock_.reset(now); // a new offset: the drift control starts over
    }
    if (addr == reg::kDcSystemTime && (data.size() == 4 || data.size() == 8)) {
        on_system_time_write(data, now);
    }
}

bool EscSlave::logical(const DatagramRef& dg, bool& read_done, bool& write_done, TimePoint now) {
    // Process data moves only in SAFE-OP (inputs) and OP: below, the application keeps SM2/SM3
    // off.
    if (state_ != AlState::SafeOp && state_ != AlState::Op) {
        return false;
    }
    const std::uint32_t start = dg.address();
    const std::size_t len = dg.data.size();
    for (unsigned f = 0; f < 8; ++f) {
        const Fmmu fm = Fmmu::decode(std::span<const std::uint8_t>(mem_).subspan(reg::fmmu(f), 16));
        if ((fm.activate & 1) == 0 || fm.length == 0 ||
            !overlaps(start, len, fm.logical_start, fm.length)) {
            continue;
        }
        // In 64 bits: a window that a master placed at the top of the 4 GiB logical space
        // would wrap in 32 and seem longer than the datagram.
        const std::uint64_t ov_start = std::max(start, fm.logical_start);
        const std::uint64_t ov_end = std::min<std::uint64_t>(
            std::uint64_t{start} + len, std::uint64_t{fm.logical_start} + fm.length);
        const auto n = static_cast<std::size_t>(ov_end - ov_start);
        const auto phys =
            static_cast<std::uint16_t>(fm.physical_start + (ov_start - fm.logical_start));
        auto window = dg.data.subspan(static_cast<std::size_t>(ov_start - start), n);
        if ((fm.type & Fmmu::kRead) != 0 && command_reads(dg.command)) {
            read_done = read_memory(phys, window, false, now) || read_done;
        }
        // Outputs only in OP: in SAFE-OP the application keeps the output sync manager
        // disabled (PDI), so writes neither land nor count — a master sees a slave that left OP
        // (its SM watchdog expired, an error) as a working counter short by 2 per LRW.
        if ((fm.type & Fmmu::kWrite) != 0 && command_writes(dg.command) && state_ == AlState::Op) {
            write_memory(phys, window, now);
            write_done = true;
        }
    }
    return read_done || write_done;
}

void EscSlave::update_dl_status(const ChainContext& ctx) {
    // Port 0 faces the master and is open with communication; port 1 is open towards the next
    // slave, closed (loop) on the last one; ports 2 and 3 (not implemented, 0x0007) are closed
    // (ETG.1000.4 §6.1.4). A master reads its line topology from this (SOEM's "activeports").
    namespace dl = dl_status;
    auto v =
        static_cast<std::uint16_t>(dl::kPdiOperational | dl::kPdiWatchdogOk | dl::link(0) |
                                   dl::communication(0) | dl::loop_closed(2) | dl::loop_closed(3));
    if (ctx.position + 1 < ctx.chain_length) {
        v = static_cast<std::uint16_t>(v | dl::link(1) | dl::communication(1));
    } else {
        v = static_cast<std::uint16_t>(v | dl::loop_closed(1));
    }
    put_le<std::uint16_t>(mem_.data() + reg::kDlStatus, v);
}

void EscSlave::process(const DatagramRef& dg, const ChainContext& ctx) {
    if (faults_.silent) {
        return;
    }
    update_dl_status(ctx);
    bool addressed = false;
    const Addressing mode = addressing_of(dg.command);
    switch (mode) {
    case Addressing::AutoIncrement:
        addressed = dg.adp() == 0;
        dg.set_adp(static_cast<std::uint16_t>(dg.adp() + 1));
        break;
    case Addressing::Configured:
        addressed = dg.adp() == station_address();
        break;
    case Addressing::Broadcast:
        addressed = true;
        dg.set_adp(static_cast<std::uint16_t>(dg.adp() + 1));
        break;
    case Addressing::Logical:
    case Addressing::None:
        break;
    }
    bool read_done = false;
    bool write_done = false;
    const std::uint16_t ado = dg.ado();
    // The frame reaches this slave `position` hops after the first one (the same model as the
    // receive time latches): its DC registers are read and written at that instant, so clocks
    // in sync show the same time at the same instant and a master's delay compensation holds.
    const TimePoint at = ctx.now + nanoseconds(static_cast<std::int64_t>(ctx.position) * kDcHopNs);
    if (mode == Addressing::Logical) {
        logical(dg, read_done, write_done, ctx.now);
    } else if (dg.command == Command::Armw || dg.command == Command::Frmw) {
        if (addressed) {
            read_done = read_memory(ado, dg.data, false, at);
        } else if (write_allowed_by_sm(ado, dg.data.size())) {
            write_memory(ado, dg.data, at);
            write_done = true;
        }
    } else if (addressed) {
        if (mode == Addressing::Broadcast && dg.command == Command::Bwr &&
            ado == reg::kDcReceiveTimePort0) {
            latch_receive_times(ctx);
            write_done = true;
        } else {
            std::vector<std::uint8_t> incoming;
            if (command_writes(dg.command) && command_reads(dg.command)) {
                incoming.assign(dg.data.begin(), dg.data.end());
            }
            if (command_reads(dg.command)) {
                read_done = read_memory(ado, dg.data, dg.command == Command::Brd, at);
            }
            if (command_writes(dg.command)) {
                std::span<const std::uint8_t> src = incoming.empty()
                                                        ? std::span<const std::uint8_t>(dg.data)
                                                        : std::span<const std::uint8_t>(incoming);
                if (ado + src.size() <= mem_.size() && write_allowed_by_sm(ado, src.size())) {
                    write_memory(ado, src, at);
                    write_done = true;
                }
            }
        }
    }
    dg.set_wkc(
        static_cast<std::uint16_t>(dg.wkc() + wkc_increment(dg.command, read_done, write_done)));
}

void EscSlave::on_sii_control() {
    const std::uint16_t ctl = reg16(reg::kSiiControl);
    if ((ctl & sii_ctl::kRead) != 0) {
        const std::uint32_t word = get_le<std::uint32_t>(mem_.data() + reg::kSiiAddress);
        for (std::size_t i = 0; i < 8; ++i) {
            const std::size_t b = static_cast<std::size_t>(word) * 2 + i;
            mem_[reg::kSiiData + i] = b < eeprom_.size() ? eeprom_[b] : 0xFF;
        }
        put_le<std::uint16_t>(mem_.data() + reg::kSiiControl, sii_ctl::kReadSize8);
    } else if ((ctl & (sii_ctl::kWrite | sii_ctl::kReload)) != 0) {
        // The simulated EEPROM is read-only.
        put_le<std::uint16_t>(mem_.data() + reg::kSiiControl,
                              sii_ctl::kReadSize8 | sii_ctl::kCommandError);
    }
}

std::size_t EscSlave::sm_end(const ethercat::SyncManager& s) const {
    // An SM's start and length are 16 bits each: a master may configure one that runs past the
    // 64 KiB the ESC addresses (fuzz_slave_replies did, from a corrupted SII). Only the part in
    // the ESC's memory holds process data.
    return std::min<std::size_t>(static_cast<std::size_t>(s.start) + s.length, mem_.size());
}

std::span<std::uint8_t> EscSlave::sm_area(const SyncManager& s) {
    const std::size_t end = sm_end(s);
    const std::size_t start = std::min<std::size_t>(s.start, end);
    return std::span<std::uint8_t>(mem_).subspan(start, end - start);
}

void EscSlave::pack_inputs() {
    const SyncManager s3 = sm(3);
    if (!s3.enabled() || s3.length == 0) {
        return;
    }
    ObjectDictionary& od = app_->od();
    for_each_mapped_in(0x1C13, sm_area(s3),
                       [&](std::uint32_t entry, std::span<std::uint8_t> bytes) {
                           auto v = od.read(static_cast<std::uint16_t>(entry >> 16),
                                            static_cast<std::uint8_t>(entry >> 8));
                           for (std::size_t k = 0; k < bytes.size(); ++k) {
                               bytes[k] = v && k < v->size() ? (*v)[k] : 0;
                           }
                       });
}

void EscSlave::unpack_outputs(TimePoint now) {
    const SyncManager s2 = sm(2);
    ObjectDictionary& od = app_->od();
    for_each_mapped_in(0x1C12, sm_area(s2),
                       [&](std::uint32_t entry, std::span<std::uint8_t> bytes) {
                           (void)od.write(static_cast<std::uint16_t>(entry >> 16),
                                          static_cast<std::uint8_t>(entry >> 8), bytes, true);
                       });
    app_->on_outputs(now);
}

Duration EscSlave::watchdog_time() const {
    return nanoseconds(static_cast<std::int64_t>(reg16(reg::kWatchdogDivider) + 2) * 40 *
                       reg16(reg::kWatchdogProcessData));
}

bool EscSlave::tick(TimePoint now) {
    if (state_ != AlState::Op || faults_.silent) {
        watchdog_armed_ = false;
        return false;
    }
    const SyncManager s2 = sm(2);
    const Duration limit = watchdog_time();
    if (!s2.enabled() || (s2.control & SyncManager::kWatchdog) == 0 || limit == Duration::zero()) {
        return false;
    }
    if (!watchdog_armed_) {
        watchdog_armed_ = true;
        last_outputs_ = now;
        return false;
    }
    if (now - last_outputs_ <= limit) {
        return false;
    }
    mem_[kWatchdogStatus] = 0x00;
    ++mem_[kWatchdogCounter];
    ++watchdog_expiries_;
    watchdog_armed_ = false;
    state_ = AlState::SafeOp;
    set_al_status(state_, true, al_code::kSmWatchdog);
    app_->on_state_change(AlState::Op, AlState::SafeOp);
    return true;
}

bool EscSlave::sm_synchronous() const {
    // ETG.1020 §21.1.3.1: 1C32h:01 = 1, synchronous with the SM2 event: in SAFE-OP and OP the
    // application cycle starts when the master's outputs arrive in SM2 (the AKD2G's PLL on
    // the SM2 event without DC, manual §3.7); below SAFE-OP there is no process data to wait
    // for and the application runs free.
    if (state_ != AlState::SafeOp && state_ != AlState::Op) {
        return false;
    }
    return app_->od().get<std::uint16_t>(0x1C32, 1).value_or(0) == 1;
}

void EscSlave::run_application(TimePoint now) {
    ++application_cycles_;
    app_->step(now);
}

void EscSlave::idle(TimePoint now) {
    if (!faults_.silent && !sm_synchronous()) {
        run_application(now);
    }
}

void EscSlave::before_frame(TimePoint now) {
    ++frames_seen_;
    if (faults_.silent) {
        return;
    }
    (void)tick(now);
    if (!sm_synchronous()) {
        run_application(now);
    }
    if (app_->take_restart() && state_ != AlState::Init) {
        // The device restarted: its ESC comes back in INIT, mailbox empty.
        const AlState from = state_;
        state_ = AlState::Init;
        set_al_status(state_, false, 0);
        clear_mailboxes();
        app_->on_state_change(from, state_);
    }
    if (state_ == AlState::SafeOp || state_ == AlState::Op) {
        pack_inputs();
    }
}

void EscSlave::after_frame(TimePoint now) {
    if (faults_.silent) {
        return;
    }
    if (mailbox_in_full_) {
        const SyncManager s0 = sm(0);
        auto msg = MailboxMessage::decode(sm_area(s0));
        mailbox_in_full_ = false;
        set_sm_status(0, 0);
        // A write the master repeated because its frame was lost carries the same counter:
        // it was handled already (ETG.1000.6 §5.6.1, counter 0 = no duplicate detection).
        const bool duplicate =
            msg && msg->header.counter != 0 && msg->header.counter == last_request_counter_;
        if (msg) {
            last_request_counter_ = msg->header.counter;
        }
        if (duplicate) {
            ++duplicate_requests_;
        } else if (!faults_.mailbox_silent && state_ != AlState::Init) {
            if (!msg) {
                std::vector<std::uint8_t> err{0x01, 0x00, 0x05, 0x00}; // invalid header
                send_mailbox(std::move(err), MailboxType::Error);
            } else if (msg->header.type == MailboxType::Coe) {
                for (auto& reply : coe_->handle(msg->payload, state_)) {
                    send_mailbox(std::move(reply), MailboxType::Coe);
                }
            } else if (msg->header.type == MailboxType::Foe && foe_) {
                if (auto reply = foe_->handle(msg->payload, state_)) {
                    send_mailbox(std::move(*reply), MailboxType::Foe);
                }
            } else {
                std::vector<std::uint8_t> err{0x01, 0x00, 0x02, 0x00}; // unsupported protocol
                send_mailbox(std::move(err), MailboxType::Error);
            }
        }
    }
    serve_mailbox_repeat();
    if (state_ != AlState::Init) {
        for (const auto& e : app_->take_emergencies()) {
            send_mailbox(CoeServer::emergency(e), MailboxType::Coe);
        }
    }
    if (outputs_fresh_) {
        outputs_fresh_ = false;
        if (state_ == AlState::Op) {
            last_outputs_ = now;
            mem_[kWatchdogStatus] = 0x01;
            unpack_outputs(now);
            if (sm_synchronous()) {
                run_application(now); // the SM2 event starts the application cycle
            }
        }
    }
}

} // namespace codrive::sim::ecat
