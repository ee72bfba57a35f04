// SPDX-License-Identifier: Apache-2.0
// SDO conversation tracking and reassembly (CiA 301 §7.2.4.3).
#include <codrive/dump/sdo_tracker.hpp>

#include <codrive/core/sdo_abort.hpp>
#include <codrive/dump/text_append.hpp>
#include <codrive/dump/value_format.hpp>
#include <codrive/sdo/crc16.hpp>

#include <algorithm>
#include <iterator>

namespace codrive::dump {
namespace {

using sdo::FrameKind;

double to_ms(std::int64_t ns) {
    return static_cast<double>(ns) / 1e6;
}

} // namespace

SdoTracker::SdoTracker(const ObjectCatalog& catalog, std::int64_t timeout_ns)
    : catalog_(catalog), timeout_ns_(timeout_ns) {}

void SdoTracker::object_name(fmt::memory_buffer& out, NodeId node, std::uint16_t index,
                             std::uint8_t sub) const {
    fmt::format_to(std::back_inserter(out), "{:04X}:{:02X}", index, sub);
    const auto before = out.size();
    out.push_back(' ');
    (void)catalog_.lookup(node, index, sub, &out);
    if (out.size() == before + 1) {
        out.resize(before);
    }
}

namespace {
constexpr std::string_view kOpNames[] = {"", "download ", "upload ", "block download ",
                                         "block upload "};
} // namespace

bool SdoTracker::start(NodeId node, Channel& ch, Op op, const sdo::FrameInfo& fi, std::int64_t ts,
                       fmt::memory_buffer& out) {
    const bool abandoned = ch.op != Op::None;
    if (!abandoned) {
        ++open_;
    } else {
        // CiA 301 §7.2.4.3: one transfer per SDO channel; a new initiate ends the old one unseen.
        fmt::format_to(std::back_inserter(out), "SDO {}", kOpNames[static_cast<int>(ch.op)]);
        object_name(out, node, ch.index, ch.subindex);
        text::put(out, " abandoned by the client");
        put_elapsed(out, ch, ts, " after ");
        text::put(out, "; ");
    }
    std::vector<std::uint8_t> keep = std::move(ch.data);
    ch = Channel{};
    ch.data = std::move(keep);
    ch.data.clear();
    ch.op = op;
    ch.started_timed = frame_timed_;
    ch.clocked = frame_timed_;
    ch.clock = frame_clock_;
    ch.index = fi.index;
    ch.subindex = fi.subindex;
    ch.t0 = frame_timed_ ? ts : 0;
    ch.last = ch.t0;
    ch.size_known = fi.size_indicated && !fi.expedited;
    ch.size = fi.size;
    ch.crc = fi.crc;
    return abandoned;
}

void SdoTracker::add_data(Channel& ch, std::span<const std::uint8_t> bytes) {
    if (ch.crc) {
        ch.crc_value = sdo::crc16_ccitt(bytes, ch.crc_value);
    }
    ch.total += static_cast<std::uint32_t>(bytes.size());
    const auto room = kKeepBytes - std::min(kKeepBytes, ch.data.size());
    const auto n = std::min(room, bytes.size());
    ch.data.insert(ch.data.end(), bytes.begin(), bytes.begin() + static_cast<std::ptrdiff_t>(n));
}

SdoOutcome SdoTracker::complete(NodeId node, Channel& ch, std::int64_t ts, SdoMode mode,
                                fmt::memory_buffer& out) {
    const bool upload = ch.op == Op::Upload || ch.op == Op::BlockUpload;
    text::put(out, upload ? "upload " : "download ");
    object_name(out, node, ch.index, ch.subindex);
    text::put(out, " = ");
    const auto info = catalog_.lookup(node, ch.index, ch.subindex, nullptr);
    format_value(out, info, ch.data);
    if (ch.data.size() <= 8 && !ch.data.empty()) {
        format_cia402_meaning(out, ch.index, get_le_n(ch.data.data(), ch.data.size()));
    }
    static constexpr std::string_view kModes[] = {"expedited", "segmented", "block"};
    fmt::format_to(std::back_inserter(out), " ({} byte{}, {}", ch.total, ch.total == 1 ? "" : "s",
                   kModes[static_cast<int>(mode)]);
    put_elapsed(out, ch, ts, ", ");
    if (ch.size_known && ch.size != ch.total) {
        fmt::format_to(std::back_inserter(out), ", size mismatch: {} announced", ch.size);
    }
    out.push_back(')');
    SdoOutcome o;
    o.kind = SdoOutcome::Kind::Completed;
    o.upload = upload;
    o.index = ch.index;
    o.subindex = ch.subindex;
    o.data = ch.data;
    o.size = ch.total;
    o.timed = measured(ch);
    o.duration_ns = o.timed ? ts - ch.t0 : 0;
    ch.op = Op::None;
    --open_;
    return o;
}

void SdoTracker::put_elapsed(fmt::memory_buffer& out, const Channel& ch, std::int64_t ts,
                             std::string_view before) const {
    if (measured(ch)) {
        text::put(out, before);
        fmt::format_to(std::back_inserter(out), "{:.1f} ms", to_ms(ts - ch.t0));
    }
}

SdoOutcome SdoTracker::on_frame(NodeId node, sdo::Sender sender,
                                std::span<const std::uint8_t> payload, std::int64_t ts,
                                fmt::memory_buffer& out, bool timed, std::uint8_t clock) {
    frame_timed_ = timed;
    frame_clock_ = clock;
    auto it = std::back_inserter(out);
    fmt::format_to(it, "node {} ", node);
    SdoOutcome none;
    const bool client = sender == sdo::Sender::Client;
    if (payload.size() < sdo::kFrameLen) {
        fmt::format_to(it, "SDO {} frame of {} bytes (CiA 301 requires 8)",
                       client ? "request" : "response", payload.size());
        none.kind = SdoOutcome::Kind::ProtocolError;
        if (Channel& cur = channels_[node]; cur.op != Op::None && !client) {
            // The response is the one the open transfer waited for: named here, and not
            // reported again as a timeout if no valid response follows.
            fmt::format_to(it, " in {}", kOpNames[static_cast<int>(cur.op)]);
            object_name(out, node, cur.index, cur.subindex);
            cur.short_response = true;
        }
        return none;
    }
    Channel& ch = channels_[node];
    const bool block_sender =
        (client && ch.op == Op::BlockDownload) || (!client && ch.op == Op::BlockUpload);
    const bool in_block = ch.in_block && block_sender && (payload[0] & sdo::kSeqnoMask) != 0;
    const auto fi = sdo::parse_frame(payload, sender, in_block);
    if (ch.op != Op::None) {
        if (frame_timed_) {
            // A transfer is on the clock of its last timed frame; one that moves to another
            // interface's clock has no duration.
            ch.started_timed = ch.started_timed && ch.clock == frame_clock_;
            ch.last = ts;
            ch.clocked = true;
            ch.clock = frame_clock_;
        }
        ch.client_spoke_last = client;
        ch.short_response = ch.short_response && client;
    }
    const auto unexpected = [&] {
        text::put(out, "SDO ");
        text::put(out, sdo::to_string(fi.kind));
        if (sdo::is_initiate_response(fi.kind)) {
            out.push_back(' ');
            object_name(out, node, fi.index, fi.subindex);
        }
        text::put(out, " without a matching request");
        if (ch.op != Op::None) {
            fmt::format_to(it, " (open: {}", kOpNames[static_cast<int>(ch.op)]);
            object_name(out, node, ch.index, ch.subindex);
            out.push_back(')');
        }
        none.kind = SdoOutcome::Kind::ProtocolError;
        return none;
    };

    switch (fi.kind) {
    case FrameKind::Invalid:
        fmt::format_to(it, "SDO invalid command byte 0x{:02X}", payload[0]);
        none.kind = SdoOutcome::Kind::ProtocolError;
        return none;

    case FrameKind::Abort: {
        fmt::format_to(it, "SDO abort {}", kOpNames[static_cast<int>(ch.op)]);
        object_name(out, node, fi.index, fi.subindex);
        fmt::format_to(it, ": 0x{:08X} {} (by {}", fi.abort_code, sdo_abort_describe(fi.abort_code),
                       client ? "client" : "server");
        SdoOutcome o;
        o.kind = SdoOutcome::Kind::Aborted;
        o.index = fi.index;
        o.subindex = fi.subindex;
        if (ch.op != Op::None) {
            put_elapsed(out, ch, ts, ", after ");
            o.upload = ch.op == Op::Upload || ch.op == Op::BlockUpload;
            o.timed = measured(ch);
            o.duration_ns = o.timed ? ts - ch.t0 : 0;
            ch.op = Op::None;
            --open_;
        }
        out.push_back(')');
        return o;
    }

    case FrameKind::InitiateDownloadRequest: {
        if (start(node, ch, Op::Download, fi, ts, out)) {
            none.kind = SdoOutcome::Kind::ProtocolError;
        }
        ch.client_spoke_last = true;
        text::put(out, "SDO download request ");
        object_name(out, node, fi.index, fi.subindex);
        if (fi.expedited) {
            ch.expedited = true;
            const std::size_t n = fi.size_indicated ? fi.data_len : sdo::kExpeditedMax;
            add_data(ch, std::span(fi.data.data(), n));
            text::put(out, " = ");
            format_value(out, catalog_.lookup(node, fi.index, fi.subindex, nullptr), ch.data);
            if (!ch.data.empty()) {
                format_cia402_meaning(out, fi.index, get_le_n(ch.data.data(), ch.data.size()));
            }
        } else if (fi.size_indicated) {
            fmt::format_to(it, " (segmented, {} bytes)", fi.size);
        } else {
            text::put(out, " (segmented, size not indicated)");
        }
        return none;
    }
    case FrameKind::InitiateDownloadResponse:
        if (ch.op != Op::Download || fi.index != ch.index || fi.subindex != ch.subindex) {
            return unexpected();
        }
        if (ch.expedited) {
            return complete(node, ch, ts, SdoMode::Expedited, out);
        }
        text::put(out, "SDO download response ");
        object_name(out, node, fi.index, fi.subindex);
        text::put(out, ", segments follow");
        return none;
    case FrameKind::DownloadSegmentRequest:
        if (ch.op != Op::Download || ch.expedited) {
            return unexpected();
        }
        add_data(ch, std::span(fi.data.data(), fi.data_len));
        ++ch.segments;
        fmt::format_to(it, "SDO download segment {} ({} byte{}{}", ch.segments, fi.data_len,
                       fi.data_len == 1 ? "" : "s", fi.last ? ", last" : "");
        if (fi.toggle != ch.toggle) {
            text::put(out, ", toggle error");
        }
        out.push_back(')');
        ch.end_seen = fi.last;
        return none;
    case FrameKind::DownloadSegmentResponse:
        if (ch.op != Op::Download || ch.expedited) {
            return unexpected();
        }
        ch.toggle = !ch.toggle;
        if (ch.end_seen) {
            return complete(node, ch, ts, SdoMode::Segmented, out);
        }
        fmt::format_to(it, "SDO download segment {} confirmed", ch.segments);
        return none;

    case FrameKind::InitiateUploadRequest:
        if (start(node, ch, Op::Upload, fi, ts, out)) {
            none.kind = SdoOutcome::Kind::ProtocolError;
        }
        ch.client_spoke_last = true;
        text::put(out, "SDO upload request ");
        object_name(out, node, fi.index, fi.subindex);
        return none;
    case FrameKind::InitiateUploadResponse:
        // A block upload request may be answered this way (protocol switch, §7.2.4.3.13).
        if ((ch.op != Op::Upload && ch.op != Op::BlockUpload) || fi.index != ch.index ||
            fi.subindex != ch.subindex) {
            return unexpected();
        }
        ch.op = Op::Upload;
        if (fi.expedited) {
            const std::size_t n = fi.size_indicated ? fi.data_len : sdo::kExpeditedMax;
            add_data(ch, std::span(fi.data.data(), n));
            return complete(node, ch, ts, SdoMode::Expedited, out);
        }
        ch.size_known = fi.size_indicated;
        ch.size = fi.size;
        ch.confirmed = true;
        text::put(out, "SDO upload response ");
        object_name(out, node, fi.index, fi.subindex);
        if (fi.size_indicated) {
            fmt::format_to(it, " (segmented, {} bytes)", fi.size);
        } else {
            text::put(out, " (segmented, size not indicated)");
        }
        return none;
    case FrameKind::UploadSegmentRequest:
        if (ch.op != Op::Upload) {
            return unexpected();
        }
        fmt::format_to(it, "SDO upload segment {} request", ch.segments + 1);
        if (fi.toggle != ch.toggle) {
            text::put(out, " (toggle error)");
        }
        return none;
    case FrameKind::UploadSegmentResponse: {
        if (ch.op != Op::Upload) {
            return unexpected();
        }
        if (!ch.confirmed) {
            // CiA 301 §7.2.4.3.6: the initiate upload request is answered by an initiate upload
            // response (scs 2) or an abort, never by a segment.
            text::put(out, "SDO upload segment answers upload request ");
            object_name(out, node, ch.index, ch.subindex);
            text::put(out, ": expected the initiate upload response (0x4n) or an abort");
            none.kind = SdoOutcome::Kind::ProtocolError;
            return none;
        }
        const bool toggle_ok = fi.toggle == ch.toggle;
        ch.toggle = !ch.toggle;
        add_data(ch, std::span(fi.data.data(), fi.data_len));
        ++ch.segments;
        if (fi.last && toggle_ok) {
            return complete(node, ch, ts, SdoMode::Segmented, out);
        }
        fmt::format_to(it, "SDO upload segment {} ({} byte{}{}{})", ch.segments, fi.data_len,
                       fi.data_len == 1 ? "" : "s", fi.last ? ", last" : "",
                       toggle_ok ? "" : ", toggle error");
        if (fi.last) {
            ch.op = Op::None;
            --open_;
        }
        return none;
    }

    case FrameKind::BlockDownloadInitiateRequest:
        if (start(node, ch, Op::BlockDownload, fi, ts, out)) {
            none.kind = SdoOutcome::Kind::ProtocolError;
        }
        ch.client_spoke_last = true;
        ch.size_known = fi.size_indicated;
        text::put(out, "SDO block download request ");
        object_name(out, node, fi.index, fi.subindex);
        if (fi.size_indicated) {
            fmt::format_to(it, " ({} bytes{})", fi.size, fi.crc ? ", CRC" : "");
        }
        return none;
    case FrameKind::BlockDownloadInitiateResponse:
        if (ch.op != Op::BlockDownload || fi.index != ch.index || fi.subindex != ch.subindex) {
            return unexpected();
        }
        ch.crc = ch.crc && fi.crc; // both sides must support CRC for it to be used
        ch.block_size = fi.block_size;
        ch.in_block = true;
        ch.sub_len = 0;
        ch.last_seq = 0;
        text::put(out, "SDO block download response ");
        object_name(out, node, fi.index, fi.subindex);
        fmt::format_to(it, " (blksize {})", fi.block_size);
        return none;
    case FrameKind::BlockUploadInitiateRequest:
        if (start(node, ch, Op::BlockUpload, fi, ts, out)) {
            none.kind = SdoOutcome::Kind::ProtocolError;
        }
        ch.client_spoke_last = true;
        ch.block_size = fi.block_size;
        text::put(out, "SDO block upload request ");
        object_name(out, node, fi.index, fi.subindex);
        fmt::format_to(it, " (blksize {}{})", fi.block_size, fi.crc ? ", CRC" : "");
        return none;
    case FrameKind::BlockUploadInitiateResponse:
        if (ch.op != Op::BlockUpload || fi.index != ch.index || fi.subindex != ch.subindex) {
            return unexpected();
        }
        ch.crc = ch.crc && fi.crc;
        ch.size_known = fi.size_indicated;
        ch.size = fi.size;
        text::put(out, "SDO block upload response ");
        object_name(out, node, fi.index, fi.subindex);
        if (fi.size_indicated) {
            fmt::format_to(it, " ({} bytes)", fi.size);
        }
        return none;
    case FrameKind::BlockUploadStart:
        if (ch.op != Op::BlockUpload) {
            return unexpected();
        }
        ch.in_block = true;
        ch.sub_len = 0;
        ch.last_seq = 0;
        text::put(out, "SDO block upload start");
        return none;
    case FrameKind::BlockSegment: {
        const std::uint8_t seq = fi.seqno;
        fmt::format_to(it, "SDO block segment {}{}", seq, fi.last ? " (last)" : "");
        if (seq == ch.last_seq + 1 && ch.sub_len + sdo::kSegmentData <= ch.sub_block.size()) {
            std::copy_n(fi.data.begin(), sdo::kSegmentData,
                        ch.sub_block.begin() + static_cast<std::ptrdiff_t>(ch.sub_len));
            ch.sub_len += sdo::kSegmentData;
            ch.last_seq = seq;
            ch.end_seen = fi.last;
        } else {
            fmt::format_to(it, " out of sequence (expected {})", ch.last_seq + 1);
        }
        ++ch.segments;
        if (fi.last || seq >= ch.block_size) {
            ch.in_block = false; // the receiver acknowledges next
        }
        return none;
    }
    case FrameKind::BlockDownloadAck:
    case FrameKind::BlockUploadAck: {
        const Op want =
            fi.kind == FrameKind::BlockDownloadAck ? Op::BlockDownload : Op::BlockUpload;
        if (ch.op != want) {
            return unexpected();
        }
        const std::uint8_t ack = std::min(fi.seqno, ch.last_seq);
        const unsigned sent = ch.last_seq;
        const bool end_acked = ch.end_seen && ack == ch.last_seq && ack > 0;
        const std::size_t keep =
            end_acked ? (ack - 1U) * sdo::kSegmentData : std::size_t{ack} * sdo::kSegmentData;
        add_data(ch, std::span(ch.sub_block.data(), keep));
        if (end_acked) {
            std::copy_n(ch.sub_block.begin() + static_cast<std::ptrdiff_t>(keep), sdo::kSegmentData,
                        ch.tail.begin());
            ch.tail_pending = true;
        } else {
            ch.end_seen = false;
        }
        ch.sub_len = 0;
        ch.last_seq = 0;
        ch.block_size = fi.block_size;
        ch.in_block = !end_acked;
        fmt::format_to(it, "SDO block ack {} (blksize {}", fi.seqno, fi.block_size);
        if (sent > fi.seqno) {
            fmt::format_to(it, ", segments {}..{} to be sent again", fi.seqno + 1, sent);
        }
        out.push_back(')');
        return none;
    }
    case FrameKind::BlockDownloadEndRequest:
    case FrameKind::BlockUploadEndRequest: {
        const Op want =
            fi.kind == FrameKind::BlockDownloadEndRequest ? Op::BlockDownload : Op::BlockUpload;
        if (ch.op != want) {
            return unexpected();
        }
        if (ch.tail_pending) {
            const std::size_t n = sdo::kSegmentData - std::min<std::size_t>(fi.unused, 7);
            add_data(ch, std::span(ch.tail.data(), n));
            ch.tail_pending = false;
        }
        fmt::format_to(it, "SDO block {} end ({} byte{} unused in the last segment",
                       want == Op::BlockDownload ? "download" : "upload", fi.unused,
                       fi.unused == 1 ? "" : "s");
        if (ch.crc) {
            const bool ok = fi.crc_value == ch.crc_value;
            fmt::format_to(it, ", CRC 0x{:04X} {}", fi.crc_value,
                           ok ? "ok" : fmt::format("mismatch: data gives 0x{:04X}", ch.crc_value));
        }
        out.push_back(')');
        ch.end_seen = true;
        return none;
    }
    case FrameKind::BlockDownloadEndResponse:
    case FrameKind::BlockUploadEndResponse: {
        const Op want =
            fi.kind == FrameKind::BlockDownloadEndResponse ? Op::BlockDownload : Op::BlockUpload;
        if (ch.op != want) {
            return unexpected();
        }
        return complete(node, ch, ts, SdoMode::Block, out);
    }
    }
    return unexpected();
}

void SdoTracker::stall_text(NodeId node, const Channel& ch, std::string& text) const {
    fmt::memory_buffer b;
    static constexpr std::string_view kOps[] = {"", "download", "upload", "block download",
                                                "block upload"};
    fmt::format_to(std::back_inserter(b), "node {} SDO {} ", node, kOps[static_cast<int>(ch.op)]);
    object_name(b, node, ch.index, ch.subindex);
    text.assign(b.data(), b.size());
}

void SdoTracker::check_timeouts(std::int64_t now_ns, std::vector<SdoStall>& stalls,
                                std::uint8_t clock) {
    if (open_ == 0) {
        return;
    }
    for (std::size_t n = 0; n < channels_.size(); ++n) {
        Channel& ch = channels_[n];
        if (ch.op == Op::None || !ch.clocked || ch.clock != clock ||
            now_ns - ch.last <= timeout_ns_) {
            continue;
        }
        if (ch.short_response) { // already reported with the too-short response
            ch.op = Op::None;
            --open_;
            continue;
        }
        SdoStall s;
        s.node = static_cast<NodeId>(n);
        s.ts_ns = ch.last + timeout_ns_;
        stall_text(s.node, ch, s.text);
        s.text += ch.client_spoke_last
                      ? fmt::format(": no response within {:.0f} ms (timeout)", to_ms(timeout_ns_))
                      : fmt::format(": client did not continue within {:.0f} ms (abandoned)",
                                    to_ms(timeout_ns_));
        stalls.push_back(std::move(s));
        ch.op = Op::None;
        --open_;
    }
}

void SdoTracker::restart_clocks(std::int64_t now_ns, std::uint8_t clock) {
    for (Channel& ch : channels_) {
        if (ch.op != Op::None && ch.clocked && ch.clock == clock) {
            ch.started_timed = false; // a duration across the step would measure nothing
            ch.last = std::min(ch.last, now_ns);
        }
    }
}

void SdoTracker::finish(std::vector<SdoStall>& stalls) {
    for (std::size_t n = 0; n < channels_.size(); ++n) {
        Channel& ch = channels_[n];
        if (ch.op == Op::None) {
            continue;
        }
        if (ch.short_response) { // already reported with the too-short response
            ch.op = Op::None;
            --open_;
            continue;
        }
        SdoStall s;
        s.node = static_cast<NodeId>(n);
        s.ts_ns = ch.last;
        s.timed = ch.clocked;
        stall_text(s.node, ch, s.text);
        s.text += ch.client_spoke_last ? ": no response before the end of the trace"
                                       : ": unfinished at the end of the trace";
        stalls.push_back(std::move(s));
        ch.op = Op::None;
        --open_;
    }
}

} // namespace codrive::dump
