// SPDX-License-Identifier: Apache-2.0
// CoE services as sans-I/O state machines: one request payload out, one reply in per step
// (SDO upload/download with the CiA 301 codec of sdo/, SDO information), and the per-slave
// mailbox channel that carries them one datagram per cycle.
#pragma once

#include <codrive/ethercat/master.hpp>

#include <deque>
#include <memory>
#include <string>
#include <vector>

namespace codrive::ethercat::detail {

/// What a transfer wants after a reply. SendLast: `request` is the last message (FoE's final
/// ACK, or an ERR telling the slave why the master gives up); the transfer ends, with its
/// outcome, once the slave took it. Stray: the reply answers an earlier transfer (one that timed
/// out, whose answer waited in SM1 ahead of this one's): dropped and counted, the step's
/// deadline stays, so a slave that only sends such answers still times out.
enum class TransferStep : int { Send, Wait, Done, Failed, SendLast, Stray };

/// One CoE exchange (ETG.1000.6 §5.6.2), or an FoE one (mailbox_type() Foe, §5.7: every FoE
/// reply goes to on_reply()). The channel sends request(), feeds every reply of service() (and
/// SDO aborts) to on_reply(), and finishes the transfer on Done or Failed.
class CoeTransfer {
public:
    using Step = TransferStep;
    virtual ~CoeTransfer() = default;
    /// The first request (CoE header first) into `request`. A transfer that cannot start sets
    /// outcome.error and its sentence instead; the channel then finishes it without sending.
    virtual void first(std::vector<std::uint8_t>& request) = 0;
    /// A reply (CoE header first). Send: `request` holds the next request; Wait: more
    /// fragments follow; Failed: outcome holds the error and its sentence.
    virtual Step on_reply(std::span<const std::uint8_t> coe,
                          std::vector<std::uint8_t>& request) = 0;
    /// The step's deadline passed. A transfer whose dropped (Stray) replies explain the silence
    /// sets outcome and says Failed, or SendLast with the abort in `request`; Wait lets the
    /// channel report the timeout.
    virtual Step on_timeout(std::vector<std::uint8_t>& request) {
        (void)request;
        return Step::Wait;
    }
    /// The CoE service the replies come with.
    [[nodiscard]] virtual CoeService service() const = 0;
    /// The mailbox protocol of its messages: CoE here, FoE for file transfers (foe_transfer.cpp).
    [[nodiscard]] virtual MailboxType mailbox_type() const { return MailboxType::Coe; }

    std::string label;  ///< "slave 2 (AKD2G)"
    std::string what;   ///< "SDO upload 0x6064:00"
    CoeOutcome outcome; ///< data on success, error + sentence on failure
    CoeDone done;

protected:
    Step failed(std::error_code ec, const std::string& why);
};

/// `mailbox_out`: the slave's SM0 size (bounds the requests), for segmenting downloads.
std::unique_ptr<CoeTransfer> make_sdo_upload(std::uint16_t index, std::uint8_t subindex,
                                             bool complete_access);
std::unique_ptr<CoeTransfer> make_sdo_download(std::uint16_t index, std::uint8_t subindex,
                                               std::vector<std::uint8_t> data, bool complete_access,
                                               std::size_t mailbox_out);
/// SDO information request `request_opcode` (odd, ETG.1000.6 Table 42) with its body; the reply
/// fragments are joined into outcome.data.
std::unique_ptr<CoeTransfer> make_sdo_info(std::uint8_t request_opcode,
                                           std::vector<std::uint8_t> body, std::string what);

/// Where a slave's mailbox exchange stands; each phase is one datagram per cycle.
enum class MailboxPhase : std::uint8_t {
    Idle,        ///< nothing to do (an emergency poll may read SM1 now and then)
    Write,       ///< FPWR of the request into SM0 (WKC 0: SM0 still full)
    Read,        ///< FPRD of SM1 (WKC 0: no answer yet)
    RepeatRead,  ///< FPRD of SM1 activate (0x0806) before toggling RepeatReq
    RepeatWrite, ///< FPWR of SM1 activate with RepeatReq toggled (ETG.1000.4 §6.7.2)
    RepeatAck,   ///< FPRD of SM1 PDI control (0x0807) until RepeatAck follows
};

struct MailboxChannel {
    std::deque<std::unique_ptr<CoeTransfer>> queue; ///< front() runs when `active`
    bool active = false;
    MailboxPhase phase = MailboxPhase::Idle;
    std::vector<std::uint8_t> request; ///< CoE payload of the current step
    std::vector<std::uint8_t> out;     ///< the SM0 image of the current request
    TimePoint deadline = kNever;       ///< of the current step
    TimePoint started{};               ///< of the current step (for the sentence)
    TimePoint next_poll{};             ///< emergency poll while idle
    bool sm0_full = false;             ///< the last write found SM0 full
    bool last_write = false;           ///< the transfer ends once this write is taken (SendLast)
    /// The slave took a repeat request and no message was read since: one with the counter of
    /// the last message read is a copy of it (the channel and Master::mailbox_read() share it).
    bool repeated = false;
    std::uint8_t repeat_want = 0; ///< SM1 activate value with RepeatReq toggled
    unsigned frames_lost = 0;     ///< of the current step, not back in time
    unsigned frames_unsent = 0;   ///< of the current step, could not be sent
    unsigned strays = 0;          ///< of the current step, messages read that it did not take
    int datagram = -1;            ///< position of its datagram in the frame in flight
};

} // namespace codrive::ethercat::detail
