// SPDX-License-Identifier: Apache-2.0
// SDO server state machine (CiA 301 §7.2.4.3): one transfer at a time per channel, for CAN and
// CoE (ETG.1000.6 §5.6.2: normal transfer, long segments, complete access, no block transfer).
#include "server_session.hpp"

#include <codrive/sdo/protocol.hpp>
#include <codrive/sdo/server_machine.hpp>

#include <algorithm>
#include <vector>

namespace codrive::sdo {

using detail::BlockReceiver;
using detail::BlockSender;
using detail::Ctx;
using detail::key;
using detail::State;

SdoServerFraming SdoServerFraming::coe(std::size_t sdo_room) {
    // One answer holds the 8-byte frame then normal-transfer data (ETG.1000.6 §5.6.2.5), or a
    // segment's command byte then its data (§5.6.2.6); a segment always holds CiA 301's 7 bytes.
    SdoServerFraming f;
    f.initiate_room = sdo_room > kFrameLen ? sdo_room - kFrameLen : 0;
    f.segment_room = std::max(kSegmentData, sdo_room > 1 ? sdo_room - 1 : 0);
    f.complete_access = true;
    f.block = false;
    f.ignore_repeats = false;
    return f;
}

SdoServerMachine::SdoServerMachine(ObjectDictionary& od, ServerConfig config,
                                   SdoServerFraming framing, Send send)
    : od_(od), config_(config), framing_(framing), send_(std::move(send)),
      session_(std::make_unique<detail::ServerSession>()) {
    config_.block_size = std::clamp<std::uint8_t>(config_.block_size, 1, kMaxBlockSize);
}

SdoServerMachine::~SdoServerMachine() = default;

void SdoServerMachine::set_domain_upload(std::uint16_t index, std::uint8_t sub,
                                         DomainUploadHandler handler) {
    upload_handlers_[key(index, sub)] = std::move(handler);
}

void SdoServerMachine::set_domain_download(std::uint16_t index, std::uint8_t sub,
                                           DomainDownloadHandler handler) {
    download_handlers_[key(index, sub)] = std::move(handler);
}

bool SdoServerMachine::busy() const {
    return session_->state != State::Idle;
}

TimePoint SdoServerMachine::next_deadline() const {
    return session_->deadline;
}

namespace {

/// A request byte-identical to the previous one is a repeat of the same frame for the kinds a
/// client never sends twice in a row on purpose: segment requests alternate the toggle bit, and
/// start, end request and end response come once per transfer. Initiate requests are answered
/// again (a client retries an expedited request unchanged; restarting is harmless), and two
/// successive sub-block responses may legitimately be identical.
bool is_ignorable_repeat(FrameKind kind) {
    switch (kind) {
    case FrameKind::UploadSegmentRequest:
    case FrameKind::DownloadSegmentRequest:
    case FrameKind::BlockUploadStart:
    case FrameKind::BlockDownloadEndRequest:
    case FrameKind::BlockUploadEndResponse:
        return true;
    default:
        return false;
    }
}

} // namespace

void SdoServerMachine::on_request(std::span<const std::uint8_t> request, TimePoint now) {
    detail::ServerSession& s = *session_;
    Ctx c{od_, config_, framing_, send_, s, stats_, now};
    const bool in_block = s.state == State::BlockDownloadData;
    // The CiA 301 frame, then (CoE) its data past 8 bytes; parse_frame() pads a shorter one.
    const auto frame = request.first(std::min(request.size(), kFrameLen));
    const auto extra =
        request.size() > kFrameLen ? request.subspan(kFrameLen) : std::span<const std::uint8_t>{};
    const FrameInfo info = parse_frame(frame, Sender::Client, in_block);
    ++stats_.requests;

    const bool same_as_last =
        framing_.ignore_repeats && s.have_last_request && request.size() == kFrameLen &&
        std::equal(s.last_request.begin(), s.last_request.end(), frame.begin());
    if (same_as_last && in_block &&
        parse_frame(frame, Sender::Client).kind == FrameKind::BlockDownloadInitiateRequest) {
        // The block download initiate request again (a repeat, or the client's retry after our
        // response was lost): inside the sub-block it would read as a segment. Answer it again;
        // a client that got the first answer ignores the copy.
        ++stats_.repeats_ignored;
        c.send(s.flow_frame);
        return;
    }
    const bool repeat = !in_block && same_as_last;
    std::copy_n(frame.begin(), frame.size(), s.last_request.begin());
    s.have_last_request = request.size() == kFrameLen;
    // In the end phase of a block download the copy of the last segment (c bit set, no command
    // specifier) parses as some command: a repeat of it is ignored whatever it looks like.
    if (repeat && (is_ignorable_repeat(info.kind) || s.state == State::BlockDownloadEnd)) {
        ++stats_.repeats_ignored;
        return;
    }
    if (info.kind == FrameKind::BlockUploadAck && s.state == State::BlockUploadEnd) {
        // A sub-block response after the last sub-block was taken as acknowledged: a repeat, or
        // the answer to a sub-block a repeated response made us send early. The data it
        // acknowledges is already confirmed; the end frame is on its way.
        ++stats_.repeats_ignored;
        return;
    }

    if (info.kind == FrameKind::Abort && s.state != State::Idle &&
        (info.index != s.index || info.subindex != s.sub)) {
        // CiA 301 §7.2.4.3.17: an abort names the transfer it ends. One for another object is
        // left over from an earlier transfer (or a late block segment that looks like one).
        ++stats_.repeats_ignored;
        return;
    }
    if (info.kind == FrameKind::Abort) {
        ++stats_.aborts_received;
        c.cancel_writer();
        c.idle();
        return;
    }

    // A new initiate request ends whatever ran before: the client has given up on it.
    switch (info.kind) {
    case FrameKind::InitiateUploadRequest:
    case FrameKind::InitiateDownloadRequest:
    case FrameKind::BlockUploadInitiateRequest:
    case FrameKind::BlockDownloadInitiateRequest:
        c.cancel_writer();
        c.idle();
        s.index = info.index;
        s.sub = info.subindex;
        s.done = 0;
        s.total.reset();
        s.write_error = SdoAbort::DataTransfer;
        // CoE complete access: bit 4 of an initiate request (ETG.1000.6 §5.6.2.1.1); on CAN the
        // bit is reserved ("x", CiA 301 §7.2.4.3.3/6) and ignored.
        s.complete_access = framing_.complete_access && !frame.empty() &&
                            (frame[0] & kCompleteAccessBit) != 0 &&
                            (info.kind == FrameKind::InitiateUploadRequest ||
                             info.kind == FrameKind::InitiateDownloadRequest);
        if (!framing_.block && (info.kind == FrameKind::BlockUploadInitiateRequest ||
                                info.kind == FrameKind::BlockDownloadInitiateRequest)) {
            // CoE has no block transfer: command specifiers 5 and 6 are not valid there
            // (ETG.1000.6 §5.6.2), CiA 301 §7.2.4.3.17's 0x05040001.
            c.abort(SdoAbort::UnknownCommand);
            return;
        }
        if (access_hook_) {
            const Direction dir = (info.kind == FrameKind::InitiateUploadRequest ||
                                   info.kind == FrameKind::BlockUploadInitiateRequest)
                                      ? Direction::Upload
                                      : Direction::Download;
            if (auto refused = access_hook_(s.index, s.sub, dir)) {
                c.abort(*refused);
                return;
            }
        }
        break;
    default:
        break;
    }

    const auto unexpected = [&] { c.abort(SdoAbort::UnknownCommand); };

    switch (info.kind) {
    case FrameKind::InitiateUploadRequest:
        if (auto ok = open_upload(c, upload_handlers_); !ok) {
            c.abort(ok.error());
            return;
        }
        respond_upload(c);
        return;

    case FrameKind::InitiateDownloadRequest: {
        std::optional<std::size_t> size;
        if (info.expedited) {
            if (info.size_indicated) {
                size = info.data_len;
            } else if (const SubObject* sub =
                           s.complete_access ? nullptr : od_.find(s.index, s.sub)) {
                // e=1, s=0: size unspecified; a fixed-size object takes its own size.
                const std::size_t fixed = data_type_size(sub->type);
                size = fixed != 0 && fixed <= kExpeditedMax ? fixed : kExpeditedMax;
            } else {
                size = kExpeditedMax;
            }
        } else if (info.size_indicated) {
            size = info.size;
        }
        if (auto ok = open_download(c, download_handlers_, size); !ok) {
            c.abort(ok.error());
            return;
        }
        if (info.expedited) {
            if (!write_data(c, std::span<const std::uint8_t>(info.data.data(), *size))) {
                c.abort(s.write_error);
                return;
            }
            if (auto ok = commit_download(c); !ok) {
                c.abort(ok.error());
                return;
            }
            c.send(make_initiate_download_response(s.index, s.sub));
            c.complete();
            return;
        }
        s.total = size;
        s.toggle = false;
        if (framing_.initiate_room > 0) {
            // CoE normal transfer (ETG.1000.6 §5.6.2.2): data follows the size in the same
            // request; segments follow only for the rest (an announced 0 bytes is complete
            // here). Bytes past the size are padding.
            const auto data = size ? extra.first(std::min(extra.size(), *size)) : extra;
            if (!write_data(c, data)) {
                c.abort(s.write_error);
                return;
            }
            s.done = data.size();
            if (size && s.done == *size) {
                if (auto ok = commit_download(c); !ok) {
                    c.abort(ok.error());
                    return;
                }
                c.send(make_initiate_download_response(s.index, s.sub));
                c.complete();
                return;
            }
        }
        s.state = State::DownloadSegment;
        c.send(make_initiate_download_response(s.index, s.sub));
        c.arm();
        return;
    }

    case FrameKind::UploadSegmentRequest:
        if (s.state != State::UploadSegment) {
            unexpected();
            return;
        }
        if (info.toggle != s.toggle) {
            c.abort(SdoAbort::ToggleBit);
            return;
        }
        send_segment(c);
        return;

    case FrameKind::DownloadSegmentRequest: {
        if (s.state != State::DownloadSegment) {
            unexpected();
            return;
        }
        if (info.toggle != s.toggle) {
            c.abort(SdoAbort::ToggleBit);
            return;
        }
        // CiA 301: up to 7 bytes. CoE: a segment with seg data size 0 (7 bytes in the frame)
        // carries every byte after its command byte (ETG.1000.6 §5.6.2.4).
        std::vector<std::uint8_t> long_segment;
        std::span<const std::uint8_t> data(info.data.data(), info.data_len);
        if (info.data_len == kSegmentData && !extra.empty()) {
            long_segment.assign(data.begin(), data.end());
            long_segment.insert(long_segment.end(), extra.begin(), extra.end());
            data = long_segment;
        }
        if (s.total && s.done + data.size() > *s.total) {
            c.abort(SdoAbort::LengthTooHigh);
            return;
        }
        if (!write_data(c, data)) {
            c.abort(s.write_error);
            return;
        }
        s.done += data.size();
        if (info.last) {
            if (s.total && s.done != *s.total) {
                c.abort(SdoAbort::LengthMismatch);
                return;
            }
            if (auto ok = commit_download(c); !ok) {
                c.abort(ok.error());
                return;
            }
            c.send(make_download_segment_response(s.toggle));
            c.complete();
            return;
        }
        c.send(make_download_segment_response(s.toggle));
        s.toggle = !s.toggle;
        c.arm();
        return;
    }

    case FrameKind::BlockDownloadInitiateRequest: {
        std::optional<std::size_t> size;
        if (info.size_indicated) {
            size = info.size;
        }
        if (auto ok = open_download(c, download_handlers_, size); !ok) {
            c.abort(ok.error());
            return;
        }
        s.total = size;
        s.crc = config_.crc && info.crc;
        s.block_size = config_.block_size;
        s.receiver.reset(s.block_size);
        s.state = State::BlockDownloadData;
        s.flow_frame = make_block_download_initiate_response(s.index, s.sub, s.crc, s.block_size);
        c.send(s.flow_frame);
        // Repeated only on request (ServerConfig::repeat_block_responses): codrive's client
        // ignores a late initiate response in mid-transfer, but other clients do not.
        if (config_.repeat_block_responses) {
            s.flow_sent = now;
            s.deadline = std::min(s.deadline, now + config_.block_gap_timeout);
        }
        c.arm();
        return;
    }

    case FrameKind::BlockSegment: {
        using R = BlockReceiver::SegmentResult;
        const auto r = s.receiver.on_segment(
            info, [&c](std::span<const std::uint8_t> d) { return write_data(c, d); });
        if (r != BlockReceiver::SegmentResult::Stale) {
            s.flow_sent = kNever; // the sub-block asked for is coming
        }
        switch (r) {
        case R::InvalidSequence:
            c.abort(SdoAbort::InvalidSequence);
            return;
        case R::WriteFailed:
            c.abort(s.write_error);
            return;
        case R::Stale:
            c.arm();
            return;
        case R::Stored:
        case R::Skipped:
            if (s.total && s.receiver.received() > *s.total) {
                c.abort(SdoAbort::LengthTooHigh);
                return;
            }
            s.gap_activity = now;
            s.deadline = std::min(s.deadline, now + config_.block_gap_timeout);
            c.arm();
            return;
        case R::SubBlockDone:
            break;
        }
        const std::uint8_t ackseq = s.receiver.ackseq();
        if (s.receiver.complete()) {
            s.state = State::BlockDownloadEnd;
        }
        s.block_size = s.receiver.next_block_size(config_.block_size);
        s.receiver.start_sub_block(s.block_size);
        s.gap_activity = kNever;
        send_flow(c, make_block_download_ack(ackseq, s.block_size), !s.receiver.complete());
        c.arm();
        return;
    }

    case FrameKind::BlockDownloadEndRequest: {
        if (s.state != State::BlockDownloadEnd) {
            unexpected();
            return;
        }
        if (!s.receiver.finish(
                info.unused, [&c](std::span<const std::uint8_t> d) { return write_data(c, d); })) {
            c.abort(s.write_error);
            return;
        }
        if (s.crc && s.receiver.crc() != info.crc_value) {
            c.abort(SdoAbort::CrcError);
            return;
        }
        if (s.total && s.receiver.received() != *s.total) {
            c.abort(SdoAbort::LengthMismatch);
            return;
        }
        if (auto ok = commit_download(c); !ok) {
            c.abort(ok.error());
            return;
        }
        c.send(make_block_download_end_response());
        c.complete();
        return;
    }

    case FrameKind::BlockUploadInitiateRequest: {
        if (info.block_size == 0 || info.block_size > kMaxBlockSize) {
            c.abort(SdoAbort::InvalidBlockSize);
            return;
        }
        if (auto ok = open_upload(c, upload_handlers_); !ok) {
            c.abort(ok.error());
            return;
        }
        if (info.pst != 0 && s.reader.size <= info.pst) {
            // CiA 301 §7.2.4.3.13: at or below the protocol switch threshold the server may
            // answer with an ordinary initiate upload response.
            respond_upload(c);
            return;
        }
        if (s.reader.size > 0xFFFFFFFFU) {
            c.abort(SdoAbort::LengthTooHigh);
            return;
        }
        s.crc = config_.crc && info.crc;
        s.block_size = info.block_size;
        s.sender.reset(s.reader.size);
        s.state = State::BlockUploadStart;
        c.send(make_block_upload_initiate_response(s.index, s.sub, s.crc,
                                                   static_cast<std::uint32_t>(s.reader.size)));
        c.arm();
        return;
    }

    case FrameKind::BlockUploadStart:
        if (s.state != State::BlockUploadStart) {
            unexpected();
            return;
        }
        send_sub_block(c);
        return;

    case FrameKind::BlockUploadAck: {
        if (s.state != State::BlockUploadAck) {
            unexpected();
            return;
        }
        const auto r = s.sender.on_ack(info.seqno, info.block_size);
        if (r == BlockSender::AckResult::Repeat) {
            ++stats_.repeats_ignored;
            return;
        }
        if (r == BlockSender::AckResult::InvalidSequence) {
            c.abort(SdoAbort::InvalidSequence);
            return;
        }
        if (r == BlockSender::AckResult::InvalidBlockSize) {
            c.abort(SdoAbort::InvalidBlockSize);
            return;
        }
        if (r == BlockSender::AckResult::Done) {
            s.state = State::BlockUploadEnd;
            c.send(make_block_upload_end(s.sender.last_unused(), s.crc ? s.sender.crc() : 0));
            c.arm();
            return;
        }
        s.block_size = info.block_size;
        send_sub_block(c);
        return;
    }

    case FrameKind::BlockUploadEndResponse:
        if (s.state != State::BlockUploadEnd) {
            unexpected();
            return;
        }
        c.complete();
        return;

    default:
        unexpected();
        return;
    }
}

void SdoServerMachine::on_tick(TimePoint now) {
    detail::ServerSession& s = *session_;
    Ctx c{od_, config_, framing_, send_, s, stats_, now};
    if (s.state == State::BlockDownloadData && s.gap_activity != kNever &&
        now >= s.gap_activity + config_.block_gap_timeout) {
        // The sub-block stalled, most likely because its last segment was lost: acknowledge
        // what arrived in sequence so the client repeats the rest (CiA 301 §7.2.4.3.10).
        const std::uint8_t ackseq = s.receiver.ackseq();
        s.block_size = s.receiver.next_block_size(config_.block_size);
        s.receiver.start_sub_block(s.block_size, /*early=*/true);
        s.gap_activity = kNever;
        ++stats_.early_acks;
        send_flow(c, make_block_download_ack(ackseq, s.block_size), true);
        c.arm();
    } else if (s.state == State::BlockDownloadData && s.flow_sent != kNever &&
               now >= s.flow_sent + config_.block_gap_timeout &&
               now < s.activity + config_.timeout) {
        // Nothing of the sub-block came: the response was probably lost.
        ++stats_.acks_repeated;
        s.flow_sent = now;
        c.send(s.flow_frame);
    } else if (s.state != State::Idle && now >= s.activity + config_.timeout) {
        ++stats_.timeouts;
        c.abort(SdoAbort::Timeout);
    }
    if (s.state == State::Idle) {
        s.deadline = kNever;
        return;
    }
    s.deadline = s.activity + config_.timeout;
    if (s.gap_activity != kNever) {
        s.deadline = std::min(s.deadline, s.gap_activity + config_.block_gap_timeout);
    }
    if (s.flow_sent != kNever) {
        s.deadline = std::min(s.deadline, s.flow_sent + config_.block_gap_timeout);
    }
}

} // namespace codrive::sdo
