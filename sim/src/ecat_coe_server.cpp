// SPDX-License-Identifier: Apache-2.0
// Slave-side CoE: SDO server with expedited/normal/segmented transfers and complete access,
// SDO information (OD list, object and entry descriptions), emergencies (ETG.1000.6 §5.6.2-3).
#include <codrive/sim/ecat/coe_server.hpp>

#include <codrive/core/endian.hpp>
#include <codrive/ethercat/mailbox.hpp>

#include <algorithm>

namespace codrive::sim::ecat {

using namespace codrive::ethercat;

namespace {

constexpr std::size_t kSdoHeader = kCoeHeaderSize + 4;

std::vector<std::uint8_t> sdo_reply(std::uint8_t cmd, std::uint16_t index, std::uint8_t sub) {
    std::vector<std::uint8_t> p(kCoeHeaderSize + 8, 0);
    put_le<std::uint16_t>(p.data(), coe_header(CoeService::SdoResponse));
    p[2] = cmd;
    put_le<std::uint16_t>(p.data() + 3, index);
    p[5] = sub;
    return p;
}

std::uint16_t access_bits(const SubObject& s) {
    // ETG.1000.6 Table 44: bits 0..2 readable in PRE-OP/SAFE-OP/OP, 3..5 writable, 6 RxPDO,
    // 7 TxPDO mappable.
    std::uint16_t a = 0;
    if (readable(s.access)) {
        a |= 0x0007;
    }
    if (writable(s.access)) {
        a |= 0x0038;
    }
    if (s.pdo_mappable) {
        if (s.mappable(PdoDir::Rpdo)) {
            a |= 0x0040;
        }
        if (s.mappable(PdoDir::Tpdo)) {
            a |= 0x0080;
        }
    }
    return a;
}

} // namespace

CoeServer::CoeServer(ObjectDictionary& od, std::size_t mailbox_size)
    : od_(od), mailbox_size_(mailbox_size) {}

bool CoeServer::preop_only(std::uint16_t index) {
    return index == 0x1C12 || index == 0x1C13 || (index >= 0x1600 && index <= 0x17FF) ||
           (index >= 0x1A00 && index <= 0x1BFF);
}

std::vector<std::uint8_t> CoeServer::emergency(const emcy::EmcyMessage& m) {
    std::vector<std::uint8_t> p(kCoeHeaderSize + 8, 0);
    put_le<std::uint16_t>(p.data(), coe_header(CoeService::Emergency));
    put_le<std::uint16_t>(p.data() + 2, m.error_code);
    p[4] = m.error_register;
    std::copy(m.manufacturer.begin(), m.manufacturer.end(), p.begin() + 5);
    return p;
}

std::vector<std::uint8_t> CoeServer::abort(std::uint16_t index, std::uint8_t sub,
                                           std::uint32_t code) {
    upload_active_ = false;
    download_active_ = false;
    auto p = sdo_reply(sdo_cmd::kAbort, index, sub);
    put_le<std::uint32_t>(p.data() + kSdoHeader, code);
    // An abort is an SDO request-type service in CoE (ETG.1000.6 §5.6.2.7).
    put_le<std::uint16_t>(p.data(), coe_header(CoeService::SdoRequest));
    return p;
}

tl::expected<std::vector<std::uint8_t>, SdoAbort> CoeServer::read_value(std::uint16_t index,
                                                                        std::uint8_t sub, bool ca) {
    if (!ca) {
        auto v = od_.read(index, sub);
        if (!v) {
            return tl::unexpected(v.error());
        }
        return std::vector<std::uint8_t>(v->begin(), v->end());
    }
    // Complete access (ETG.1000.6 §5.6.2.1, ETG.1020 §12.2 "SDO Complete Access"): the object
    // as its data type lays it out (ETG.2000 DataType: sub-index 0, UINT8, at bit 0 and
    // sub-index 1 at bit offset 16), i.e. sub 0 padded to 16 bits, then every sub-index 1..n
    // packed. Starting at sub 1 leaves sub 0 out.
    const Object* obj = od_.find(index);
    if (obj == nullptr) {
        return tl::unexpected(SdoAbort::NoObject);
    }
    if (sub > 1) {
        return tl::unexpected(SdoAbort::UnsupportedAccess);
    }
    std::vector<std::uint8_t> out;
    const auto count = od_.get<std::uint8_t>(index, 0).value_or(0);
    if (sub == 0) {
        out.push_back(count);
        out.push_back(0); // padding to 16 bits
    }
    for (std::uint8_t s = 1; s <= count; ++s) {
        auto v = od_.read(index, s);
        if (!v) {
            return tl::unexpected(v.error());
        }
        out.insert(out.end(), v->begin(), v->end());
    }
    return out;
}

tl::expected<void, SdoAbort> CoeServer::write_value(std::uint16_t index, std::uint8_t sub,
                                                    std::span<const std::uint8_t> data, bool ca,
                                                    AlState state) {
    if (preop_only(index) && state != AlState::PreOp) {
        return tl::unexpected(SdoAbort::DataTransferState);
    }
    if (!ca) {
        return od_.write(index, sub, data);
    }
    const Object* obj = od_.find(index);
    if (obj == nullptr) {
        return tl::unexpected(SdoAbort::NoObject);
    }
    if (sub > 1) {
        return tl::unexpected(SdoAbort::UnsupportedAccess);
    }
    std::size_t pos = 0;
    std::uint8_t count = od_.get<std::uint8_t>(index, 0).value_or(0);
    if (sub == 0) {
        // Sub 0 padded to 16 bits, as in an upload (ETG.1000.6 §5.6.2.1).
        if (data.size() < 2) {
            return tl::unexpected(SdoAbort::LengthTooLow);
        }
        count = data[0];
        pos = 2;
        // PDO objects: clear the count before entries, set it last (ETG.1000.6 §5.6.7.4).
        const std::uint8_t zero = 0;
        if (auto r = od_.write(index, 0, std::span<const std::uint8_t>(&zero, 1)); !r) {
            return r;
        }
    }
    for (std::uint8_t s = 1; s <= count; ++s) {
        const SubObject* so = od_.find(index, s);
        if (so == nullptr) {
            return tl::unexpected(SdoAbort::NoSubindex);
        }
        const std::size_t n = data_type_size(so->type);
        if (n == 0 || pos + n > data.size()) {
            return tl::unexpected(SdoAbort::LengthMismatch);
        }
        if (auto r = od_.write(index, s, data.subspan(pos, n)); !r) {
            return r;
        }
        pos += n;
    }
    if (sub == 0) {
        return od_.write(index, 0, std::span<const std::uint8_t>(&count, 1));
    }
    return {};
}

std::vector<std::uint8_t> CoeServer::sdo(std::span<const std::uint8_t> p, AlState state) {
    if (p.size() < kCoeHeaderSize + 1) {
        return abort(0, 0, static_cast<std::uint32_t>(SdoAbort::UnknownCommand));
    }
    const std::uint8_t cmd = p[2];
    const std::uint8_t ccs = cmd & sdo_cmd::kSpecifierMask;
    const std::uint16_t index = p.size() >= 5 ? get_le<std::uint16_t>(p.data() + 3) : 0;
    const std::uint8_t sub = p.size() >= 6 ? p[5] : 0;
    const std::size_t room = mailbox_size_ - kMailboxHeaderSize; // CoE payload per answer

    if (ccs == sdo_cmd::kAbort) {
        upload_active_ = false;
        download_active_ = false;
        return {};
    }
    if (ccs == sdo_cmd::kUploadInitiateReq) {
        if (p.size() < kSdoHeader) {
            return abort(index, sub, static_cast<std::uint32_t>(SdoAbort::UnknownCommand));
        }
        const bool ca = (cmd & sdo_cmd::kCompleteAccess) != 0;
        auto v = read_value(index, sub, ca);
        if (!v) {
            return abort(index, sub, static_cast<std::uint32_t>(v.error()));
        }
        if (v->size() <= 4 && !v->empty()) {
            auto r = sdo_reply(
                static_cast<std::uint8_t>(sdo_cmd::kUploadInitiateResp | sdo_cmd::kExpedited |
                                          sdo_cmd::kSizeIndicated | ((4U - v->size()) << 2)),
                index, sub);
            std::copy(v->begin(), v->end(), r.begin() + kSdoHeader);
            return r;
        }
        auto r = sdo_reply(sdo_cmd::kUploadInitiateResp | sdo_cmd::kSizeIndicated, index, sub);
        put_le<std::uint32_t>(r.data() + kSdoHeader, static_cast<std::uint32_t>(v->size()));
        const std::size_t first = std::min(v->size(), room - kSdoHeader - 4);
        r.insert(r.end(), v->begin(), v->begin() + static_cast<long>(first));
        if (first < v->size()) {
            upload_active_ = true;
            xfer_index_ = index;
            xfer_sub_ = sub;
            toggle_ = 0;
            buffer_ = std::move(*v);
            offset_ = first;
        }
        return r;
    }
    if (ccs == sdo_cmd::kUploadSegmentReq) {
        if (!upload_active_) {
            return abort(xfer_index_, xfer_sub_,
                         static_cast<std::uint32_t>(SdoAbort::UnknownCommand));
        }
        if ((cmd & sdo_cmd::kToggle) != toggle_) {
            return abort(xfer_index_, xfer_sub_, static_cast<std::uint32_t>(SdoAbort::ToggleBit));
        }
        const std::size_t n = std::min(buffer_.size() - offset_, room - kCoeHeaderSize - 1);
        const bool last = offset_ + n == buffer_.size();
        std::vector<std::uint8_t> r(kCoeHeaderSize + 1, 0);
        put_le<std::uint16_t>(r.data(), coe_header(CoeService::SdoResponse));
        r[2] = static_cast<std::uint8_t>(sdo_cmd::kUploadSegmentResp | toggle_ |
                                         (last ? sdo_cmd::kLastSegment : 0) |
                                         (n < 7 ? ((7U - n) << 1) : 0U));
        r.insert(r.end(), buffer_.begin() + static_cast<long>(offset_),
                 buffer_.begin() + static_cast<long>(offset_ + n));
        if (r.size() < kCoeHeaderSize + 8) {
            r.resize(kCoeHeaderSize + 8, 0);
        }
        offset_ += n;
        toggle_ ^= sdo_cmd::kToggle;
        if (last) {
            upload_active_ = false;
        }
        return r;
    }
    if (ccs == sdo_cmd::kDownloadInitiateReq) {
        if (p.size() < kSdoHeader + 4) {
            return abort(index, sub, static_cast<std::uint32_t>(SdoAbort::UnknownCommand));
        }
        const bool ca = (cmd & sdo_cmd::kCompleteAccess) != 0;
        if ((cmd & sdo_cmd::kExpedited) != 0) {
            std::size_t n = 4;
            if ((cmd & sdo_cmd::kSizeIndicated) != 0) {
                n = 4U - ((cmd >> 2) & 0x03U);
            }
            if (auto w = write_value(index, sub, p.subspan(kSdoHeader, n), ca, state); !w) {
                return abort(index, sub, static_cast<std::uint32_t>(w.error()));
            }
            return sdo_reply(sdo_cmd::kDownloadInitiateResp, index, sub);
        }
        const std::uint32_t size = get_le<std::uint32_t>(p.data() + kSdoHeader);
        auto data = p.subspan(kSdoHeader + 4);
        if (data.size() >= size) {
            if (auto w = write_value(index, sub, data.first(size), ca, state); !w) {
                return abort(index, sub, static_cast<std::uint32_t>(w.error()));
            }
            return sdo_reply(sdo_cmd::kDownloadInitiateResp, index, sub);
        }
        // Check early so a long transfer to a bad object aborts at once.
        if (!ca && od_.find(index, sub) == nullptr) {
            return abort(index, sub,
                         static_cast<std::uint32_t>(od_.find(index) == nullptr
                                                        ? SdoAbort::NoObject
                                                        : SdoAbort::NoSubindex));
        }
        download_active_ = true;
        xfer_index_ = index;
        xfer_sub_ = sub;
        xfer_ca_ = ca;
        toggle_ = 0;
        expected_size_ = size;
        buffer_.assign(data.begin(), data.end());
        return sdo_reply(sdo_cmd::kDownloadInitiateResp, index, sub);
    }
    if (ccs == sdo_cmd::kDownloadSegmentReq) {
        if (!download_active_) {
            return abort(xfer_index_, xfer_sub_,
                         static_cast<std::uint32_t>(SdoAbort::UnknownCommand));
        }
        if ((cmd & sdo_cmd::kToggle) != toggle_) {
            return abort(xfer_index_, xfer_sub_, static_cast<std::uint32_t>(SdoAbort::ToggleBit));
        }
        std::size_t n = p.size() - 3;
        if (p.size() == kCoeHeaderSize + 8) {
            n = 7U - ((cmd >> 1) & 0x07U);
        }
        buffer_.insert(buffer_.end(), p.begin() + 3, p.begin() + 3 + static_cast<long>(n));
        std::vector<std::uint8_t> r(kCoeHeaderSize + 8, 0);
        put_le<std::uint16_t>(r.data(), coe_header(CoeService::SdoResponse));
        r[2] = static_cast<std::uint8_t>(sdo_cmd::kDownloadSegmentResp | toggle_);
        toggle_ ^= sdo_cmd::kToggle;
        if ((cmd & sdo_cmd::kLastSegment) != 0) {
            download_active_ = false;
            if (buffer_.size() != expected_size_) {
                return abort(xfer_index_, xfer_sub_,
                             static_cast<std::uint32_t>(SdoAbort::LengthMismatch));
            }
            if (auto w = write_value(xfer_index_, xfer_sub_, buffer_, xfer_ca_, state); !w) {
                return abort(xfer_index_, xfer_sub_, static_cast<std::uint32_t>(w.error()));
            }
        }
        return r;
    }
    return abort(index, sub, static_cast<std::uint32_t>(SdoAbort::UnknownCommand));
}

std::vector<std::vector<std::uint8_t>> CoeServer::info(std::span<const std::uint8_t> p) {
    const auto error = [](SdoAbort a) {
        std::vector<std::uint8_t> r(kCoeHeaderSize + sdo_info::kHeaderSize + 4, 0);
        put_le<std::uint16_t>(r.data(), coe_header(CoeService::SdoInformation));
        r[2] = sdo_info::kErrorReq;
        put_le<std::uint32_t>(r.data() + 6, static_cast<std::uint32_t>(a));
        return std::vector<std::vector<std::uint8_t>>{r};
    };
    if (p.size() < kCoeHeaderSize + sdo_info::kHeaderSize + 2) {
        return error(SdoAbort::UnknownCommand);
    }
    const std::uint8_t opcode = p[2] & 0x7F;
    const auto body = p.subspan(kCoeHeaderSize + sdo_info::kHeaderSize);
    std::vector<std::uint8_t> data;
    std::uint8_t resp = 0;
    if (opcode == sdo_info::kGetOdListReq) {
        resp = sdo_info::kGetOdListResp;
        const auto list_type = get_le<std::uint16_t>(body.data());
        data.resize(2);
        put_le<std::uint16_t>(data.data(), list_type);
        if (list_type == sdo_info::kListAll) {
            for (const auto& [index, obj] : od_.objects()) {
                data.push_back(static_cast<std::uint8_t>(index));
                data.push_back(static_cast<std::uint8_t>(index >> 8));
            }
        }
    } else if (opcode == sdo_info::kGetObjectDescReq) {
        resp = sdo_info::kGetObjectDescResp;
        const auto index = get_le<std::uint16_t>(body.data());
        const Object* obj = od_.find(index);
        if (obj == nullptr || obj->subs.empty()) {
            return error(SdoAbort::NoObject);
        }
        const SubObject& last = obj->subs.rbegin()->second;
        data.resize(6);
        put_le<std::uint16_t>(data.data(), index);
        put_le<std::uint16_t>(data.data() + 2, static_cast<std::uint16_t>(last.type));
        data[4] = obj->code == ObjectCode::Var ? 0 : obj->subs.rbegin()->first;
        data[5] = static_cast<std::uint8_t>(obj->code);
        data.insert(data.end(), obj->name.begin(), obj->name.end());
    } else if (opcode == sdo_info::kGetEntryDescReq) {
        resp = sdo_info::kGetEntryDescResp;
        if (body.size() < 4) {
            return error(SdoAbort::UnknownCommand);
        }
        const auto index = get_le<std::uint16_t>(body.data());
        const std::uint8_t sub = body[2];
        const SubObject* s = od_.find(index, sub);
        if (s == nullptr) {
            return error(od_.find(index) == nullptr ? SdoAbort::NoObject : SdoAbort::NoSubindex);
        }
        data.resize(10);
        put_le<std::uint16_t>(data.data(), index);
        data[2] = sub;
        data[3] = 0; // no value info requested/returned
        put_le<std::uint16_t>(data.data() + 4, static_cast<std::uint16_t>(s->type));
        const std::size_t fixed = data_type_size(s->type);
        put_le<std::uint16_t>(data.data() + 6, static_cast<std::uint16_t>(
                                                   (fixed != 0 ? fixed : s->value.size()) * 8));
        put_le<std::uint16_t>(data.data() + 8, access_bits(*s));
        data.insert(data.end(), s->name.begin(), s->name.end());
    } else {
        return error(SdoAbort::UnknownCommand);
    }
    // Fragment to the mailbox size (ETG.1000.6 §5.6.3.2: "fragments left" counts down).
    const std::size_t room =
        mailbox_size_ - kMailboxHeaderSize - kCoeHeaderSize - sdo_info::kHeaderSize;
    const std::size_t fragments = data.empty() ? 1 : (data.size() + room - 1) / room;
    std::vector<std::vector<std::uint8_t>> out;
    for (std::size_t f = 0; f < fragments; ++f) {
        std::vector<std::uint8_t> r(kCoeHeaderSize + sdo_info::kHeaderSize, 0);
        put_le<std::uint16_t>(r.data(), coe_header(CoeService::SdoInformation));
        const std::size_t left = fragments - f - 1;
        r[2] = static_cast<std::uint8_t>(resp | (left > 0 ? sdo_info::kIncomplete : 0));
        put_le<std::uint16_t>(r.data() + 4, static_cast<std::uint16_t>(left));
        const std::size_t from = f * room;
        const std::size_t to = std::min(data.size(), from + room);
        r.insert(r.end(), data.begin() + static_cast<long>(from),
                 data.begin() + static_cast<long>(to));
        out.push_back(std::move(r));
    }
    return out;
}

std::vector<std::vector<std::uint8_t>> CoeServer::handle(std::span<const std::uint8_t> payload,
                                                         AlState state) {
    if (payload.size() < kCoeHeaderSize) {
        return {};
    }
    switch (coe_service(get_le<std::uint16_t>(payload.data()))) {
    case CoeService::SdoRequest: {
        auto r = sdo(payload, state);
        if (r.empty()) {
            return {};
        }
        return {std::move(r)};
    }
    case CoeService::SdoInformation:
        return info(payload);
    default:
        return {};
    }
}

} // namespace codrive::sim::ecat
