// SPDX-License-Identifier: Apache-2.0
// CoE SDO upload/download and SDO information as step machines. The SDO command bytes are the
// CiA 301 SDO frame (ETG.1000.6 §5.6.2.1: "the CoE SDO payload is the CANopen SDO frame"), so
// they are built and parsed with sdo/'s codec; only what CoE adds (complete access, data past
// the 8 bytes in normal transfers and long segments) is handled here.
#include "coe_transfer.hpp"

#include <codrive/ethercat/error.hpp>

#include <codrive/core/endian.hpp>
#include <codrive/core/sdo_abort.hpp>
#include <codrive/sdo/protocol.hpp>

#include <fmt/format.h>

#include <algorithm>

namespace codrive::ethercat::detail {
namespace {

constexpr std::size_t kSdoFrame = kCoeHeaderSize + sdo::kFrameLen; // CoE header + 8 bytes

void put_request(std::vector<std::uint8_t>& out, CoeService service, const sdo::Payload& p) {
    out.assign(kCoeHeaderSize, 0);
    put_le<std::uint16_t>(out.data(), coe_header(service));
    out.insert(out.end(), p.begin(), p.end());
}

std::error_code abort_error(std::uint32_t code) {
    return {static_cast<int>(code), sdo_abort_category()};
}

/// The SDO frame inside a CoE SDO reply, parsed with the CAN codec; Invalid if too short.
sdo::FrameInfo parse_reply(std::span<const std::uint8_t> coe) {
    if (coe.size() < kSdoFrame) {
        return {};
    }
    return sdo::parse_frame(coe.subspan(kCoeHeaderSize, sdo::kFrameLen), sdo::Sender::Server);
}

class SdoUpload final : public CoeTransfer {
public:
    SdoUpload(std::uint16_t index, std::uint8_t subindex, bool ca)
        : index_(index), subindex_(subindex), ca_(ca) {}
    [[nodiscard]] CoeService service() const override { return CoeService::SdoResponse; }
    void first(std::vector<std::uint8_t>& request) override {
        auto p = sdo::make_initiate_upload(index_, subindex_);
        if (ca_) {
            p[0] = static_cast<std::uint8_t>(p[0] | sdo_cmd::kCompleteAccess);
        }
        put_request(request, CoeService::SdoRequest, p);
    }
    Step on_reply(std::span<const std::uint8_t> coe, std::vector<std::uint8_t>& request) override {
        const sdo::FrameInfo f = parse_reply(coe);
        if (f.kind == sdo::FrameKind::Invalid) {
            return failed(make_error_code(EcatErrc::ProtocolError), "the CoE answer is too short");
        }
        if (f.kind == sdo::FrameKind::Abort) {
            return aborted(f.abort_code);
        }
        if (!segmented_) {
            // CiA 301 client check: the answer names the object asked for (complete access
            // answers with the sub-index it starts from).
            if (f.kind != sdo::FrameKind::InitiateUploadResponse || f.index != index_ ||
                (!ca_ && f.subindex != subindex_)) {
                return failed(make_error_code(EcatErrc::ProtocolError),
                              "the answer does not match the request");
            }
            if (f.expedited) {
                const std::size_t n = f.size_indicated ? f.data_len : sdo::kExpeditedMax;
                outcome.data.assign(f.data.begin(), f.data.begin() + static_cast<long>(n));
                return Step::Done;
            }
            if (coe.size() < kSdoFrame) {
                return failed(make_error_code(EcatErrc::ProtocolError), "the answer has no size");
            }
            size_ = get_le<std::uint32_t>(coe.data() + kCoeHeaderSize + 4);
            outcome.data.assign(coe.begin() + kSdoFrame, coe.end());
            if (outcome.data.size() >= size_) {
                outcome.data.resize(size_); // the rest of the mailbox is padding
                return Step::Done;
            }
            segmented_ = true;
            put_request(request, CoeService::SdoRequest, sdo::make_upload_segment_request(false));
            return Step::Send;
        }
        // Upload segments (CiA 301 §7.2.4.3.6), CoE allows more than 7 data bytes each.
        if (f.kind != sdo::FrameKind::UploadSegmentResponse) {
            return failed(make_error_code(EcatErrc::ProtocolError), "expected an upload segment");
        }
        if (f.toggle != toggle_) {
            return failed(make_error_code(EcatErrc::ProtocolError),
                          "the segment toggle bit is wrong");
        }
        const std::size_t header = kCoeHeaderSize + 1;
        const std::size_t n = coe.size() == kSdoFrame ? f.data_len : coe.size() - header;
        if (n == 0 && !f.last) {
            // Progress guard: an empty segment that is not the last would loop forever.
            return failed(make_error_code(EcatErrc::ProtocolError),
                          "a zero-length segment that is not the last one");
        }
        outcome.data.insert(outcome.data.end(), coe.begin() + static_cast<long>(header),
                            coe.begin() + static_cast<long>(header + n));
        if (outcome.data.size() > size_ || (f.last && outcome.data.size() != size_)) {
            return failed(make_error_code(EcatErrc::ProtocolError),
                          "the segments do not add up to the announced size");
        }
        if (f.last) {
            return Step::Done;
        }
        toggle_ = !toggle_;
        put_request(request, CoeService::SdoRequest, sdo::make_upload_segment_request(toggle_));
        return Step::Send;
    }

private:
    Step aborted(std::uint32_t code) {
        outcome.error = abort_error(code);
        outcome.sentence = fmt::format("{}: {} aborted 0x{:08X} ({})", label, what, code,
                                       sdo_abort_describe(code));
        return Step::Failed;
    }
    std::uint16_t index_;
    std::uint8_t subindex_;
    bool ca_;
    bool segmented_ = false;
    bool toggle_ = false;
    std::uint32_t size_ = 0;
};

class SdoDownload final : public CoeTransfer {
public:
    SdoDownload(std::uint16_t index, std::uint8_t subindex, std::vector<std::uint8_t> data, bool ca,
                std::size_t mailbox_out)
        : index_(index), subindex_(subindex), data_(std::move(data)), ca_(ca),
          mailbox_out_(mailbox_out) {}
    [[nodiscard]] CoeService service() const override { return CoeService::SdoResponse; }
    void first(std::vector<std::uint8_t>& request) override {
        const std::uint8_t ca = ca_ ? sdo_cmd::kCompleteAccess : 0;
        if (!data_.empty() && data_.size() <= sdo::kExpeditedMax) {
            auto p = sdo::make_initiate_download_expedited(index_, subindex_, data_);
            p[0] = static_cast<std::uint8_t>(p[0] | ca);
            put_request(request, CoeService::SdoRequest, p);
            sent_ = data_.size();
            return;
        }
        // Normal transfer (ETG.1000.6 §5.6.2.4): size in the 4 data bytes, data after them.
        auto p = sdo::make_initiate_download_segmented(index_, subindex_,
                                                       static_cast<std::uint32_t>(data_.size()));
        p[0] = static_cast<std::uint8_t>(p[0] | ca);
        put_request(request, CoeService::SdoRequest, p);
        const std::size_t room = mailbox_out_ > kMailboxHeaderSize + kSdoFrame
                                     ? mailbox_out_ - kMailboxHeaderSize - kSdoFrame
                                     : 0;
        sent_ = std::min(room, data_.size());
        request.insert(request.end(), data_.begin(), data_.begin() + static_cast<long>(sent_));
    }
    Step on_reply(std::span<const std::uint8_t> coe, std::vector<std::uint8_t>& request) override {
        const sdo::FrameInfo f = parse_reply(coe);
        if (f.kind == sdo::FrameKind::Invalid) {
            return failed(make_error_code(EcatErrc::ProtocolError), "the CoE answer is too short");
        }
        if (f.kind == sdo::FrameKind::Abort) {
            outcome.error = abort_error(f.abort_code);
            outcome.sentence = fmt::format("{}: {} aborted 0x{:08X} ({})", label, what,
                                           f.abort_code, sdo_abort_describe(f.abort_code));
            return Step::Failed;
        }
        if (!initiated_) {
            if (f.kind != sdo::FrameKind::InitiateDownloadResponse || f.index != index_) {
                return failed(make_error_code(EcatErrc::ProtocolError),
                              "the answer does not match the request");
            }
            initiated_ = true;
        } else {
            if (f.kind != sdo::FrameKind::DownloadSegmentResponse || f.toggle != toggle_) {
                return failed(make_error_code(EcatErrc::ProtocolError),
                              "the segment answer does not match (toggle)");
            }
            toggle_ = !toggle_;
        }
        if (sent_ >= data_.size()) {
            return Step::Done;
        }
        // Download segment: 7 data bytes as on CAN, or more in one CoE segment (the rest of
        // the mailbox); at least 7 bytes are always sent (n tells the unused ones).
        const std::size_t room = mailbox_out_ - kMailboxHeaderSize - kCoeHeaderSize - 1;
        const std::size_t n = std::min(room, data_.size() - sent_);
        const bool last = sent_ + n == data_.size();
        const auto chunk = std::span<const std::uint8_t>(data_).subspan(sent_, n);
        if (n <= sdo::kSegmentData) {
            put_request(request, CoeService::SdoRequest,
                        sdo::make_download_segment(toggle_, last, chunk));
        } else {
            auto p = sdo::make_download_segment(toggle_, last, chunk.first(sdo::kSegmentData));
            put_request(request, CoeService::SdoRequest, p);
            request.insert(request.end(), chunk.begin() + sdo::kSegmentData, chunk.end());
        }
        sent_ += n;
        return Step::Send;
    }

private:
    std::uint16_t index_;
    std::uint8_t subindex_;
    std::vector<std::uint8_t> data_;
    bool ca_;
    std::size_t mailbox_out_;
    std::size_t sent_ = 0;
    bool initiated_ = false;
    bool toggle_ = false;
};

class SdoInfo final : public CoeTransfer {
public:
    SdoInfo(std::uint8_t opcode, std::vector<std::uint8_t> body)
        : opcode_(opcode), body_(std::move(body)) {}
    [[nodiscard]] CoeService service() const override { return CoeService::SdoInformation; }
    void first(std::vector<std::uint8_t>& request) override {
        request.assign(kCoeHeaderSize + sdo_info::kHeaderSize, 0);
        put_le<std::uint16_t>(request.data(), coe_header(CoeService::SdoInformation));
        request[2] = opcode_;
        request.insert(request.end(), body_.begin(), body_.end());
    }
    Step on_reply(std::span<const std::uint8_t> coe, std::vector<std::uint8_t>&) override {
        const std::size_t head = kCoeHeaderSize + sdo_info::kHeaderSize;
        if (coe.size() < head) {
            return failed(make_error_code(EcatErrc::ProtocolError), "the answer is too short");
        }
        const std::uint8_t opcode = coe[2] & 0x7F;
        if (opcode == sdo_info::kErrorReq) {
            const std::uint32_t code =
                coe.size() >= head + 4 ? get_le<std::uint32_t>(&coe[head]) : 0;
            outcome.error = abort_error(code);
            outcome.sentence = fmt::format("{}: SDO information request refused 0x{:08X} ({})",
                                           label, code, sdo_abort_describe(code));
            return Step::Failed;
        }
        if (opcode != opcode_ + 1) {
            return failed(make_error_code(EcatErrc::ProtocolError),
                          fmt::format("unexpected SDO information opcode {}", opcode));
        }
        outcome.data.insert(outcome.data.end(), coe.begin() + static_cast<long>(head), coe.end());
        return (coe[2] & sdo_info::kIncomplete) != 0 ? Step::Wait : Step::Done;
    }

private:
    std::uint8_t opcode_;
    std::vector<std::uint8_t> body_;
};

} // namespace

CoeTransfer::Step CoeTransfer::failed(std::error_code ec, const std::string& why) {
    outcome.error = ec;
    outcome.sentence = fmt::format("{}: {}: {}", label, what, why);
    return Step::Failed;
}

std::unique_ptr<CoeTransfer> make_sdo_upload(std::uint16_t index, std::uint8_t subindex,
                                             bool complete_access) {
    auto t = std::make_unique<SdoUpload>(index, subindex, complete_access);
    t->what = fmt::format("SDO upload 0x{:04X}:{:02X}", index, subindex);
    return t;
}

std::unique_ptr<CoeTransfer> make_sdo_download(std::uint16_t index, std::uint8_t subindex,
                                               std::vector<std::uint8_t> data, bool complete_access,
                                               std::size_t mailbox_out) {
    auto t = std::make_unique<SdoDownload>(index, subindex, std::move(data), complete_access,
                                           mailbox_out);
    t->what = fmt::format("SDO download 0x{:04X}:{:02X}", index, subindex);
    return t;
}

std::unique_ptr<CoeTransfer> make_sdo_info(std::uint8_t request_opcode,
                                           std::vector<std::uint8_t> body, std::string what) {
    auto t = std::make_unique<SdoInfo>(request_opcode, std::move(body));
    t->what = std::move(what);
    return t;
}

} // namespace codrive::ethercat::detail
