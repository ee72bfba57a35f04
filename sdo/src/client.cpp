// SPDX-License-Identifier: Apache-2.0
// SDO client state machine: expedited, segmented and block upload/download (CiA 301 §7.2.4.3).
#include "client_transfer.hpp"

#include <codrive/sdo/client.hpp>
#include <codrive/sdo/protocol.hpp>

#include <algorithm>
#include <array>
#include <fmt/format.h>
#include <span>

namespace codrive::sdo {

using detail::BlockReceiver;
using detail::BlockSender;
using detail::ClientState;

namespace {

/// Transfers failing inside start() in one start_next() call before the rest is deferred to
/// the next tick (bounds the work of one call when a callback retries during bus-off).
constexpr int kMaxFailedStartsPerCall = 16;
/// cancel_all() also ends what its callbacks submit, up to this many: a callback that submits
/// again on every failure would otherwise keep it busy forever.
constexpr std::size_t kMaxResubmitsPerCancelAll = 64;

std::string bytes_of(std::size_t done, std::optional<std::size_t> total) {
    return total ? fmt::format("{} of {} bytes", done, *total) : fmt::format("{} bytes", done);
}

FrameKind expected_kind(ClientState s) {
    switch (s) {
    case ClientState::InitiateUpload:
        return FrameKind::InitiateUploadResponse;
    case ClientState::UploadSegment:
        return FrameKind::UploadSegmentResponse;
    case ClientState::InitiateDownload:
        return FrameKind::InitiateDownloadResponse;
    case ClientState::DownloadSegment:
        return FrameKind::DownloadSegmentResponse;
    case ClientState::BlockDownloadInitiate:
        return FrameKind::BlockDownloadInitiateResponse;
    case ClientState::BlockDownloadAck:
        return FrameKind::BlockDownloadAck;
    case ClientState::BlockDownloadEnd:
        return FrameKind::BlockDownloadEndResponse;
    case ClientState::BlockUploadInitiate:
        return FrameKind::BlockUploadInitiateResponse;
    case ClientState::BlockUploadData:
        return FrameKind::BlockSegment;
    case ClientState::BlockUploadEnd:
        return FrameKind::BlockUploadEndRequest;
    case ClientState::Queued:
        break;
    }
    return FrameKind::Invalid;
}

/// The states the shared expedited/segmented machine runs (SdoClientMachine).
bool machine_state(ClientState s) {
    return s == ClientState::InitiateUpload || s == ClientState::UploadSegment ||
           s == ClientState::InitiateDownload || s == ClientState::DownloadSegment;
}

bool initiate_state(ClientState s) {
    return s == ClientState::InitiateUpload || s == ClientState::InitiateDownload ||
           s == ClientState::BlockDownloadInitiate || s == ClientState::BlockUploadInitiate;
}

/// Marks the time of the frame or tick being handled, for the duration of the handler.
class DispatchScope {
public:
    DispatchScope(TimePoint& slot, TimePoint now) : slot_(slot), saved_(slot) { slot_ = now; }
    ~DispatchScope() { slot_ = saved_; }
    DispatchScope(const DispatchScope&) = delete;
    DispatchScope& operator=(const DispatchScope&) = delete;

private:
    TimePoint& slot_;
    TimePoint saved_;
};

} // namespace

namespace detail {

bool ClientTransfer::begin(std::optional<std::size_t> size) {
    if (size && !sink.write) {
        buffer.reserve(std::min(*size, kMaxUploadReserve));
    }
    return !sink.begin || sink.begin(size);
}

bool ClientTransfer::write(std::span<const std::uint8_t> data) {
    if (sink.write) {
        return data.empty() || sink.write(data);
    }
    buffer.insert(buffer.end(), data.begin(), data.end());
    return true;
}

bool ClientTransfer::read(std::span<std::uint8_t> out) {
    return out.empty() || (source.read && source.read(out));
}

SdoError size_mismatch(NodeId node, std::uint16_t index, std::uint8_t subindex, std::size_t got,
                       std::size_t want) {
    SdoError e;
    e.node = node;
    e.index = index;
    e.subindex = subindex;
    e.direction = Direction::Upload;
    e.cause = make_error_code(SdoErrc::SizeMismatch);
    e.detail = fmt::format("object has {} bytes, the requested type {}", got, want);
    return e;
}
} // namespace detail

SdoClient::SdoClient(ICanBus& bus, const IClock& clock, ClientConfig config)
    : bus_(bus), clock_(clock), config_(config),
      request_id_(config.request_id != 0 ? config.request_id : cob::sdo_rx(config.node)),
      response_id_(config.response_id != 0 ? config.response_id : cob::sdo_tx(config.node)) {}

SdoClient::~SdoClient() = default;

bool SdoClient::busy() const {
    return active_ != nullptr || !queue_.empty();
}

TransferId SdoClient::upload(std::uint16_t index, std::uint8_t subindex, UploadCallback done,
                             TransferOptions options) {
    auto t = std::make_unique<Transfer>();
    t->direction = Direction::Upload;
    t->index = index;
    t->subindex = subindex;
    t->options = std::move(options);
    t->on_upload = std::move(done);
    return enqueue(std::move(t));
}

TransferId SdoClient::upload(std::uint16_t index, std::uint8_t subindex, UploadSink sink,
                             DoneCallback done, TransferOptions options) {
    auto t = std::make_unique<Transfer>();
    t->direction = Direction::Upload;
    t->index = index;
    t->subindex = subindex;
    t->options = std::move(options);
    t->sink = std::move(sink);
    t->on_done = std::move(done);
    return enqueue(std::move(t));
}

TransferId SdoClient::download(std::uint16_t index, std::uint8_t subindex, Bytes data,
                               DoneCallback done, TransferOptions options) {
    return download(index, subindex, bytes_source(std::move(data)), std::move(done),
                    std::move(options));
}

TransferId SdoClient::download(std::uint16_t index, std::uint8_t subindex, DownloadSource source,
                               DoneCallback done, TransferOptions options) {
    auto t = std::make_unique<Transfer>();
    t->direction = Direction::Download;
    t->index = index;
    t->subindex = subindex;
    t->options = std::move(options);
    t->source = std::move(source);
    t->total = t->source.size;
    t->on_done = std::move(done);
    return enqueue(std::move(t));
}

TransferId SdoClient::enqueue(std::unique_ptr<Transfer> t) {
    t->id = next_id_++;
    t->timeout = t->options.timeout.value_or(config_.timeout);
    t->retries_left = t->options.retries.value_or(config_.retries);
    const TransferId id = t->id;
    queue_.push_back(std::move(t));
    if (!active_ && !in_callback_) {
        start_next(clock_.now());
    }
    return id;
}

bool SdoClient::cancel(TransferId id) {
    if (active_ && active_->id == id) {
        cancel_running("cancelled by the application");
        return true;
    }
    const auto it =
        std::find_if(queue_.begin(), queue_.end(), [id](const auto& t) { return t->id == id; });
    if (it == queue_.end()) {
        return false;
    }
    std::unique_ptr<Transfer> t = std::move(*it);
    queue_.erase(it);
    end_queued(std::move(t), make_error_code(SdoErrc::Cancelled), "cancelled before it started");
    return true;
}

void SdoClient::cancel_running(std::string detail) {
    (void)send(make_abort(active_->index, active_->subindex,
                          static_cast<std::uint32_t>(SdoAbort::General)));
    fail(make_error_code(SdoErrc::Cancelled), std::move(detail));
}

void SdoClient::end_queued(std::unique_ptr<Transfer> t, std::error_code cause, std::string detail) {
    SdoError e = make_error(*t, cause, std::move(detail), AbortOrigin::None);
    ++stats_.failed;
    if (t->on_upload) {
        t->on_upload(tl::unexpected(std::move(e)));
    } else if (t->on_done) {
        t->on_done(tl::unexpected(std::move(e)));
    }
}

std::size_t SdoClient::cancel_all(std::string_view why) {
    // start_next() does nothing while draining_ is set: the running transfer's end starts no
    // queued one (whose request would go out only to be aborted), and a callback that submits
    // again only queues. The loop ends what those callbacks queue too, within a bound.
    const bool was_draining = std::exchange(draining_, true);
    const std::size_t limit = queue_.size() + (active_ ? 1U : 0U) + kMaxResubmitsPerCancelAll;
    std::size_t ended = 0;
    while ((active_ || !queue_.empty()) && ended < limit) {
        if (active_) {
            cancel_running(std::string(why));
        } else {
            std::unique_ptr<Transfer> t = std::move(queue_.front());
            queue_.pop_front();
            end_queued(std::move(t), make_error_code(SdoErrc::Cancelled), std::string(why));
        }
        ++ended;
    }
    draining_ = was_draining;
    // Past the bound, what a callback keeps submitting starts at the next on_tick().
    deferred_start_ = !queue_.empty();
    reschedule();
    if (deferred_start_) {
        deadline_ = std::min(deadline_, clock_.now());
    }
    return ended;
}

void SdoClient::start_next(TimePoint now) {
    // Iterative, never nested: a transfer that fails inside start() (the bus refuses the
    // request, e.g. bus-off) completes through finish(), whose callback may submit again, and
    // finish() calls start_next() again. The outer call drains the queue; the inner returns.
    if (draining_) {
        return;
    }
    draining_ = true;
    int failed_at_start = 0;
    while (!active_ && !queue_.empty() && !in_callback_) {
        if (failed_at_start == kMaxFailedStartsPerCall) {
            // A callback that retries at once while every send fails would otherwise loop
            // here forever: the rest waits for the next on_tick().
            deferred_start_ = true;
            deadline_ = std::min(deadline_, now);
            break;
        }
        active_ = std::move(queue_.front());
        queue_.pop_front();
        start(*active_, now);
        failed_at_start += active_ ? 0 : 1;
    }
    draining_ = false;
}

bool SdoClient::send(const Payload& payload) {
    return bus_.send(Frame::make(request_id_, payload)).has_value();
}

void SdoClient::arm(TimePoint now) {
    // The timer only ever moves earlier here; on_tick() pushes it out again. A stream of
    // requests therefore re-arms the event loop's timer about once per timeout, not per frame.
    active_->activity = now;
    deadline_ = std::min(deadline_, now + active_->timeout);
}

void SdoClient::start(Transfer& t, TimePoint now) {
    const bool block = t.options.mode == Mode::Block;
    // Expedited and segmented transfers run in the shared machine with CAN's framing; a block
    // upload keeps one ready for the server's switch to them (protocol switch threshold).
    t.machine = SdoClientMachine(t, SdoFraming{}, t.index, t.subindex);
    if (t.direction == Direction::Upload) {
        (void)t.machine.begin_upload();
        if (block) {
            t.protocol = Protocol::Block;
            t.state = ClientState::BlockUploadInitiate;
            t.block_size = std::clamp<std::uint8_t>(t.options.block_size, 1, kMaxBlockSize);
            t.initiate = make_block_upload_initiate(t.index, t.subindex, t.options.crc,
                                                    t.block_size, t.options.pst);
        } else {
            t.state = ClientState::InitiateUpload;
            t.initiate = t.machine.request();
        }
    } else if (block) {
        const std::size_t size = t.source.size;
        if (auto too_large = download_too_large(size)) {
            fail(make_error_code(SdoErrc::TooLarge), std::move(*too_large));
            return;
        }
        t.protocol = Protocol::Block;
        t.state = ClientState::BlockDownloadInitiate;
        t.initiate = make_block_download_initiate(t.index, t.subindex, t.options.crc,
                                                  static_cast<std::uint32_t>(size));
    } else {
        const auto step = t.machine.begin_download(t.source.size, t.options.mode == Mode::Auto);
        sync(t);
        if (step == SdoClientMachine::Step::Failed) {
            fail_with(t.machine.failure());
            return;
        }
        t.state = ClientState::InitiateDownload;
        t.initiate = t.machine.request();
    }
    if (!send(t.initiate)) {
        fail(make_error_code(SdoErrc::SendFailed), "initiate request refused by the bus");
        return;
    }
    arm(now);
}

bool SdoClient::on_frame(const Frame& frame, TimePoint now) {
    const DispatchScope scope(dispatch_now_, now);
    if (config_.watch_boot_up && frame.id == cob::heartbeat(config_.node) && frame.len == 1 &&
        frame.data[0] == 0 && !frame.rtr()) {
        if (active_) {
            // CiA 301 §7.2.8.3.2.1: boot-up means the node reset; its SDO server forgot us.
            const auto& t = *active_;
            fail(make_error_code(SdoErrc::NodeRebooted),
                 fmt::format("boot-up message received after {}", bytes_of(t.done, t.total)));
        }
        return false;
    }
    if (frame.id != response_id_ || frame.extended() || frame.rtr() || frame.error()) {
        ++stats_.frames_ignored;
        return false;
    }
    if (!active_ || active_->state == ClientState::Queued) {
        ++stats_.unexpected_responses;
        return true;
    }
    if (is_repeat(frame)) {
        // Ignored without re-arming the timeout: a stream of repeats cannot keep a dead
        // transfer alive.
        ++stats_.stale_responses;
        return true;
    }
    if (active_->state == ClientState::BlockUploadData) {
        handle_block_upload_segment(frame, now);
    } else {
        handle_response(frame, now);
    }
    return true;
}

void SdoClient::remember_response(const Frame& frame) {
    Transfer& t = *active_;
    std::copy_n(frame.data.begin(), kFrameLen, t.last_response.begin());
    t.have_last_response = frame.len == kFrameLen;
}

bool SdoClient::is_repeat(const Frame& frame) const {
    const Transfer& t = *active_;
    if (!t.have_last_response || frame.len != kFrameLen ||
        !std::equal(t.last_response.begin(), t.last_response.end(), frame.data.begin())) {
        return false;
    }
    switch (t.state) {
    case ClientState::BlockDownloadAck:
        // Two successive sub-block responses may legitimately be identical (same ackseq and
        // blksize): BlockSender::on_ack() decides, knowing whether the server alternates the
        // block size.
        return false;
    case ClientState::BlockUploadData:
        // The segment accepted next may carry the bytes of the previous one (blksize 1, repeated
        // data): only an out-of-sequence copy is a repeat.
        return frame.data[0] != 0x80 && (frame.data[0] & 0x7FU) != t.receiver.next_seqno();
    default:
        return true;
    }
}

bool SdoClient::is_leftover(const FrameInfo& info) {
    Transfer& t = *active_;
    const FrameKind want = expected_kind(t.state);
    if (initiate_state(t.state)) {
        // A block upload the server answers with a normal initiate upload response (protocol
        // switch threshold) is answered all the same.
        const bool upload_switch = t.state == ClientState::BlockUploadInitiate &&
                                   info.kind == FrameKind::InitiateUploadResponse;
        const bool ours = (info.kind == want || upload_switch) && info.index == t.index &&
                          info.subindex == t.subindex;
        if (answers_another_transfer(info.kind, want, true, ours)) {
            // Segments of an earlier block upload the server was still streaming can carry any
            // byte 0, including a reserved command specifier: noted, for on_timeout().
            t.machine.note_stray(info);
            return true;
        }
        return false;
    }
    switch (t.state) {
    case ClientState::BlockDownloadEnd:
        // A sub-block response after the last one was taken: a repeat or a late answer.
        return is_initiate_response(info.kind) || info.kind == FrameKind::BlockDownloadAck;
    case ClientState::BlockUploadEnd:
        // Block segments carry no command specifier: a late or repeated one (they come in
        // bursts) can look like any frame. Only the end request and an abort are answers.
        return info.kind != FrameKind::BlockUploadEndRequest && info.kind != FrameKind::Abort;
    default:
        // Only a response of this protocol in the wrong phase is an error.
        return answers_another_transfer(info.kind, want, false, false);
    }
}

void SdoClient::server_abort(const FrameInfo& info) {
    Transfer& t = *active_;
    // CiA 301 §7.2.4.3.17: an abort carries the multiplexer of the transfer it ends. One for
    // another object is stale (an earlier transfer's, or a rebooted node answering a frame of
    // the transfer that its reset ended) and must not end this transfer.
    if (info.index != t.index || info.subindex != t.subindex) {
        ++stats_.unexpected_responses;
        return;
    }
    (void)t.machine.server_abort(info);
    fail_with(t.machine.failure());
}

bool SdoClient::begin_upload_data(const FrameInfo& info) {
    Transfer& t = *active_;
    if (info.size_indicated) {
        t.total = info.size;
    }
    if (!t.begin(t.total)) {
        abort_and_fail(static_cast<std::uint32_t>(SdoAbort::DataTransfer),
                       "the local data sink refused the size");
        return false;
    }
    return true;
}

void SdoClient::handle_response(const Frame& frame, TimePoint now) {
    Transfer& t = *active_;
    const FrameInfo info = parse_frame(frame.payload(), Sender::Server);
    if (info.kind == FrameKind::Abort) {
        server_abort(info);
        return;
    }
    if (is_leftover(info)) {
        ++stats_.stale_responses;
        return;
    }
    // A block upload the server answered with a normal initiate upload response (protocol
    // switch threshold, CiA 301 §7.2.4.3.13) continues in the machine like any upload.
    const bool upload_switch = t.state == ClientState::BlockUploadInitiate &&
                               info.kind == FrameKind::InitiateUploadResponse;
    if (machine_state(t.state) || upload_switch) {
        remember_response(frame);
        apply(t.machine.on_reply(info), now);
        return;
    }
    if (info.kind != expected_kind(t.state)) {
        abort_and_fail(static_cast<std::uint32_t>(SdoAbort::UnknownCommand),
                       fmt::format("expected {}, received {}", to_string(expected_kind(t.state)),
                                   to_string(info.kind)));
        return;
    }
    remember_response(frame);

    switch (t.state) {
    case ClientState::BlockUploadInitiate:
        t.crc = t.options.crc && info.crc;
        if (!begin_upload_data(info)) {
            return;
        }
        t.receiver.reset(t.block_size);
        t.state = ClientState::BlockUploadData;
        t.flow_frame = make_block_upload_start();
        if (!send(t.flow_frame)) {
            fail(make_error_code(SdoErrc::SendFailed), "start request refused by the bus");
            return;
        }
        // A repeated start is ignored by a server that got the first (codrive's does); sent
        // only on request (ClientConfig::repeat_block_responses).
        if (config_.repeat_block_responses) {
            t.flow_sent = now;
            deadline_ = std::min(deadline_, now + config_.block_gap_timeout);
        }
        arm(now);
        return;

    case ClientState::BlockDownloadInitiate:
        if (info.block_size == 0 || info.block_size > kMaxBlockSize) {
            abort_and_fail(static_cast<std::uint32_t>(SdoAbort::InvalidBlockSize),
                           fmt::format("server asked for block size {}", info.block_size));
            return;
        }
        t.crc = t.options.crc && info.crc;
        t.block_size = info.block_size;
        t.sender.reset(t.source.size);
        send_sub_block(now);
        return;

    case ClientState::BlockDownloadAck: {
        const auto r = t.sender.on_ack(info.seqno, info.block_size);
        if (r == BlockSender::AckResult::Repeat) {
            ++stats_.stale_responses;
            return;
        }
        if (r == BlockSender::AckResult::InvalidSequence) {
            abort_and_fail(static_cast<std::uint32_t>(SdoAbort::InvalidSequence),
                           fmt::format("server acknowledged segment {} of a {}-segment sub-block",
                                       info.seqno, t.sender.segments()));
            return;
        }
        if (r == BlockSender::AckResult::InvalidBlockSize) {
            abort_and_fail(static_cast<std::uint32_t>(SdoAbort::InvalidBlockSize),
                           fmt::format("server asked for block size {}", info.block_size));
            return;
        }
        stats_.retransmitted_segments +=
            static_cast<std::uint64_t>(t.sender.segments() - info.seqno);
        t.done = t.sender.acknowledged();
        report_progress();
        if (r == BlockSender::AckResult::Done) {
            t.state = ClientState::BlockDownloadEnd;
            if (!send(
                    make_block_download_end(t.sender.last_unused(), t.crc ? t.sender.crc() : 0))) {
                fail(make_error_code(SdoErrc::SendFailed), "end request refused by the bus");
                return;
            }
            arm(now);
            return;
        }
        t.block_size = info.block_size;
        send_sub_block(now);
        return;
    }

    case ClientState::BlockDownloadEnd:
        finish({});
        return;

    case ClientState::BlockUploadEnd: {
        auto& rx = t.receiver;
        if (!rx.finish(info.unused,
                       [this](std::span<const std::uint8_t> d) { return deliver(d); })) {
            abort_and_fail(static_cast<std::uint32_t>(SdoAbort::DataTransfer),
                           "the local data sink refused the data");
            return;
        }
        t.done = rx.received();
        if (t.crc && rx.crc() != info.crc_value) {
            abort_and_fail(static_cast<std::uint32_t>(SdoAbort::CrcError),
                           fmt::format("CRC 0x{:04X} received, 0x{:04X} computed over {} bytes",
                                       info.crc_value, rx.crc(), t.done));
            return;
        }
        if (t.total && t.done != *t.total) {
            abort_and_fail(static_cast<std::uint32_t>(SdoAbort::LengthMismatch),
                           fmt::format("server sent {} bytes, announced {}", t.done, *t.total));
            return;
        }
        if (!send(make_block_upload_end_response())) {
            fail(make_error_code(SdoErrc::SendFailed), "end response refused by the bus");
            return;
        }
        report_progress();
        finish({});
        return;
    }

    case ClientState::InitiateUpload:
    case ClientState::UploadSegment:
    case ClientState::InitiateDownload:
    case ClientState::DownloadSegment:
    case ClientState::BlockUploadData:
    case ClientState::Queued:
        break;
    }
}

void SdoClient::handle_block_upload_segment(const Frame& frame, TimePoint now) {
    Transfer& t = *active_;
    const FrameInfo info = parse_frame(frame.payload(), Sender::Server, true);
    if (info.kind == FrameKind::Abort) {
        server_abort(info);
        return;
    }
    using R = BlockReceiver::SegmentResult;
    const auto r =
        t.receiver.on_segment(info, [this](std::span<const std::uint8_t> d) { return deliver(d); });
    if (r != R::Stale) {
        t.flow_sent = kNever; // the sub-block asked for is coming
    }
    switch (r) {
    case R::InvalidSequence:
        abort_and_fail(static_cast<std::uint32_t>(SdoAbort::InvalidSequence),
                       fmt::format("segment with sequence number {} in a sub-block of {}",
                                   info.seqno, t.receiver.block_size()));
        return;
    case R::WriteFailed:
        abort_and_fail(static_cast<std::uint32_t>(SdoAbort::DataTransfer),
                       "the local data sink refused the data");
        return;
    case R::Stale:
        arm(now);
        return;
    case R::Stored:
    case R::Skipped:
        if (r == R::Stored) {
            remember_response(frame);
        }
        t.done = t.receiver.received();
        t.gap_activity = now;
        deadline_ = std::min(deadline_, now + config_.block_gap_timeout);
        arm(now);
        return;
    case R::SubBlockDone:
        remember_response(frame);
        t.done = t.receiver.received();
        report_progress();
        send_block_upload_ack(now);
        return;
    }
}

void SdoClient::send_block_upload_ack(TimePoint now, bool early) {
    Transfer& t = *active_;
    const std::uint8_t ackseq = t.receiver.ackseq();
    const bool complete = t.receiver.complete();
    t.block_size = t.receiver.next_block_size(
        std::clamp<std::uint8_t>(t.options.block_size, 1, kMaxBlockSize));
    t.receiver.start_sub_block(t.block_size, early);
    t.gap_activity = kNever;
    if (complete) {
        t.state = ClientState::BlockUploadEnd;
    }
    t.flow_frame = make_block_upload_ack(ackseq, t.block_size);
    if (!send(t.flow_frame)) {
        fail(make_error_code(SdoErrc::SendFailed), "sub-block response refused by the bus");
        return;
    }
    // Repeating a response is safe only when the server can tell the copy from a new response:
    // successive responses differ when the block size alternates (BlockReceiver::next_block_size).
    const bool alternating = t.options.block_size > 1;
    t.flow_sent = !complete && alternating && config_.repeat_block_responses ? now : kNever;
    if (t.flow_sent != kNever) {
        deadline_ = std::min(deadline_, now + config_.block_gap_timeout);
    }
    arm(now);
}

void SdoClient::send_sub_block(TimePoint now) {
    Transfer& t = *active_;
    if (!t.sender.fill(t.block_size,
                       [this](std::span<std::uint8_t> out) { return read_source(out); })) {
        return;
    }
    t.state = ClientState::BlockDownloadAck;
    // The sub-block (up to 127 segments) goes to the bus in bursts: ICanBus::send_many(), one
    // sendmmsg() per burst on SocketCAN instead of a system call per segment.
    std::array<Frame, 32> burst;
    const unsigned segments = t.sender.segments();
    for (unsigned seq = 1; seq <= segments;) {
        std::size_t k = 0;
        for (; k < burst.size() && seq + k <= segments; ++k) {
            burst[k] =
                Frame::make(request_id_, t.sender.segment(static_cast<std::uint8_t>(seq + k)));
        }
        if (const std::size_t sent = bus_.send_many(std::span<const Frame>(burst.data(), k));
            sent < k) {
            fail(make_error_code(SdoErrc::SendFailed),
                 fmt::format("block segment {} refused by the bus", seq + sent));
            return;
        }
        seq += static_cast<unsigned>(k);
    }
    arm(now);
}

bool SdoClient::deliver(std::span<const std::uint8_t> data) {
    return active_->write(data);
}

bool SdoClient::read_source(std::span<std::uint8_t> out) {
    Transfer& t = *active_;
    if (t.read(out)) {
        return true;
    }
    // Block download (it runs after the initiate request): the server is told the data cannot
    // be supplied (CiA 301 abort 0x08000020).
    (void)send(make_abort(t.index, t.subindex, static_cast<std::uint32_t>(SdoAbort::DataTransfer)));
    fail(make_error_code(SdoErrc::LocalTransferError),
         fmt::format("the data source failed after {}", bytes_of(t.done, t.total)));
    return false;
}

void SdoClient::sync(Transfer& t) {
    t.done = t.machine.done();
    t.total = t.machine.total();
    t.protocol = t.machine.protocol();
}

void SdoClient::apply(SdoClientMachine::Step step, TimePoint now) {
    using Step = SdoClientMachine::Step;
    using Phase = SdoClientMachine::Phase;
    Transfer& t = *active_;
    sync(t);
    if (t.machine.progressed()) {
        report_progress();
    }
    switch (step) {
    case Step::Send: {
        const bool upload = t.machine.phase() == Phase::UploadSegment;
        t.state = upload ? ClientState::UploadSegment : ClientState::DownloadSegment;
        if (!send(t.machine.request())) {
            fail(make_error_code(SdoErrc::SendFailed),
                 upload ? "segment request refused by the bus" : "segment refused by the bus");
            return;
        }
        arm(now);
        return;
    }
    case Step::Done:
        finish({});
        return;
    case Step::Failed:
        fail_with(t.machine.failure());
        return;
    case Step::Ignore:
        ++stats_.stale_responses;
        return;
    }
}

void SdoClient::fail_with(const SdoClientMachine::Failure& f) {
    if (f.abort) {
        (void)send(active_->machine.request());
    }
    fail(f.cause, f.detail, f.origin);
}

void SdoClient::report_progress() {
    const Transfer& t = *active_;
    if (t.options.progress) {
        t.options.progress(t.done, t.total);
    }
}

TimePoint SdoClient::next_deadline() const {
    return deadline_;
}

void SdoClient::reschedule() {
    if (!active_) {
        deadline_ = deferred_start_ ? deadline_ : kNever;
        return;
    }
    const Transfer& t = *active_;
    deadline_ = t.activity + t.timeout;
    if (t.gap_activity != kNever) {
        deadline_ = std::min(deadline_, t.gap_activity + config_.block_gap_timeout);
    }
    if (t.flow_sent != kNever) {
        deadline_ = std::min(deadline_, t.flow_sent + config_.block_gap_timeout);
    }
}

void SdoClient::on_tick(TimePoint now) {
    const DispatchScope scope(dispatch_now_, now);
    if (deferred_start_ && !active_) {
        deferred_start_ = false;
        start_next(now);
    }
    if (active_) {
        Transfer& t = *active_;
        if (t.state == ClientState::BlockUploadData && t.gap_activity != kNever &&
            now >= t.gap_activity + config_.block_gap_timeout) {
            // A sub-block stalled (its last segment was lost): acknowledge what arrived in
            // sequence so the server repeats the rest (CiA 301 §7.2.4.3.14).
            ++stats_.early_acks;
            send_block_upload_ack(now, /*early=*/true);
        } else if (t.state == ClientState::BlockUploadData && t.flow_sent != kNever &&
                   now >= t.flow_sent + config_.block_gap_timeout && now < t.activity + t.timeout) {
            // Nothing of the sub-block came: the response (or start) was probably lost.
            ++stats_.acks_repeated;
            t.flow_sent = now;
            (void)send(t.flow_frame);
        } else if (now >= t.activity + t.timeout) {
            on_timeout(now);
        }
    }
    reschedule();
}

void SdoClient::on_timeout(TimePoint now) {
    Transfer& t = *active_;
    // Any unanswered initiate request may be repeated: nothing has been transferred yet, and a
    // server that did get the first one restarts the same transfer (its repeated response is
    // ignored as a repeat, see is_repeat()).
    if (initiate_state(t.state) && t.retries_left > 0) {
        --t.retries_left;
        ++stats_.retries;
        if (send(t.initiate)) {
            arm(now);
            return;
        }
    }
    if (initiate_state(t.state) && t.machine.unanswered() == SdoClientMachine::Step::Failed) {
        // Only answers of other transfers came: the machine says which.
        fail_with(t.machine.failure());
        return;
    }
    std::string phase;
    switch (t.state) {
    case ClientState::InitiateUpload:
    case ClientState::InitiateDownload:
    case ClientState::BlockDownloadInitiate:
    case ClientState::BlockUploadInitiate:
        phase = "no response to initiate request";
        break;
    case ClientState::UploadSegment:
        phase = fmt::format("no response to segment request after {}", bytes_of(t.done, t.total));
        break;
    case ClientState::DownloadSegment:
        phase = fmt::format("no response to segment after {}", bytes_of(t.done, t.total));
        break;
    case ClientState::BlockDownloadAck:
        phase = fmt::format("no sub-block response after {}", bytes_of(t.done, t.total));
        break;
    case ClientState::BlockDownloadEnd:
        phase = "no response to end request";
        break;
    case ClientState::BlockUploadData:
        phase = fmt::format("no block segment after {}", bytes_of(t.done, t.total));
        break;
    case ClientState::BlockUploadEnd:
        phase = "no end request after the last segment";
        break;
    case ClientState::Queued:
        break;
    }
    (void)send(make_abort(t.index, t.subindex, static_cast<std::uint32_t>(SdoAbort::Timeout)));
    fail(make_error_code(SdoErrc::Timeout), std::move(phase));
}

SdoError SdoClient::make_error(const Transfer& t, std::error_code cause, std::string detail,
                               AbortOrigin origin) const {
    SdoError e;
    e.node = config_.node;
    e.index = t.index;
    e.subindex = t.subindex;
    e.direction = t.direction;
    e.protocol = t.protocol;
    e.cause = cause;
    e.origin = origin;
    e.timeout = t.timeout;
    e.detail = std::move(detail);
    return e;
}

void SdoClient::abort_and_fail(std::uint32_t code, std::string detail) {
    Transfer& t = *active_;
    (void)t.machine.abort(code, std::error_code(static_cast<int>(code), sdo_abort_category()),
                          std::move(detail));
    fail_with(t.machine.failure());
}

void SdoClient::fail(std::error_code cause, std::string detail, AbortOrigin origin) {
    finish(tl::unexpected(make_error(*active_, cause, std::move(detail), origin)));
}

void SdoClient::finish(SdoResult<void> outcome) {
    std::unique_ptr<Transfer> t = std::move(active_);
    if (outcome) {
        ++stats_.completed;
    } else {
        ++stats_.failed;
    }
    in_callback_ = true;
    if (t->on_upload) {
        if (outcome) {
            t->on_upload(std::move(t->buffer));
        } else {
            t->on_upload(tl::unexpected(std::move(outcome.error())));
        }
    } else if (t->on_done) {
        t->on_done(std::move(outcome));
    }
    in_callback_ = false;
    // Inside on_frame()/on_tick() the dispatch time is current enough; reading the clock again
    // costs a system call per request on some targets.
    start_next(dispatch_now_ != kNever ? dispatch_now_ : clock_.now());
}

} // namespace codrive::sdo
