// SPDX-License-Identifier: Apache-2.0
// The EtherCAT master: frame exchange, bring-up (addresses, SII), ESM, mailbox/CoE, process data
// and distributed clocks over an IEcatLink.
#pragma once

#include <codrive/ethercat/al_state.hpp>
#include <codrive/ethercat/datagram.hpp>
#include <codrive/ethercat/foe.hpp>
#include <codrive/ethercat/link.hpp>
#include <codrive/ethercat/mailbox.hpp>
#include <codrive/ethercat/sii.hpp>

#include <codrive/core/endian.hpp>
#include <codrive/core/error.hpp>
#include <codrive/core/sdo_abort.hpp>
#include <codrive/core/time.hpp>
#include <codrive/emcy/message.hpp>

#include <array>
#include <bitset>
#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

namespace codrive::ethercat {

namespace detail {
struct MailboxChannel;
class CoeTransfer;
enum class TransferStep : int;
} // namespace detail

/// Timeouts and retries. Mailbox traffic (CoE, FoE) runs as per-slave state machines that put one
/// datagram per slave into each frame: the cyclic LRW frame while process data runs, or a
/// mailbox-only frame for the blocking calls (bring-up, CLI). The cyclic path never waits on
/// the mailbox.
struct MasterConfig {
    Duration frame_timeout = milliseconds(20); ///< per attempt
    int frame_retries = 3;                     ///< attempts per acyclic frame
    Duration state_timeout = seconds(2);       ///< ESM transition
    Duration mailbox_timeout = seconds(1);     ///< CoE/FoE answer, per request/reply step
    Duration mailbox_poll = microseconds(200); ///< pause between mailbox-only frames (blocking)
    /// How often an idle CoE slave's send mailbox (SM1) is read for emergencies.
    Duration emergency_poll = milliseconds(10);
    Duration sii_timeout = milliseconds(100);
    std::uint16_t first_station_address = 0x1001;
    /// scan() refuses a segment whose broadcast read counts more slaves than this: a count that
    /// large comes from a corrupted frame or a wrong interface, and probing every position up
    /// to 65535 would take thousands of frames before saying so.
    std::uint16_t max_slaves = 512;
    /// After configure_dc(): every cyclic frame carries an FRMW of the reference clock's system
    /// time (0x0910) so that the other DC slaves keep steering their clocks to it (continuous
    /// drift compensation, ETG.1000.4 §9.1.3). Off only to show what drift does without it.
    bool continuous_drift_compensation = true;
    /// Number of the first slave in messages ("slave 0 (FIO)" by default); the CLI uses 1, as
    /// its -n counts positions from 1.
    unsigned slave_label_base = 0;
};

/// One entry of a PDO mapping (1600h/1A00h sub-index value: index, sub-index, bit length).
struct PdoEntry {
    std::uint16_t index = 0;
    std::uint8_t subindex = 0;
    std::uint8_t bits = 0;
    [[nodiscard]] std::uint32_t encode() const {
        return (static_cast<std::uint32_t>(index) << 16) |
               (static_cast<std::uint32_t>(subindex) << 8) | bits;
    }
    static PdoEntry decode(std::uint32_t v) {
        return {static_cast<std::uint16_t>(v >> 16), static_cast<std::uint8_t>(v >> 8),
                static_cast<std::uint8_t>(v)};
    }
};

/// One PDO (a mapping object) with its entries.
struct PdoMapping {
    std::uint16_t index = 0; ///< 1600h.. (RxPDO) or 1A00h.. (TxPDO)
    std::vector<PdoEntry> entries;
    [[nodiscard]] std::size_t bits() const;
};

/// Where one mapped object lives in a slave's process data (byte offset from the slave's start).
struct PdoField {
    PdoEntry entry;
    std::size_t byte_offset = 0;
};

/// What the master knows about one slave.
struct SlaveInfo {
    std::uint16_t position = 0;        ///< 0-based position on the segment
    std::uint16_t station_address = 0; ///< configured address (0x0010)
    SiiInfo sii;
    AlState state = AlState::Init;
    /// The AL state, error flag and status code the slave was in when scan() found it, before
    /// scan() reset it to INIT: what the previous master (or a crash) left behind, e.g.
    /// SAFE-OP + error 0x001B when its SM watchdog expired because process data stopped.
    AlState found_state = AlState::None;
    bool found_error = false;
    std::uint16_t found_code = 0;
    bool has_dc = false;
    // Process data (after map_process_data()).
    std::vector<PdoMapping> rx_pdos; ///< outputs, SM2
    std::vector<PdoMapping> tx_pdos; ///< inputs, SM3
    std::vector<PdoField> outputs_layout;
    std::vector<PdoField> inputs_layout;
    std::uint16_t output_bytes = 0;
    std::uint16_t input_bytes = 0;
    std::size_t output_offset = 0; ///< in the process image
    std::size_t input_offset = 0;
    std::uint8_t mailbox_counter = 0;
    std::uint8_t mailbox_rx_counter = 0; ///< counter of the last message read from SM1

    /// "AKD2G", or "0x0000006A:0x12345678" when the EEPROM has no name.
    [[nodiscard]] std::string display_name() const;
};

/// SDO information: an object description (ETG.1000.6 §5.6.3.5).
struct ObjectDescription {
    std::uint16_t index = 0;
    std::uint16_t data_type = 0;
    std::uint8_t max_subindex = 0;
    std::uint8_t object_code = 0;
    std::string name;
};

/// SDO information: an entry description (ETG.1000.6 §5.6.3.6).
struct EntryDescription {
    std::uint16_t index = 0;
    std::uint8_t subindex = 0;
    std::uint16_t data_type = 0;
    std::uint16_t bit_length = 0;
    std::uint16_t access = 0;
    std::string name;
};

/// Outcome of an asynchronous mailbox transfer (CoE, FoE).
struct CoeOutcome {
    /// Empty on success: SdoAbort codes, FoE error codes (foe_category()), MailboxTimeout,
    /// ProtocolError.
    std::error_code error;
    std::string sentence; ///< on failure: "slave 2 (AKD2G): CoE SDO upload 0x6064:00 timed out ..."
    std::vector<std::uint8_t> data; ///< uploads and SDO information answers
};
using CoeDone = std::function<void(CoeOutcome)>;

/// Counters of the cyclic exchange.
struct ProcessDataStats {
    std::uint64_t cycles = 0;
    std::uint64_t lost_frames = 0;
    std::uint64_t consecutive_lost = 0;     ///< lost frames since the last one that came back
    std::uint64_t max_consecutive_lost = 0; ///< the longest run of lost frames
    std::uint64_t mailbox_datagrams = 0;    ///< mailbox datagrams carried in cyclic frames
    /// SM1 messages nobody waited for (dropped): late answers of transfers that timed out too
    std::uint64_t stray_mailbox_messages = 0;
    std::uint64_t wkc_errors = 0;
    /// Frames that brought the inputs in (the expected working counter): the input image holds
    /// the newest one's. Not `cycles − wkc_errors`: the frames before OP (whose short working
    /// counter is expected, see set_state_all()) count as cycles but bring no inputs in.
    std::uint64_t input_frames = 0;
    /// Of the lost_frames, those read after all by a later wait and dropped: the host or the
    /// wire was slow, the frame was not lost. `lost_frames − late_frames` never came back, but
    /// for the frames lost since the last one read (consecutive_lost), which may still be on
    /// their way. A frame back more than 255 frames late finds its index reused: not counted.
    std::uint64_t late_frames = 0;
    /// Late frames that were not counted in lost_frames: lost attempts of blocking calls
    /// (scan(), register access, SDO outside cyclic operation) and a cyclic frame whose wait
    /// failed with a receive error. Read after their deadline, dropped.
    std::uint64_t late_other_frames = 0;
    /// Frames read while waiting that were not a late frame of ours and would not decode as
    /// the awaited one: no EtherCAT header, a corrupted datagram, an index never sent or
    /// already read. Dropped; the wait goes on.
    std::uint64_t unreadable_frames = 0;
    /// Cyclic waits that ended with a receive error of the link (the interface went down, say)
    /// rather than a timeout: not in lost_frames, but the frame's mailbox datagrams, AL probes
    /// and AL control writes count as lost and go again.
    std::uint64_t receive_errors = 0;
    /// Frames that could not be sent: the link's error (the interface is down, its transmit
    /// queue is full). Cyclic, mailbox-only and blocking calls' frames alike; not lost (they
    /// never left), so not in lost_frames.
    std::uint64_t send_errors = 0;
    /// Cyclic frames that carried the reference clock's system time (FRMW 0x0910).
    std::uint64_t dc_time_distributions = 0;
};

/// DC state of one slave after configure_dc().
struct DcSlaveStatus {
    std::uint16_t position = 0;
    std::uint64_t system_time = 0;        ///< ns since 2000-01-01 as read (0x0910)
    std::int64_t offset_to_reference = 0; ///< system time minus the reference clock's, same frame
    std::uint32_t delay = 0;              ///< propagation delay written to 0x0928
    /// 0x092C system time difference, decoded (ns): the slave's mean of its own system time
    /// minus the distributed reference time; what its drift control steers to zero. 0 for the
    /// reference clock itself and before any time was distributed.
    std::int32_t difference = 0;
};

class Master {
public:
    Master(IEcatLink& link, IClock& clock, MasterConfig config = {});
    ~Master();
    Master(const Master&) = delete;
    Master& operator=(const Master&) = delete;

    // ---- Frame exchange --------------------------------------------------------------------
    /// Sends the datagrams in one frame and waits for it to come back (retrying lost frames).
    /// Fills data and WKC; does not check working counters. Errors: NoResponse, FrameTooLarge,
    /// link errors.
    VoidResult exchange(std::span<Datagram> datagrams);
    /// Configured-address read/write of one slave's registers; WKC must be 1. Errors: as
    /// exchange(), WorkingCounter.
    Result<std::vector<std::uint8_t>> read_registers(std::size_t slave, std::uint16_t reg,
                                                     std::size_t size);
    VoidResult write_registers(std::size_t slave, std::uint16_t reg,
                               std::span<const std::uint8_t> data);
    template <typename T>
    Result<T> read_register(std::size_t slave, std::uint16_t reg) {
        auto d = read_registers(slave, reg, sizeof(T));
        if (!d) {
            return fail(d.error());
        }
        return get_le<T>(d->data());
    }
    template <typename T>
    VoidResult write_register(std::size_t slave, std::uint16_t reg, T value) {
        std::array<std::uint8_t, sizeof(T)> b{};
        put_le<T>(b.data(), value);
        return write_registers(slave, reg, b);
    }

    // ---- Bring-up --------------------------------------------------------------------------
    /// Counts the slaves with a broadcast read (its WKC). Errors: NoResponse.
    Result<std::uint16_t> count_slaves();
    /// Resets the segment to INIT (AL control, FMMUs, SMs, DC activation cleared), assigns
    /// station addresses 0x1001.. by position and reads every SII. Errors: NoSlaves, NoResponse,
    /// SiiTimeout/SiiError, WorkingCounter.
    VoidResult scan();
    [[nodiscard]] const std::vector<SlaveInfo>& slaves() const { return slaves_; }
    [[nodiscard]] std::vector<SlaveInfo>& slaves() { return slaves_; }
    /// Reads `words` 16-bit words of the SII EEPROM from `word_address`. Errors: SiiTimeout,
    /// SiiError, WorkingCounter.
    Result<std::vector<std::uint8_t>> read_sii(std::size_t slave, std::uint16_t word_address,
                                               std::size_t words);
    /// Reads header and categories and parses them. Errors: as read_sii().
    Result<SiiInfo> read_sii_info(std::size_t slave);

    // ---- EtherCAT state machine ------------------------------------------------------------
    /// AL status (state + error flag) and AL status code of one slave.
    struct AlStatus {
        AlState state = AlState::None;
        bool error = false;
        std::uint16_t code = 0;
        /// From the 6 bytes read at 0x0130: AL status, reserved, AL status code.
        [[nodiscard]] static AlStatus decode(std::span<const std::uint8_t> six) {
            AlStatus st;
            const auto raw = get_le<std::uint16_t>(six.data());
            st.state = al_state_from_bits(raw).value_or(AlState::None);
            st.error = (raw & kAlErrorFlag) != 0;
            st.code = get_le<std::uint16_t>(six.data() + 4);
            return st;
        }
    };
    Result<AlStatus> read_al_status(std::size_t slave);
    /// One direct transition (ETG.1000.6 §6.4.1). Configures the mailbox sync managers before
    /// INIT→PRE-OP. On refusal the AL error is acknowledged and the error is StateChangeRefused
    /// with last_error() naming the slave, the transition and the AL status code text.
    /// Errors: StateChangeRefused, StateChangeTimeout, WorkingCounter, NoResponse.
    VoidResult request_state(std::size_t slave, AlState target);
    /// Steps every slave up (or down) to `target`: mailboxes before PRE-OP, process data mapped
    /// before SAFE-OP, one valid process data exchange before OP. Each slave's state is read
    /// first (its AL status), so a slave that left OP by itself — SAFE-OP with the watchdog
    /// error 0x001B, or INIT after a power cycle — is brought back: its error acknowledged, its
    /// mailbox and its part of the process image (SM2/SM3, FMMUs) configured again, provided
    /// its PDO layout (1C12h/1C13h) is the one mapped. Errors: as request_state(),
    /// map_process_data(); NotConfigured when a slave came back with another PDO layout.
    VoidResult set_state_all(AlState target);

    // ---- Mailbox and CoE -------------------------------------------------------------------
    /// Writes one mailbox message to SM0, retrying while the mailbox is full. Errors:
    /// MailboxNotSupported, MailboxTimeout.
    VoidResult mailbox_write(std::size_t slave, MailboxMessage message);
    /// Reads the next message from SM1, waiting up to `timeout`. Errors: MailboxTimeout,
    /// MailboxError.
    Result<MailboxMessage> mailbox_read(std::size_t slave, Duration timeout);
    /// SDO upload (expedited, normal or segmented as the slave chooses). `complete_access` reads
    /// the whole object (sub-index 0 or 1 onwards). Errors: SdoAbort codes from the slave,
    /// MailboxTimeout, ProtocolError.
    Result<std::vector<std::uint8_t>> sdo_upload(std::size_t slave, std::uint16_t index,
                                                 std::uint8_t subindex,
                                                 bool complete_access = false);
    /// SDO download: expedited for 1..4 bytes, normal when it fits the mailbox, segmented
    /// otherwise. Errors: as sdo_upload().
    VoidResult sdo_download(std::size_t slave, std::uint16_t index, std::uint8_t subindex,
                            std::span<const std::uint8_t> data, bool complete_access = false);
    template <typename T>
    Result<T> sdo_read(std::size_t slave, std::uint16_t index, std::uint8_t subindex) {
        auto d = sdo_upload(slave, index, subindex);
        if (!d) {
            return fail(d.error());
        }
        if (d->size() < sizeof(T)) {
            return fail(SdoAbort::LengthTooLow);
        }
        return get_le<T>(d->data());
    }
    template <typename T>
    VoidResult sdo_write(std::size_t slave, std::uint16_t index, std::uint8_t subindex, T value) {
        std::array<std::uint8_t, sizeof(T)> b{};
        put_le<T>(b.data(), value);
        return sdo_download(slave, index, subindex, b);
    }
    /// Asynchronous SDO upload/download: queued on the slave's mailbox channel and advanced one
    /// step per frame (the cyclic frame, or run_mailbox_cycle()); `done` runs from the call
    /// that processes the returned frame (receive_process_data(), run_mailbox_cycle()), never
    /// inside this call. A mute mailbox fails only this transfer, after mailbox_timeout, with
    /// its sentence. Errors (returned at once, `done` not called): NoSuchSlave,
    /// MailboxNotSupported.
    VoidResult sdo_upload_async(std::size_t slave, std::uint16_t index, std::uint8_t subindex,
                                CoeDone done, bool complete_access = false);
    VoidResult sdo_download_async(std::size_t slave, std::uint16_t index, std::uint8_t subindex,
                                  std::vector<std::uint8_t> data, CoeDone done,
                                  bool complete_access = false);
    /// Transfers queued or running on one slave's mailbox channel.
    [[nodiscard]] std::size_t mailbox_transfers(std::size_t slave) const;
    /// Ends every transfer queued or running on the slave's mailbox channel now, without another
    /// frame: each `done` runs once, inside this call, with EcatErrc::Cancelled and a sentence
    /// naming the slave, the transfer and `why` ("slave 1 (AKD2G): CoE SDO upload 0x6502:00
    /// cancelled: the controller shut down before the slave answered"). For a master that stops
    /// exchanging frames (shutdown) and must not leave callbacks waiting for ever: a slave that
    /// had taken a request may still put its answer in its mailbox. Transfers a callback queues
    /// meanwhile are cancelled too, up to 64 (a callback that resubmits on every failure cannot
    /// keep the call going; the rest runs in the next mailbox cycle).
    void cancel_mailbox_transfers(std::size_t slave, std::string_view why);
    /// One mailbox-only frame (blocking up to frame_timeout): for use when no cyclic exchange
    /// runs (bring-up, tools). Errors: link errors.
    VoidResult run_mailbox_cycle();
    /// Runs mailbox-only frames until the slave's channel has nothing queued (each transfer
    /// ends by its own timeout at the latest).
    void run_mailbox_until_idle(std::size_t slave);
    /// SDO information service. Errors: SdoAbort (from an SDO info error), MailboxTimeout,
    /// ProtocolError, MailboxNotSupported when the slave does not offer SDO information.
    Result<std::vector<std::uint16_t>> sdo_info_object_list(std::size_t slave);
    Result<ObjectDescription> sdo_info_object(std::size_t slave, std::uint16_t index);
    Result<EntryDescription> sdo_info_entry(std::size_t slave, std::uint16_t index,
                                            std::uint8_t subindex);
    // ---- FoE (file access over EtherCAT, ETG.1000.6 §5.7) ----------------------------------
    /// Reads the file `name` from the slave: RRQ, then DATA/ACK one message per frame until a
    /// DATA shorter than the slave's mailbox allows ends it. Runs on the slave's mailbox channel
    /// like the CoE transfers (in the cyclic frame or run_mailbox_cycle()); `done` gets the
    /// file in outcome.data, or the error and its sentence ("slave 1 (AKD2G): FoE read
    /// 'x.akd': error 0x8001 (not found) ..."). Errors (returned at once): NoSuchSlave,
    /// MailboxNotSupported (no mailbox or no FoE in the slave's SII).
    VoidResult foe_read_async(std::size_t slave, std::string name, CoeDone done,
                              FoeOptions options = {});
    /// Writes `data` as the file `name`: WRQ, ACK 0, then DATA n / ACK n; BUSY answers make the
    /// master send the same DATA again (up to options.busy_timeout).
    VoidResult foe_write_async(std::size_t slave, std::string name, std::vector<std::uint8_t> data,
                               CoeDone done, FoeOptions options = {});
    /// Blocking forms over mailbox-only frames (no cyclic exchange running). Errors: FoE error
    /// codes (foe_category()), MailboxTimeout, ProtocolError, MailboxNotSupported, with
    /// last_error() naming slave, file and cause.
    Result<std::vector<std::uint8_t>> foe_read(std::size_t slave, const std::string& name,
                                               FoeOptions options = {});
    VoidResult foe_write(std::size_t slave, const std::string& name,
                         std::span<const std::uint8_t> data, FoeOptions options = {});

    /// Called with every CoE emergency (decoded with the emcy/ module's EmcyMessage).
    using EmergencyHandler = std::function<void(std::size_t slave, const emcy::EmcyMessage&)>;
    void on_emergency(EmergencyHandler handler) { emergency_handler_ = std::move(handler); }
    /// Reads pending mailbox messages of every CoE slave (emergencies outside SDO traffic) and
    /// returns how many it read. At most kPolledMessagesPerSlave per slave and call: a slave
    /// refills SM1 after each read, and one whose SM1 never runs dry (a wrong mailbox address in
    /// its SII reads plain memory, "full" every time) must not hold the caller. What is left
    /// waits in the slave for the next call.
    static constexpr std::size_t kPolledMessagesPerSlave = 16;
    std::size_t poll_mailboxes();
    /// Asks the slave to write its last SM1 message again (ETG.1000.4 §6.7.2: toggles the repeat
    /// request, waits for the repeat acknowledge). mailbox_read() does this by itself when the
    /// frame of a mailbox read was lost, so that the answer it emptied is not lost with it.
    /// Errors: MailboxTimeout (no acknowledge), WorkingCounter, NoResponse.
    VoidResult mailbox_repeat(std::size_t slave);
    /// How many mailbox repeats were requested (lost mailbox reads recovered).
    [[nodiscard]] std::uint64_t mailbox_repeats() const { return mailbox_repeats_; }
    /// The sentence for an emergency: "slave 1 (AKD2G): EMCY 0x2310 continuous over-current ...";
    /// with a vendor text provider (drives::emcy_text_provider) the drive's own text follows.
    [[nodiscard]] std::string
    describe_emergency(std::size_t slave, const emcy::EmcyMessage& m,
                       const emcy::IEmcyTextProvider* vendor = nullptr) const;

    // ---- Process data ----------------------------------------------------------------------
    /// Writes 1C12h/1C13h and the mapping objects over CoE (PRE-OP only): sub 0 = 0, entries,
    /// sub 0 = n, as ETG.1000.6 §5.6.7.4 prescribes. Errors: SdoAbort from the slave.
    VoidResult configure_pdos(std::size_t slave, std::span<const PdoMapping> rx,
                              std::span<const PdoMapping> tx);
    /// Reads the assigned PDOs and their mapping. Errors: SdoAbort, MailboxTimeout.
    Result<std::pair<std::vector<PdoMapping>, std::vector<PdoMapping>>>
    read_pdo_assignment(std::size_t slave);
    /// Reads every slave's PDO layout, allocates the process image (all outputs, then all
    /// inputs) and programs SM2/SM3 and FMMU0/FMMU1. Slaves must be in PRE-OP.
    VoidResult map_process_data(std::uint32_t logical_base = 0x00010000);
    [[nodiscard]] bool process_data_mapped() const { return mapped_; }
    [[nodiscard]] std::span<std::uint8_t> outputs(std::size_t slave);
    [[nodiscard]] std::span<const std::uint8_t> inputs(std::size_t slave) const;
    [[nodiscard]] std::span<std::uint8_t> process_image() { return image_; }
    /// The LRW working counter when every slave answers: 2 per slave with outputs (write) plus
    /// 1 per slave with inputs (read).
    [[nodiscard]] std::uint16_t expected_wkc() const { return expected_wkc_; }
    /// Sends the cyclic LRW frame (no waiting). Errors: NotConfigured, link errors (last_error()
    /// reads `cyclic LRW frame not sent on <link>: cannot send: <cause>`).
    VoidResult send_process_data();
    /// Waits for the cyclic frame until `deadline` (a cyclic caller gives at most its period),
    /// advances the mailbox channels whose datagrams rode in it, copies inputs, returns its
    /// WKC. A lost frame is counted (stats().lost_frames, consecutive_lost). Errors:
    /// NoResponse (lost frame); a WKC mismatch is counted and returned as WorkingCounter with
    /// last_error() naming the slaves that did not answer; a receive error of the link is
    /// returned as it is (stats().receive_errors), the frame given up as if lost.
    Result<std::uint16_t> receive_process_data(TimePoint deadline);
    /// send + receive with the frame timeout.
    Result<std::uint16_t> exchange_process_data();
    [[nodiscard]] const ProcessDataStats& stats() const { return stats_; }
    /// The working counter of the last cyclic frame if it did not match (a frame that came back
    /// short), nullopt after a good one or a lost frame.
    [[nodiscard]] std::optional<std::uint16_t> last_wkc_mismatch() const {
        return last_wkc_mismatch_;
    }
    /// AL status of one slave as read by the in-frame probes.
    struct AlProbe {
        bool answered = false;
        AlStatus status;
    };
    /// After a working-counter mismatch the next cyclic frame carries an AL status read of every
    /// slave (no extra frame, no wait). True once when those results came back: they are in
    /// al_probes(), the working counter that prompted them in probed_wkc().
    bool take_al_probes();
    [[nodiscard]] const std::vector<AlProbe>& al_probes() const { return al_probes_; }
    [[nodiscard]] std::uint16_t probed_wkc() const { return probed_wkc_; }
    /// Asks for an AL control write (0x0120: requested state, bit 4 = error acknowledge,
    /// ETG.1000.6 §6.4.1) to ride in the next cyclic frame: an FPWR next to the LRW, no extra
    /// frame, no wait, no allocation. Kept until a frame brings it to the slave (WKC 1), so a
    /// lost frame repeats it. For recovering a slave that left OP while the cycle runs; the
    /// result shows in the AL status probes of later frames. False for an unknown slave or
    /// before the process data is mapped.
    bool queue_al_control(std::size_t slave, std::uint16_t value);
    /// The diagnosis sentence (see diagnose_wkc()) from probe results; touches no link.
    [[nodiscard]] std::string describe_wkc(std::uint16_t wkc,
                                           std::span<const AlProbe> probes) const;
    /// Finds the slaves that do not answer or left OP (FPRD of AL status per slave) and returns
    /// the sentence: "cyclic LRW working counter 4, expected 7: slave 2 (DS-BVS) does not
    /// answer" or "...: slave 0 (FIO) is in SAFE-OP with AL status code 0x001B (sync manager
    /// watchdog)". Blocking (one frame): call it outside the cyclic path.
    std::string diagnose_wkc(std::uint16_t wkc);

    // ---- Distributed clocks ----------------------------------------------------------------
    /// Latches receive times, computes propagation delays and offsets to the master time, and
    /// runs the static drift compensation (ARMW of the reference clock's system time). Slaves
    /// without DC are skipped. Errors: NoResponse, WorkingCounter.
    VoidResult configure_dc();
    /// 0x0910 of one slave (ns since 2000-01-01). Errors: WorkingCounter, NoResponse.
    Result<std::uint64_t> read_system_time(std::size_t slave);
    /// The position of the reference clock (the first slave with DC) after configure_dc().
    [[nodiscard]] std::optional<std::size_t> dc_reference() const { return dc_reference_; }
    /// One blocking frame that distributes the reference clock's system time (the same FRMW
    /// the cyclic frame carries): for tools and the static drift compensation, not the cyclic
    /// path. Errors: NotConfigured (no configure_dc()), NoResponse.
    VoidResult distribute_system_time();
    /// Programs SYNC0 (cycle, shift) and activates it, starting 10 ms after the slave's time.
    VoidResult configure_sync0(std::size_t slave, Duration cycle, Duration shift = {});
    /// Reads every DC slave's system time in one frame and reports offsets to the reference.
    Result<std::vector<DcSlaveStatus>> dc_status();

    // ---- Diagnostics -----------------------------------------------------------------------
    /// The sentence describing the last failure ("slave 2 (AKD2G): ..."). A failure of the
    /// cyclic exchange is recorded there without formatting (the cyclic path allocates nothing)
    /// and put into words here, on first use.
    [[nodiscard]] const std::string& last_error() const;
    /// "slave 2 (AKD2G)".
    [[nodiscard]] std::string slave_label(std::size_t slave) const;
    [[nodiscard]] IClock& clock() { return clock_; }
    [[nodiscard]] const MasterConfig& config() const { return config_; }
    [[nodiscard]] MasterConfig& config() { return config_; }
    /// Master time on the EtherCAT scale (ns since 2000-01-01).
    [[nodiscard]] std::uint64_t master_time_ns() const;

private:
    VoidResult set_error(std::error_code ec, std::string sentence);
    /// The sentence to overwrite: any failure of the cyclic exchange noted before is superseded.
    std::string& error_text() {
        cyclic_note_ = CyclicNote::None;
        return last_error_;
    }
    VoidResult check_slave(std::size_t slave);
    VoidResult setup_mailbox_sms(std::size_t slave);
    Result<std::vector<std::uint8_t>> sdo_info_request(std::size_t slave,
                                                       std::vector<std::uint8_t> request,
                                                       std::uint8_t response_opcode);
    std::uint8_t next_counter(std::size_t slave);
    /// The index of the next frame sent. It is no longer overdue: a frame with it is awaited.
    std::uint8_t next_index() {
        overdue_.reset(index_);
        overdue_cyclic_.reset(index_);
        return index_++;
    }
    /// The frame with this index was not back by its deadline (or its wait failed).
    void mark_overdue(std::uint8_t index, bool cyclic) {
        overdue_.set(index);
        overdue_cyclic_.set(index, cyclic);
    }
    /// A frame came back that is not the awaited one (another index, or not decodable as it):
    /// count it late if its index is overdue, unreadable otherwise.
    void count_unawaited(std::optional<std::uint8_t> index);
    Result<std::optional<MailboxMessage>> mailbox_read_once(std::size_t slave, bool& lost);
    // Mailbox channels (master_mailbox.cpp).
    detail::MailboxChannel& channel(std::size_t slave);
    VoidResult submit(std::size_t slave, std::unique_ptr<detail::CoeTransfer> t);
    Result<std::vector<std::uint8_t>> run_transfer(std::size_t slave,
                                                   std::unique_ptr<detail::CoeTransfer> t);
    Datagram& add_datagram(Command c, std::uint16_t adp, std::uint16_t ado, std::size_t size);
    [[nodiscard]] std::size_t frame_room() const;
    void mailbox_add(TimePoint now);
    void mailbox_done(bool lost, TimePoint now);
    /// The frame with the channels' datagrams could not be sent: nothing in it is lost (the
    /// same step goes in the next frame); each channel counts it for its timeout sentence.
    void mailbox_unsent();
    void mailbox_message(std::size_t slave, std::span<const std::uint8_t> sm1, TimePoint now);
    void mailbox_start(std::size_t slave, TimePoint now);
    void mailbox_send(std::size_t slave, TimePoint now);
    void mailbox_finish(std::size_t slave, TimePoint now);
    void mailbox_step(std::size_t slave, detail::TransferStep step, TimePoint now);
    void mailbox_fail(std::size_t slave, std::error_code ec, std::string sentence, TimePoint now);
    /// The running transfer's step deadline passed: its own verdict, or the timeout sentence.
    void mailbox_timeout(std::size_t slave, TimePoint now);
    /// A message read from SM1 that no transfer takes: counted in the stats and the step's.
    void drop_stray(detail::MailboxChannel& ch);
    void dispatch_emergency(std::size_t slave, std::span<const std::uint8_t> coe);
    void deliver_finished();
    void probes_add();
    void probes_done(bool lost);
    void al_control_add();
    void al_control_done(bool lost);
    /// The awaited cyclic frame will not be read: everything that rode in it counts as lost.
    void give_up_cyclic_frame(bool counted_lost);
    /// The continuous drift compensation datagram of the cyclic frame (master_dc.cpp).
    void dc_time_add();
    /// Programs SM2/SM3 and FMMU0/1 of one slave for its part of the process image.
    VoidResult write_process_data_config(std::size_t slave, std::uint32_t logical_base);
    /// A mapped slave back from below SAFE-OP: its PDO layout checked, its SMs/FMMUs rewritten.
    VoidResult remap_slave(std::size_t slave);

    IEcatLink& link_;
    IClock& clock_;
    MasterConfig config_;
    std::vector<SlaveInfo> slaves_;
    std::uint8_t index_ = 0;
    /// Attempts of the last exchange() whose frame left and did not return (not those whose
    /// send found the transmit queue full).
    int last_exchange_lost_ = 0;
    std::uint64_t mailbox_repeats_ = 0;
    std::vector<std::uint8_t> tx_buffer_ = std::vector<std::uint8_t>(kMaxFrameSize);
    std::vector<std::uint8_t> rx_buffer_ = std::vector<std::uint8_t>(kMaxFrameSize + 64);
    mutable std::string last_error_;
    /// A failure of the cyclic exchange not yet put into words (see last_error()).
    enum class CyclicNote : std::uint8_t {
        None,
        FrameLost,
        ReceiveError,
        SendError,
        WorkingCounter
    };
    mutable CyclicNote cyclic_note_ = CyclicNote::None;
    std::uint16_t noted_wkc_ = 0;
    std::error_code noted_error_;
    EmergencyHandler emergency_handler_;
    // Process data.
    bool mapped_ = false;
    std::uint32_t logical_base_ = 0;
    std::vector<std::uint8_t> image_;
    std::size_t output_size_ = 0;
    std::uint16_t expected_wkc_ = 0;
    std::optional<std::uint16_t> last_wkc_mismatch_;
    std::vector<Datagram> frame_; ///< datagrams of the frame in flight (LRW first when cyclic)
    std::size_t frame_used_ = 0;
    std::optional<std::uint8_t> cyclic_index_;
    /// Indexes of frames whose deadline passed before they came back, or whose wait failed
    /// (cleared when read back late or when the index is sent again), and which of them were
    /// cyclic frames counted in lost_frames.
    std::bitset<256> overdue_;
    std::bitset<256> overdue_cyclic_;
    std::vector<std::unique_ptr<detail::MailboxChannel>> channels_;
    std::vector<std::unique_ptr<detail::CoeTransfer>> finished_;
    std::size_t mailbox_first_ = 0; ///< round robin: whose datagram goes first
    bool probe_pending_ = false;
    bool probe_fresh_ = false;
    int probe_first_ = -1; ///< position of the first probe datagram in the frame
    std::uint16_t probe_wkc_ = 0;
    std::uint16_t probed_wkc_ = 0;
    std::vector<AlProbe> al_probes_;
    std::vector<std::uint16_t> al_control_; ///< per slave: AL control value to write, 0 = none
    int al_control_first_ = -1; ///< position of the first AL control datagram in the frame
    ProcessDataStats stats_;
    std::optional<std::size_t> dc_reference_;
};

} // namespace codrive::ethercat
