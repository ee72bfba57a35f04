// SPDX-License-Identifier: Apache-2.0
// The SDO server machine's session (one transfer) and the helpers over it that move data: open,
// read and write, upload responses and segments, block sub-blocks (server_machine.cpp drives them).
#pragma once

#include "block_receiver.hpp"
#include "block_sender.hpp"

#include <codrive/sdo/protocol.hpp>
#include <codrive/sdo/server_machine.hpp>

#include <algorithm>
#include <map>
#include <optional>
#include <vector>

namespace codrive::sdo::detail {

[[nodiscard]] constexpr std::uint32_t key(std::uint16_t index, std::uint8_t sub) {
    return (static_cast<std::uint32_t>(index) << 8) | sub;
}

struct ServerSession {
    enum class State : std::uint8_t {
        Idle,
        UploadSegment,
        DownloadSegment,
        BlockDownloadData,
        BlockDownloadEnd,
        BlockUploadStart,
        BlockUploadAck,
        BlockUploadEnd,
    };
    State state = State::Idle;
    std::uint16_t index = 0;
    std::uint8_t sub = 0;
    bool toggle = false;
    bool crc = false;
    std::uint8_t block_size = kMaxBlockSize;
    std::size_t done = 0;
    std::optional<std::size_t> total;
    /// The server's timer: may run early (on_tick() re-arms it), never late.
    TimePoint deadline = kNever;
    /// Last frame of the running transfer: the client timeout runs from here.
    TimePoint activity = kNever;
    /// Last block segment of a sub-block not yet acknowledged (kNever: none pending).
    TimePoint gap_activity = kNever;
    /// Block download: the initiate or sub-block response sent last, and when, while nothing of
    /// the sub-block it asks for has arrived (kNever: not waiting); repeated after the gap
    /// timeout, since a lost one would stall both sides until the timeout.
    Payload flow_frame{};
    TimePoint flow_sent = kNever;
    /// Upload: the object's bytes (copied from the dictionary) or a domain reader.
    DomainReader reader;
    /// Download: collected bytes for the dictionary, or a domain writer.
    std::optional<DomainWriter> writer;
    std::vector<std::uint8_t> buffer;
    SdoAbort write_error = SdoAbort::DataTransfer;
    /// CoE complete access (SdoServerFraming::complete_access): the whole object from sub 0/1.
    bool complete_access = false;
    /// Last request handled: a byte-identical copy is a repeat (CAN repeats a frame after an
    /// ACK error), see is_ignorable_repeat().
    Payload last_request{};
    bool have_last_request = false;
    BlockSender sender;
    BlockReceiver receiver;
};

using State = ServerSession::State;

/// What the helpers work with: the dictionary, the options, the output and the session.
struct Ctx {
    ObjectDictionary& od;
    const ServerConfig& config;
    const SdoServerFraming& framing;
    const SdoServerMachine::Send& out;
    ServerSession& s;
    ServerStats& stats;
    TimePoint now;

    void send(const Payload& p, std::span<const std::uint8_t> extra = {}) const {
        if (out) {
            out(p, extra);
        }
    }

    void cancel_writer() const {
        if (s.writer && s.writer->cancel) {
            s.writer->cancel();
        }
        s.writer.reset();
    }
    void idle() const {
        s.state = State::Idle;
        s.gap_activity = kNever;
        s.flow_sent = kNever;
        s.reader = {};
        s.writer.reset();
    }
    void abort(SdoAbort code) const { abort(s.index, s.sub, code); }
    void abort(std::uint16_t index, std::uint8_t sub, SdoAbort code) const {
        ++stats.aborts_sent;
        send(make_abort(index, sub, static_cast<std::uint32_t>(code)));
        cancel_writer();
        idle();
    }
    void arm() const {
        s.activity = now;
        s.deadline = std::min(s.deadline, now + config.timeout);
    }
    void complete() const {
        ++stats.completed;
        idle();
    }
};

/// The data of an upload: a domain reader or a copy of the dictionary value (complete access:
/// the whole object), so a value that changes while segments go out stays consistent.
tl::expected<void, SdoAbort>
open_upload(Ctx& c, const std::map<std::uint32_t, DomainUploadHandler>& handlers);
/// Checks a download before accepting data (CiA 301: refuse early, with the precise code).
tl::expected<void, SdoAbort>
open_download(Ctx& c, const std::map<std::uint32_t, DomainDownloadHandler>& handlers,
              std::optional<std::size_t> size);
/// Stores downloaded data (domain writer or buffer); false: s.write_error says why.
bool write_data(Ctx& c, std::span<const std::uint8_t> data);
/// Ends a download: the domain writer's finish or the dictionary write.
tl::expected<void, SdoAbort> commit_download(Ctx& c);
/// The next upload segment (framing.segment_room bytes at most).
void send_segment(Ctx& c);
/// The next sub-block of a block upload.
void send_sub_block(Ctx& c);
/// Sends a sub-block response; `waiting`: a sub-block is expected next.
void send_flow(Ctx& c, const Payload& p, bool waiting);
/// Initiate upload response for an opened upload; also used by a block upload that switches
/// protocol (size <= pst).
void respond_upload(Ctx& c);

} // namespace codrive::sdo::detail
