// SPDX-License-Identifier: Apache-2.0
// Transport-neutral SDO server (CiA 301 §7.2.4.3): one request in, its responses out. Serves the
// CAN server (sdo::SdoServer) and the simulated EtherCAT slaves' CoE SDO (ETG.1000.6 §5.6.2).
#pragma once

#include <codrive/core/event_loop.hpp>
#include <codrive/core/object_dictionary.hpp>
#include <codrive/sdo/error.hpp>
#include <codrive/sdo/protocol.hpp>

#include <cstddef>
#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <optional>
#include <span>
#include <tl/expected.hpp>

namespace codrive::sdo {

namespace detail {
struct ServerSession;
}

struct ServerConfig {
    /// CAN only (sdo::SdoServer): the node and its COB-IDs; 0 = default channel: requests on
    /// 600h+node, responses on 580h+node.
    NodeId node = 1;
    std::uint32_t request_id = 0;
    std::uint32_t response_id = 0;
    /// Abort with 0x05040000 when the client goes silent this long mid-transfer.
    Duration timeout = std::chrono::milliseconds(1000);
    /// Block download: sub-block size we ask for (1..127).
    std::uint8_t block_size = 127;
    bool crc = true;
    /// Answer uploads of 1..4 bytes expedited (some devices always segment; tests use that).
    bool expedited_upload = true;
    /// Block download: acknowledge early when a sub-block stalls (its last segment was lost).
    Duration block_gap_timeout = std::chrono::milliseconds(100);
    /// Block download: send the initiate or sub-block response again when nothing of the
    /// sub-block it asks for arrives within `block_gap_timeout`. Off by default: CiA 301
    /// §7.2.4.3.9-10 has one response per step, and a CAN frame reaches every node or none, so
    /// the copy reaches a client that already has the original. python-canopen, slower than
    /// 100 ms to send its first segment, took the copy for its next answer and aborted with
    /// 05040001h. Only for lossy links where the response itself may vanish (fault injection).
    bool repeat_block_responses = false;
};

/// How a transport carries SDO data beyond CiA 301's 8 bytes; the server side of SdoFraming.
/// The defaults are CAN's; coe() gives CoE's (ETG.1000.6 §5.6.2).
struct SdoServerFraming {
    /// Most data bytes one upload segment response carries (CAN: 7; CoE: the slave's send
    /// mailbox after the segment's command byte, ETG.1000.6 §5.6.2.6). A download segment
    /// request carries what the client put in it: 7 bytes, or on CoE with seg data size 0 all
    /// bytes after the command byte (§5.6.2.4).
    std::size_t segment_room = kSegmentData;
    /// Data bytes a non-expedited initiate upload response carries after its size (CAN: 0;
    /// CoE "normal transfer": the send mailbox after the 8 bytes, ETG.1000.6 §5.6.2.2/§5.6.2.5).
    /// When non-zero, an initiate download request may also carry data after its size.
    std::size_t initiate_room = 0;
    /// CoE complete access (ETG.1000.6 §5.6.2.1.1): an initiate request with command bit 4
    /// transfers the whole object from sub-index 0 or 1 (complete_access.hpp).
    bool complete_access = false;
    /// Block transfers (CiA 301 §7.2.4.3.9-16); CoE has none (ETG.1000.6 §5.6.2: its command
    /// specifiers 5 and 6 are not SDO services), so they abort 0x05040001 there.
    bool block = true;
    /// A request byte-identical to the previous one is a repeat of the same CAN frame (after an
    /// ACK error) and is ignored for the kinds never sent twice on purpose. CoE's mailbox layer
    /// already drops repeated mailbox messages (ETG.1000.4 §6.7.2), so it does not.
    bool ignore_repeats = true;

    /// CoE's framing when one answer holds `sdo_room` bytes after the CoE header (the slave's
    /// send mailbox, SM1, minus the mailbox and CoE headers).
    [[nodiscard]] static SdoServerFraming coe(std::size_t sdo_room);
};

/// Streams a large DOMAIN upload without the data sitting in the dictionary.
struct DomainReader {
    std::size_t size = 0;
    /// Fills `out` completely with the next bytes, or returns the abort code to send.
    std::function<tl::expected<void, SdoAbort>(std::span<std::uint8_t> out)> read;
};
/// Receives a DOMAIN download piece by piece.
struct DomainWriter {
    std::function<tl::expected<void, SdoAbort>(std::span<const std::uint8_t> data)> write;
    /// All data arrived (the size checks passed); an abort code refuses the whole download.
    std::function<tl::expected<void, SdoAbort>()> finish;
    /// The transfer was aborted or timed out (optional).
    std::function<void()> cancel;
};
using DomainUploadHandler =
    std::function<tl::expected<DomainReader, SdoAbort>(std::uint16_t index, std::uint8_t sub)>;
using DomainDownloadHandler = std::function<tl::expected<DomainWriter, SdoAbort>(
    std::uint16_t index, std::uint8_t sub, std::optional<std::size_t> size)>;
/// Checked before every transfer: return an abort code to refuse it (e.g. 0x08000022 in the
/// present device state, or PDO mapping changes while the PDO is valid).
using AccessHook = std::function<std::optional<SdoAbort>(std::uint16_t index, std::uint8_t sub,
                                                         Direction direction)>;

struct ServerStats {
    std::uint64_t requests = 0;
    std::uint64_t completed = 0;
    std::uint64_t aborts_sent = 0;
    std::uint64_t aborts_received = 0;
    std::uint64_t timeouts = 0;
    std::uint64_t frames_ignored = 0;
    std::uint64_t early_acks = 0; ///< sub-blocks acknowledged by the gap timer
    /// Requests ignored as byte-identical repeats or late sub-block responses (docs/sdo.md).
    std::uint64_t repeats_ignored = 0;
    /// Block download initiate / sub-block responses sent again because no segment followed.
    std::uint64_t acks_repeated = 0;
};

/// The SDO server state machine of one channel, sans-I/O: command specifiers, toggle, size
/// checks, abort codes, segment and block logic. Reads and writes go through the
/// ObjectDictionary, whose access, length and range checks give the abort codes; write hooks
/// there run on completed downloads. The transport hands in each request and sends what `send`
/// receives; the framing says what differs between CAN and CoE.
class SdoServerMachine {
public:
    /// Sends one response: the 8-byte CiA 301 frame and, on CoE, the data after it.
    using Send = std::function<void(const Payload& frame, std::span<const std::uint8_t> extra)>;

    SdoServerMachine(ObjectDictionary& od, ServerConfig config, SdoServerFraming framing,
                     Send send);
    ~SdoServerMachine();
    SdoServerMachine(const SdoServerMachine&) = delete;
    SdoServerMachine& operator=(const SdoServerMachine&) = delete;

    /// Serves uploads of index:sub from `handler` instead of the dictionary.
    void set_domain_upload(std::uint16_t index, std::uint8_t sub, DomainUploadHandler handler);
    /// Sends downloads to index:sub to `handler` instead of the dictionary.
    void set_domain_download(std::uint16_t index, std::uint8_t sub, DomainDownloadHandler handler);
    void set_access_hook(AccessHook hook) { access_hook_ = std::move(hook); }

    /// One request: the 8-byte frame and, on CoE, the bytes after it in the same message. A
    /// shorter request is read with its tail as zeros (parse_frame()).
    void on_request(std::span<const std::uint8_t> request, TimePoint now);
    /// Earliest time on_tick() has work (client timeout, block gap timer); kNever when idle.
    [[nodiscard]] TimePoint next_deadline() const;
    void on_tick(TimePoint now);

    /// A frame the transport did not hand in (counted in stats().frames_ignored).
    void count_ignored() { ++stats_.frames_ignored; }
    [[nodiscard]] bool busy() const;
    [[nodiscard]] const ServerStats& stats() const { return stats_; }
    [[nodiscard]] const ServerConfig& config() const { return config_; }
    [[nodiscard]] const SdoServerFraming& framing() const { return framing_; }

private:
    ObjectDictionary& od_;
    ServerConfig config_;
    SdoServerFraming framing_;
    Send send_;
    std::map<std::uint32_t, DomainUploadHandler> upload_handlers_;
    std::map<std::uint32_t, DomainDownloadHandler> download_handlers_;
    AccessHook access_hook_;
    std::unique_ptr<detail::ServerSession> session_;
    ServerStats stats_;
};

} // namespace codrive::sdo
