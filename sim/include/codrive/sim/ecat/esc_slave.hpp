// SPDX-License-Identifier: Apache-2.0
// A simulated EtherCAT slave controller (ESC): register memory, station address, AL control and
// status (ESM), SII EEPROM, sync managers with mailbox semantics, FMMUs, working counter, DC.
#pragma once

#include <codrive/sim/ecat/application.hpp>
#include <codrive/sim/ecat/coe_server.hpp>
#include <codrive/sim/ecat/dc_clock.hpp>
#include <codrive/sim/ecat/foe_server.hpp>

#include <codrive/ethercat/al_state.hpp>
#include <codrive/ethercat/datagram.hpp>
#include <codrive/ethercat/mailbox.hpp>
#include <codrive/ethercat/registers.hpp>
#include <codrive/ethercat/sii.hpp>

#include <cstdint>
#include <deque>
#include <map>
#include <memory>
#include <span>
#include <string>
#include <vector>

namespace codrive::sim::ecat {

/// Fault injection for tests.
struct EscFaults {
    bool silent = false;         ///< processes nothing (frames pass through untouched)
    bool mailbox_silent = false; ///< consumes mailbox requests but never answers
    /// Refuse an up-transition into a state with this AL status code.
    std::map<ethercat::AlState, std::uint16_t> refuse;
    /// Requests for OP still to refuse with `refuse_op_code` (after leave_op()).
    unsigned refuse_op_requests = 0;
    std::uint16_t refuse_op_code = 0;
};

/// Where the frame is in the chain (for auto-increment addressing and DC receive times).
struct ChainContext {
    std::size_t position = 0;
    std::size_t chain_length = 1;
    TimePoint now{};
};

class EscSlave {
public:
    /// `sii` describes identity, mailbox and sync manager defaults; it is also the EEPROM image.
    EscSlave(ethercat::SiiInfo sii, std::unique_ptr<EcatApplication> app, bool has_dc = true);

    /// Processes one datagram as the frame passes this slave (adds to the WKC in place).
    void process(const ethercat::DatagramRef& dg, const ChainContext& ctx);
    /// Before a frame: advances the application (unless SM-synchronous) and refreshes the input
    /// buffer (SM3).
    void before_frame(TimePoint now);
    /// After a frame: consumes a written mailbox (CoE), applies fresh outputs (SM2); in sync
    /// mode 1 (1C32h:01 = 1, SM-synchronous) the SM2 write is what runs the application.
    void after_frame(TimePoint now);
    /// No frame for a while: the application runs on its own timer, as a real drive's does,
    /// unless it is SM-synchronous in SAFE-OP/OP (then it waits for the next SM2 event).
    void idle(TimePoint now);
    /// True in SAFE-OP/OP with 1C32h:01 = 1 (ETG.1020 §21.1.3.1, synchronous with SM2).
    [[nodiscard]] bool sm_synchronous() const;
    /// Application cycles run so far (free-running steps and SM2 events alike).
    [[nodiscard]] std::uint64_t application_cycles() const { return application_cycles_; }
    /// Runs the process data (SM) watchdog; call it regularly even when no frames arrive (a
    /// master that died sends none). In OP, when the output sync manager has its watchdog
    /// enabled and no outputs were written for the time in 0x0400/0x0420 (default 100 ms), the
    /// slave drops to SAFE-OP with the error flag and AL status code 0x001B, and the
    /// application applies its bus-loss reaction (ETG.1000.6 §6.4; FIO: 6007h). True if it
    /// expired now.
    bool tick(TimePoint now);
    /// A local error in OP (ETG.1000.6 §6.4.1.3): the slave drops to SAFE-OP with the error
    /// flag and `code` and the application applies its bus-loss reaction. False if not in OP.
    bool leave_op(std::uint16_t code);
    /// The process data watchdog time set in 0x0400 (divider, 40 ns ticks) and 0x0420.
    [[nodiscard]] Duration watchdog_time() const;
    /// Times the SM watchdog expired.
    [[nodiscard]] std::uint64_t watchdog_expiries() const { return watchdog_expiries_; }

    [[nodiscard]] ethercat::AlState state() const { return state_; }
    [[nodiscard]] std::uint16_t al_status_code() const;
    [[nodiscard]] std::uint16_t station_address() const;
    [[nodiscard]] const ethercat::SiiInfo& sii() const { return sii_; }
    [[nodiscard]] EcatApplication& app() { return *app_; }
    /// The FoE file server, or nullptr when the SII does not list FoE.
    [[nodiscard]] FoeServer* foe() { return foe_.get(); }
    [[nodiscard]] EscFaults& faults() { return faults_; }
    [[nodiscard]] std::uint64_t system_time(TimePoint now) const;
    [[nodiscard]] bool sync0_active() const;
    /// The slave's DC clock: its drift (set_drift_ppm) and drift control loop state.
    [[nodiscard]] DcClock& dc_clock() { return dc_clock_; }
    [[nodiscard]] const DcClock& dc_clock() const { return dc_clock_; }
    /// 0x092C as the slave reports it: local minus received reference time (ns, mean).
    [[nodiscard]] std::int32_t system_time_difference() const;
    [[nodiscard]] std::uint64_t frames_seen() const { return frames_seen_; }
    /// Mailbox repeats served (ETG.1000.4 §6.7.2).
    [[nodiscard]] std::uint64_t mailbox_repeats() const { return mailbox_repeats_; }
    /// Mailbox writes dropped as duplicates (same counter as the previous one).
    [[nodiscard]] std::uint64_t duplicate_requests() const { return duplicate_requests_; }
    /// Direct register access (tests).
    [[nodiscard]] std::uint8_t reg8(std::uint16_t addr) const { return mem_[addr]; }
    [[nodiscard]] std::uint16_t reg16(std::uint16_t addr) const;

private:
    /// Simulated per-slave forwarding delay (ns): the frame reaches slave n n hops after the
    /// first (DC receive time latches and register access times).
    static constexpr std::int64_t kDcHopNs = 500;
    void write_memory(std::uint16_t addr, std::span<const std::uint8_t> data, TimePoint now);
    bool read_memory(std::uint16_t addr, std::span<std::uint8_t> out, bool or_into, TimePoint now);
    bool write_allowed_by_sm(std::uint16_t addr, std::size_t len);
    bool read_allowed_by_sm(std::uint16_t addr, std::size_t len);
    void after_sm_write(std::uint16_t addr, std::size_t len);
    void after_sm_read(std::uint16_t addr, std::size_t len);
    bool logical(const ethercat::DatagramRef& dg, bool& read_done, bool& write_done, TimePoint now);
    void on_al_control(std::uint16_t value);
    /// INIT empties both mailboxes (ETG.1000.6 §5.6).
    void clear_mailboxes();
    /// `code` goes through the application's al_status_code() unless `injected` (EscFaults).
    void set_al_status(ethercat::AlState s, bool error, std::uint16_t code, bool injected = false);
    [[nodiscard]] std::uint16_t check_transition(ethercat::AlState to);
    void on_sii_control();
    void latch_receive_times(const ChainContext& ctx);
    /// DL status (0x0110) from where the slave sits in the chain.
    void update_dl_status(const ChainContext& ctx);
    void refresh_dc(TimePoint now);
    void send_mailbox(std::vector<std::uint8_t> payload, ethercat::MailboxType type);
    void load_mailbox_out();
    void serve_mailbox_repeat();
    [[nodiscard]] ethercat::SyncManager sm(unsigned n) const;
    void set_sm_status(unsigned n, std::uint8_t status);
    /// Walks the PDO assignment `assign_index` (1C12h outputs, 1C13h inputs; ETG.1000.6
    /// §5.6.7.4): every entry of every assigned PDO's mapping, in order, with the bit offset it
    /// starts at. `fn(entry, bit)` gets the mapping entry (index << 16 | sub << 8 | bit length).
    /// Returns the total length in bits. Counts are UNSIGNED8, so the walk is bounded by 255 PDOs
    /// of 255 entries whatever the dictionary holds.
    template <typename Fn>
    std::size_t for_each_mapped(std::uint16_t assign_index, Fn&& fn);
    /// for_each_mapped() over an SM's area (sm_area()): `fn(entry, bytes)` for every entry of an
    /// object (index not 0) that lies whole inside `area`, with its bytes there.
    template <typename Fn>
    void for_each_mapped_in(std::uint16_t assign_index, std::span<std::uint8_t> area, Fn&& fn);
    [[nodiscard]] std::size_t pdo_bytes(std::uint16_t assign_index);
    void pack_inputs();
    /// Where SM `s`'s area ends in the ESC's memory (a 16-bit start and length may run past it).
    [[nodiscard]] std::size_t sm_end(const ethercat::SyncManager& s) const;
    /// The part of SM `s`'s area inside the ESC's memory.
    [[nodiscard]] std::span<std::uint8_t> sm_area(const ethercat::SyncManager& s);
    void unpack_outputs(TimePoint now);
    std::uint64_t local_time(TimePoint now) const;

    ethercat::SiiInfo sii_;
    std::vector<std::uint8_t> eeprom_;
    std::unique_ptr<EcatApplication> app_;
    std::unique_ptr<CoeServer> coe_;
    std::unique_ptr<FoeServer> foe_;
    std::vector<std::uint8_t> mem_ = std::vector<std::uint8_t>(0x10000, 0);
    ethercat::AlState state_ = ethercat::AlState::Init;
    EscFaults faults_;
    bool mailbox_in_full_ = false;  ///< SM0 written by the master, not consumed yet
    bool mailbox_out_full_ = false; ///< SM1 holds a message the master has not read
    std::deque<std::vector<std::uint8_t>> outbox_;
    std::uint8_t mailbox_counter_ = 0;
    std::vector<std::uint8_t> sm1_message_; ///< the message now in SM1 (if full)
    std::vector<std::uint8_t> last_read_;   ///< the last message the master read (to repeat)
    std::uint8_t last_request_counter_ = 0; ///< counter of the last mailbox write
    std::uint64_t mailbox_repeats_ = 0;
    std::uint64_t duplicate_requests_ = 0;
    bool outputs_fresh_ = false;
    bool watchdog_armed_ = false;
    TimePoint last_outputs_{}; ///< last SM2 write, or when OP was entered
    std::uint64_t watchdog_expiries_ = 0;
    std::uint64_t frames_seen_ = 0;
    DcClock dc_clock_;
    std::uint64_t application_cycles_ = 0;
    void run_application(TimePoint now);
    void on_system_time_write(std::span<const std::uint8_t> data, TimePoint now);
    TimePoint epoch_{};
};

template <typename Fn>
std::size_t EscSlave::for_each_mapped(std::uint16_t assign_index, Fn&& fn) {
    ObjectDictionary& od = app_->od();
    std::size_t bit = 0;
    const unsigned count = od.get<std::uint8_t>(assign_index, 0).value_or(0);
    for (unsigned i = 1; i <= count; ++i) {
        const auto pdo =
            od.get<std::uint16_t>(assign_index, static_cast<std::uint8_t>(i)).value_or(0);
        const unsigned n = od.get<std::uint8_t>(pdo, 0).value_or(0);
        for (unsigned e = 1; e <= n; ++e) {
            const auto entry = od.get<std::uint32_t>(pdo, static_cast<std::uint8_t>(e)).value_or(0);
            fn(entry, bit);
            bit += entry & 0xFFU;
        }
    }
    return bit;
}

template <typename Fn>
void EscSlave::for_each_mapped_in(std::uint16_t assign_index, std::span<std::uint8_t> area,
                                  Fn&& fn) {
    for_each_mapped(assign_index, [&](std::uint32_t entry, std::size_t bit) {
        const std::size_t at = bit / 8;
        const std::size_t bytes = (entry & 0xFFU) / 8;
        if ((entry >> 16) != 0 && at + bytes <= area.size()) {
            fn(entry, area.subspan(at, bytes));
        }
    });
}

} // namespace codrive::sim::ecat
