// SPDX-License-Identifier: Apache-2.0
// The one SDO client transfer machine (expedited and segmented, CiA 301 §7.2.4.3) shared by the
// CAN client and CoE (ETG.1000.6 §5.6.2: the CoE SDO payload is the CiA 301 frame plus data).
#include <codrive/sdo/client_machine.hpp>

#include <algorithm>
#include <array>
#include <fmt/format.h>

namespace codrive::sdo {
namespace {

constexpr std::size_t kMaxSdoSize = 0xFFFFFFFFU; // the SDO size field is 32 bits

std::string mux(std::uint16_t index, std::uint8_t subindex) {
    return fmt::format("0x{:04X}:{:02X}", index, subindex);
}

std::error_code abort_error(std::uint32_t code) {
    return {static_cast<int>(code), sdo_abort_category()};
}

FrameKind expected_reply(SdoClientMachine::Phase phase) {
    switch (phase) {
    case SdoClientMachine::Phase::InitiateUpload:
        return FrameKind::InitiateUploadResponse;
    case SdoClientMachine::Phase::UploadSegment:
        return FrameKind::UploadSegmentResponse;
    case SdoClientMachine::Phase::InitiateDownload:
        return FrameKind::InitiateDownloadResponse;
    case SdoClientMachine::Phase::DownloadSegment:
        return FrameKind::DownloadSegmentResponse;
    case SdoClientMachine::Phase::Idle:
    case SdoClientMachine::Phase::Finished:
        break;
    }
    return FrameKind::Invalid;
}

} // namespace

int response_family(FrameKind kind) {
    switch (kind) {
    case FrameKind::InitiateUploadResponse:
    case FrameKind::UploadSegmentResponse:
        return 1;
    case FrameKind::InitiateDownloadResponse:
    case FrameKind::DownloadSegmentResponse:
        return 2;
    case FrameKind::BlockDownloadInitiateResponse:
    case FrameKind::BlockDownloadAck:
    case FrameKind::BlockDownloadEndResponse:
        return 3;
    case FrameKind::BlockUploadInitiateResponse:
    case FrameKind::BlockUploadEndRequest:
    case FrameKind::BlockSegment:
        return 4;
    default:
        return 0;
    }
}

bool answers_another_transfer(FrameKind got, FrameKind want, bool initiate_phase, bool ours) {
    if (initiate_phase) {
        return !ours;
    }
    if (got == FrameKind::Invalid) {
        return false;
    }
    return is_initiate_response(got) || response_family(got) != response_family(want);
}

std::optional<std::string> download_too_large(std::size_t size) {
    if (size <= kMaxSdoSize) {
        return std::nullopt;
    }
    return fmt::format("{} bytes, the SDO size field holds at most {}", size, kMaxSdoSize);
}

std::string SdoClientMachine::position() const {
    return total_ ? fmt::format("{} of {} bytes", done_, *total_) : fmt::format("{} bytes", done_);
}

void SdoClientMachine::set_request(const Payload& p) {
    request_ = p;
    extra_.clear();
}

SdoClientMachine::Step SdoClientMachine::fail(std::error_code cause, std::string detail,
                                              AbortOrigin origin,
                                              std::optional<std::uint32_t> abort_code) {
    failure_ = Failure{cause, origin, std::move(detail), abort_code};
    if (abort_code) {
        set_request(make_abort(index_, subindex_, *abort_code));
    }
    phase_ = Phase::Finished;
    return Step::Failed;
}

SdoClientMachine::Step SdoClientMachine::abort(std::uint32_t code, std::error_code cause,
                                               std::string detail, AbortOrigin origin) {
    return fail(cause, std::move(detail), origin, code);
}

SdoClientMachine::Step SdoClientMachine::client_abort(SdoAbort code, std::string detail) {
    const auto value = static_cast<std::uint32_t>(code);
    return fail(abort_error(value), std::move(detail), AbortOrigin::Client, value);
}

SdoClientMachine::Step SdoClientMachine::wrong_object(std::uint16_t index, std::uint8_t subindex) {
    // CiA 301 leaves open what a client does when the server answers for another object: the
    // two disagree about the transfer, so it cannot continue.
    return fail(make_error_code(SdoErrc::WrongObject),
                fmt::format("server answered for {} instead of {}", mux(index, subindex),
                            mux(index_, subindex_)),
                AbortOrigin::Client, static_cast<std::uint32_t>(SdoAbort::General));
}

void SdoClientMachine::note_stray(const FrameInfo& reply) {
    stray_invalid_ = stray_invalid_ || reply.kind == FrameKind::Invalid;
    if (!stray_object_ && is_initiate_response(reply.kind) && !names_our_object(reply)) {
        stray_object_.emplace(reply.index, reply.subindex);
    }
}

SdoClientMachine::Step SdoClientMachine::unanswered() {
    if (stray_object_) {
        return wrong_object(stray_object_->first, stray_object_->second);
    }
    if (stray_invalid_) {
        return client_abort(SdoAbort::UnknownCommand,
                            "no valid response to the initiate request; frames with a reserved "
                            "command specifier came instead");
    }
    return Step::Ignore;
}

SdoClientMachine::Step SdoClientMachine::begin_upload() {
    direction_ = Direction::Upload;
    Payload p = make_initiate_upload(index_, subindex_);
    if (framing_.complete_access) {
        p[0] = static_cast<std::uint8_t>(p[0] | kCompleteAccessBit);
    }
    set_request(p);
    phase_ = Phase::InitiateUpload;
    return Step::Send;
}

SdoClientMachine::Step SdoClientMachine::begin_download(std::size_t size, bool expedited) {
    direction_ = Direction::Download;
    total_ = size;
    if (auto too_large = download_too_large(size)) {
        return fail(make_error_code(SdoErrc::TooLarge), std::move(*too_large), AbortOrigin::None,
                    std::nullopt);
    }
    const std::uint8_t ca = framing_.complete_access ? kCompleteAccessBit : 0;
    if (expedited && size >= 1 && size <= kExpeditedMax) {
        std::array<std::uint8_t, kExpeditedMax> data{};
        const auto bytes = std::span<std::uint8_t>(data.data(), size);
        if (!data_->read(bytes)) {
            return source_failed();
        }
        protocol_ = Protocol::Expedited;
        Payload p = make_initiate_download_expedited(index_, subindex_, bytes);
        p[0] = static_cast<std::uint8_t>(p[0] | ca);
        set_request(p);
        done_ = size;
    } else {
        protocol_ = Protocol::Segmented;
        Payload p =
            make_initiate_download_segmented(index_, subindex_, static_cast<std::uint32_t>(size));
        p[0] = static_cast<std::uint8_t>(p[0] | ca);
        set_request(p);
        // CoE normal transfer (ETG.1000.6 §5.6.2.2): data follows the size in the same message.
        extra_.resize(std::min(framing_.initiate_room, size));
        if (!extra_.empty() && !data_->read(extra_)) {
            return source_failed();
        }
        done_ = extra_.size();
    }
    phase_ = Phase::InitiateDownload;
    return Step::Send;
}

SdoClientMachine::Step SdoClientMachine::source_failed() {
    // Once a request went out, the server is told the data cannot be supplied (CiA 301 abort
    // 0x08000020); before, there is nobody to tell.
    std::optional<std::uint32_t> code;
    if (phase_ != Phase::Idle) {
        code = static_cast<std::uint32_t>(SdoAbort::DataTransfer);
    }
    return fail(make_error_code(SdoErrc::LocalTransferError),
                fmt::format("the data source failed after {}", position()), AbortOrigin::None,
                code);
}

SdoClientMachine::Step SdoClientMachine::server_abort(const FrameInfo& reply) {
    if (reply.abort_code == 0) {
        // Code 0 is no abort code; an error_code with value 0 would read as success.
        return fail(make_error_code(SdoErrc::ProtocolError),
                    "the server sent an abort frame with code 0x00000000, which is not an "
                    "abort code",
                    AbortOrigin::Server, std::nullopt);
    }
    return fail(abort_error(reply.abort_code), {}, AbortOrigin::Server, std::nullopt);
}

bool SdoClientMachine::names_our_object(const FrameInfo& reply) const {
    // Complete access answers with the sub-index the access starts from (ETG.1000.6 §5.6.2.1.1).
    return reply.index == index_ && (framing_.complete_access || reply.subindex == subindex_);
}

SdoClientMachine::Step SdoClientMachine::on_reply(const FrameInfo& reply,
                                                  std::span<const std::uint8_t> extra) {
    progressed_ = false;
    if (phase_ == Phase::Idle || phase_ == Phase::Finished) {
        return Step::Ignore;
    }
    if (reply.kind == FrameKind::Abort) {
        // CiA 301 §7.2.4.3.17: an abort carries the multiplexer of the transfer it ends; one for
        // another object ends an earlier transfer (on CoE: one that timed out, its abort still
        // waiting in the slave's mailbox).
        return names_our_object(reply) ? server_abort(reply) : Step::Ignore;
    }
    const FrameKind want = expected_reply(phase_);
    const bool initiate = phase_ == Phase::InitiateUpload || phase_ == Phase::InitiateDownload;
    if (answers_another_transfer(reply.kind, want, initiate,
                                 reply.kind == want && names_our_object(reply))) {
        note_stray(reply);
        return Step::Ignore;
    }
    if (reply.kind != want) {
        return client_abort(
            SdoAbort::UnknownCommand,
            fmt::format("expected {}, received {}", to_string(want), to_string(reply.kind)));
    }
    switch (phase_) {
    case Phase::InitiateUpload:
        return on_initiate_upload(reply, extra);
    case Phase::UploadSegment:
        return on_upload_segment(reply, extra);
    case Phase::InitiateDownload:
    case Phase::DownloadSegment:
        return on_download_response(reply);
    case Phase::Idle:
    case Phase::Finished:
        break;
    }
    return Step::Ignore;
}

SdoClientMachine::Step SdoClientMachine::on_initiate_upload(const FrameInfo& reply,
                                                            std::span<const std::uint8_t> extra) {
    if (reply.expedited) {
        protocol_ = Protocol::Expedited;
        const std::span<const std::uint8_t> data(reply.data.data(), reply.data_len);
        if (!data_->begin(data.size()) || !data_->write(data)) {
            return client_abort(SdoAbort::DataTransfer, "the local data sink refused the data");
        }
        done_ = data.size();
        phase_ = Phase::Finished;
        return Step::Done;
    }
    protocol_ = Protocol::Segmented;
    if (reply.size_indicated) {
        total_ = reply.size;
    }
    if (!data_->begin(total_)) {
        return client_abort(SdoAbort::DataTransfer, "the local data sink refused the size");
    }
    if (!extra.empty()) {
        // CoE normal transfer (ETG.1000.6 §5.6.2.5): data follows the size in the same message;
        // bytes past the indicated size are mailbox padding.
        const std::size_t n = total_ ? std::min(extra.size(), *total_) : extra.size();
        if (!data_->write(extra.first(n))) {
            return client_abort(SdoAbort::DataTransfer, "the local data sink refused the data");
        }
        done_ = n;
        progressed_ = true;
        if (total_ && done_ == *total_) {
            phase_ = Phase::Finished;
            return Step::Done;
        }
    }
    toggle_ = false;
    set_request(make_upload_segment_request(toggle_));
    phase_ = Phase::UploadSegment;
    return Step::Send;
}

SdoClientMachine::Step SdoClientMachine::on_upload_segment(const FrameInfo& reply,
                                                           std::span<const std::uint8_t> extra) {
    if (reply.toggle != toggle_) {
        return client_abort(SdoAbort::ToggleBit,
                            fmt::format("segment after {} had toggle {}, expected {}", position(),
                                        reply.toggle ? 1 : 0, toggle_ ? 1 : 0));
    }
    // A CoE segment longer than 7 bytes carries n = 0 and the rest after the frame (ETG.1000.6
    // §5.6.2.6); otherwise n tells the unused bytes of the 7.
    const std::size_t in_frame = extra.empty() ? reply.data_len : kSegmentData;
    const std::size_t n = in_frame + extra.size();
    if (n == 0 && !reply.last) {
        // Progress guard: an empty segment that is not the last would make the client ask for
        // the next one forever.
        return client_abort(SdoAbort::General,
                            fmt::format("empty segment that is not the last after {}; the "
                                        "transfer would never end",
                                        position()));
    }
    if (total_ && done_ + n > *total_) {
        return client_abort(
            SdoAbort::LengthTooHigh,
            fmt::format("server sent more than the {} bytes it announced", *total_));
    }
    if (!data_->write(std::span<const std::uint8_t>(reply.data.data(), in_frame)) ||
        (!extra.empty() && !data_->write(extra))) {
        return client_abort(SdoAbort::DataTransfer, "the local data sink refused the data");
    }
    done_ += n;
    progressed_ = true;
    if (reply.last) {
        if (total_ && done_ != *total_) {
            return client_abort(SdoAbort::LengthTooLow,
                                fmt::format("server sent {} bytes, announced {}", done_, *total_));
        }
        phase_ = Phase::Finished;
        return Step::Done;
    }
    toggle_ = !toggle_;
    set_request(make_upload_segment_request(toggle_));
    return Step::Send;
}

SdoClientMachine::Step SdoClientMachine::on_download_response(const FrameInfo& reply) {
    if (phase_ == Phase::InitiateDownload) {
        // CAN's segmented protocol always has a segment, even for 0 bytes; a CoE normal
        // transfer may have carried everything in the initiate request.
        const bool all_sent = framing_.initiate_room > 0 && total_ && done_ == *total_;
        if (protocol_ == Protocol::Expedited || all_sent) {
            phase_ = Phase::Finished;
            return Step::Done;
        }
        toggle_ = false;
        return next_download_segment();
    }
    if (reply.toggle != toggle_) {
        return client_abort(SdoAbort::ToggleBit,
                            fmt::format("segment response after {} had toggle {}, expected {}",
                                        position(), reply.toggle ? 1 : 0, toggle_ ? 1 : 0));
    }
    progressed_ = true;
    if (last_sent_) {
        phase_ = Phase::Finished;
        return Step::Done;
    }
    toggle_ = !toggle_;
    return next_download_segment();
}

SdoClientMachine::Step SdoClientMachine::next_download_segment() {
    const std::size_t total = total_.value_or(0);
    const std::size_t n = std::min(std::max<std::size_t>(framing_.segment_room, 1), total - done_);
    const std::size_t in_frame = std::min(n, kSegmentData);
    std::array<std::uint8_t, kSegmentData> data{};
    if (!data_->read(std::span<std::uint8_t>(data.data(), in_frame))) {
        return source_failed();
    }
    // A CoE segment longer than 7 bytes carries the rest after the frame (ETG.1000.6 §5.6.2.3).
    std::vector<std::uint8_t> rest(n - in_frame);
    if (!rest.empty() && !data_->read(rest)) {
        return source_failed();
    }
    done_ += n;
    last_sent_ = done_ == total;
    set_request(make_download_segment(toggle_, last_sent_,
                                      std::span<const std::uint8_t>(data.data(), in_frame)));
    extra_ = std::move(rest);
    phase_ = Phase::DownloadSegment;
    return Step::Send;
}

} // namespace codrive::sdo
