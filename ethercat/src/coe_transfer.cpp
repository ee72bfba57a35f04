// SPDX-License-Identifier: Apache-2.0
// CoE SDO upload/download and SDO information as step machines. The SDO command bytes are the
// CiA 301 SDO frame (ETG.1000.6 §5.6.2.1: "the CoE SDO payload is the CANopen SDO frame"), so an
// SDO transfer is sdo/'s client machine (the CAN client's) behind a CoE header; only the framing
// CoE adds (complete access, data past the 8 bytes) is configured here.
#include "coe_transfer.hpp"

#include <codrive/ethercat/error.hpp>

#include <codrive/core/endian.hpp>
#include <codrive/core/sdo_abort.hpp>
#include <codrive/sdo/client_machine.hpp>
#include <codrive/sdo/protocol.hpp>

#include <fmt/format.h>

#include <algorithm>

namespace codrive::ethercat::detail {
namespace {

constexpr std::size_t kSdoFrame = kCoeHeaderSize + sdo::kFrameLen; // CoE header + 8 bytes

std::error_code abort_error(std::uint32_t code) {
    return {static_cast<int>(code), sdo_abort_category()};
}

/// A CoE SDO upload or download: a thin adapter that runs sdo::SdoClientMachine (the CAN
/// client's machine, with its checks) over the mailbox. CoE only changes the framing: a CoE
/// header before the CiA 301 frame, data after it (normal transfer, long segments) and complete
/// access (ETG.1000.6 §5.6.2). The mailbox channel does the timing and repeats.
class CoeSdo final : public CoeTransfer, public sdo::ISdoData {
public:
    /// Upload.
    CoeSdo(std::uint16_t index, std::uint8_t subindex, bool ca)
        : upload_(true),
          machine_(*this, sdo::SdoFraming{sdo::kSegmentData, 0, ca}, index, subindex) {}
    /// Download; `mailbox_out`: the slave's SM0 size, which bounds every request.
    CoeSdo(std::uint16_t index, std::uint8_t subindex, std::vector<std::uint8_t> data, bool ca,
           std::size_t mailbox_out)
        : upload_(false), data_(std::move(data)),
          machine_(*this, download_framing(mailbox_out, ca), index, subindex) {}

    [[nodiscard]] CoeService service() const override { return CoeService::SdoResponse; }
    void first(std::vector<std::uint8_t>& request) override {
        const auto step =
            upload_ ? machine_.begin_upload() : machine_.begin_download(data_.size(), true);
        if (step == Step_::Failed) {
            (void)fail_with(machine_.failure()); // nothing was sent: no abort to send
            return;
        }
        put_request(request);
    }
    Step on_reply(std::span<const std::uint8_t> coe, std::vector<std::uint8_t>& request) override {
        // The CiA 301 frame after the CoE header. A shorter message is malformed, not the late
        // answer of another transfer: it ends this one (abort 0x05040001, as an unexpected frame).
        if (coe.size() < kSdoFrame) {
            const auto code = static_cast<std::uint32_t>(SdoAbort::UnknownCommand);
            (void)machine_.abort(code, abort_error(code),
                                 fmt::format("the answer is {} bytes, shorter than a CoE SDO "
                                             "message ({} bytes)",
                                             coe.size(), kSdoFrame));
            return failed_step(request);
        }
        const sdo::FrameInfo reply =
            sdo::parse_frame(coe.subspan(kCoeHeaderSize, sdo::kFrameLen), sdo::Sender::Server);
        const std::span<const std::uint8_t> extra = coe.subspan(kSdoFrame);
        switch (machine_.on_reply(reply, extra)) {
        case Step_::Send:
            put_request(request);
            return Step::Send;
        case Step_::Done:
            if (upload_) {
                outcome.data = std::move(data_);
            }
            return Step::Done;
        case Step_::Failed:
            return failed_step(request);
        case Step_::Ignore:
            break;
        }
        return Step::Stray;
    }
    Step on_timeout(std::vector<std::uint8_t>& request) override {
        const auto phase = machine_.phase();
        if ((phase != Phase::InitiateUpload && phase != Phase::InitiateDownload) ||
            machine_.unanswered() != Step_::Failed) {
            return Step::Wait;
        }
        return failed_step(request);
    }

    // sdo::ISdoData: the transfer's own buffer.
    bool begin(std::optional<std::size_t> size) override {
        if (size) {
            data_.reserve(std::min(*size, sdo::kMaxUploadReserve));
        }
        return true;
    }
    bool write(std::span<const std::uint8_t> d) override {
        data_.insert(data_.end(), d.begin(), d.end());
        return true;
    }
    bool read(std::span<std::uint8_t> out) override {
        if (out.size() > data_.size() - read_) {
            return false;
        }
        std::copy_n(data_.begin() + static_cast<long>(read_), out.size(), out.begin());
        read_ += out.size();
        return true;
    }

private:
    using Step_ = sdo::SdoClientMachine::Step;
    using Phase = sdo::SdoClientMachine::Phase;

    /// The machine failed: the outcome, and the abort the master sends (ETG.1000.6 §5.6.2.7).
    Step failed_step(std::vector<std::uint8_t>& request) {
        if (fail_with(machine_.failure())) {
            put_request(request);
            return Step::SendLast;
        }
        return Step::Failed;
    }

    static sdo::SdoFraming download_framing(std::size_t mailbox_out, bool ca) {
        // Room for data in one request: the mailbox after its header and, for the initiate
        // request, the 8-byte frame (ETG.1000.6 §5.6.2.2), for a segment its command byte
        // (§5.6.2.3). A segment always holds at least CiA 301's 7 bytes.
        const std::size_t room =
            mailbox_out > kMailboxHeaderSize ? mailbox_out - kMailboxHeaderSize : 0;
        sdo::SdoFraming f;
        f.initiate_room = room > kSdoFrame ? room - kSdoFrame : 0;
        f.segment_room =
            std::max(sdo::kSegmentData, room > kCoeHeaderSize + 1 ? room - kCoeHeaderSize - 1 : 0);
        f.complete_access = ca;
        return f;
    }

    void put_request(std::vector<std::uint8_t>& out) const {
        out.assign(kCoeHeaderSize, 0);
        put_le<std::uint16_t>(out.data(), coe_header(CoeService::SdoRequest));
        const auto& p = machine_.request();
        out.insert(out.end(), p.begin(), p.end());
        const auto extra = machine_.request_extra();
        out.insert(out.end(), extra.begin(), extra.end());
    }

    /// The outcome of a failed transfer; true when the master tells the slave with an abort.
    bool fail_with(const sdo::SdoClientMachine::Failure& f) {
        outcome.error = f.cause;
        outcome.data.clear();
        const bool abort_code = f.cause.category() == sdo_abort_category();
        const auto code = static_cast<std::uint32_t>(f.cause.value());
        if (f.origin == sdo::AbortOrigin::Server && abort_code) {
            outcome.sentence = fmt::format("{}: {} aborted 0x{:08X} ({})", label, what, code,
                                           sdo_abort_describe(code));
        } else if (f.origin == sdo::AbortOrigin::Client && abort_code) {
            outcome.sentence = fmt::format("{}: {} aborted by the master 0x{:08X} ({}): {}", label,
                                           what, code, sdo_abort_describe(code), f.detail);
        } else {
            outcome.sentence = fmt::format("{}: {} failed: {}{}{}", label, what, f.cause.message(),
                                           f.detail.empty() ? "" : ": ", f.detail);
        }
        return f.abort.has_value();
    }

    bool upload_;
    std::vector<std::uint8_t> data_; ///< download: the data; upload: what arrived
    std::size_t read_ = 0;
    sdo::SdoClientMachine machine_;
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
    auto t = std::make_unique<CoeSdo>(index, subindex, complete_access);
    t->what = fmt::format("SDO upload 0x{:04X}:{:02X}", index, subindex);
    return t;
}

std::unique_ptr<CoeTransfer> make_sdo_download(std::uint16_t index, std::uint8_t subindex,
                                               std::vector<std::uint8_t> data, bool complete_access,
                                               std::size_t mailbox_out) {
    auto t =
        std::make_unique<CoeSdo>(index, subindex, std::move(data), complete_access, mailbox_out);
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
