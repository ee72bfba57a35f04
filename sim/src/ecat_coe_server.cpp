// SPDX-License-Identifier: Apache-2.0
// Slave-side CoE: SDO requests into the SDO server machine of sdo/ with CoE's framing, SDO
// information (OD list, object and entry descriptions), emergencies (ETG.1000.6 §5.6.2-3).
#include <codrive/sim/ecat/coe_server.hpp>

#include <codrive/core/endian.hpp>
#include <codrive/ethercat/mailbox.hpp>

#include <algorithm>

namespace codrive::sim::ecat {

using namespace codrive::ethercat;

namespace {

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
    : od_(od), mailbox_size_(mailbox_size),
      sdo_(od, sdo::ServerConfig{},
           sdo::SdoServerFraming::coe(mailbox_size - kMailboxHeaderSize - kCoeHeaderSize),
           [this](const sdo::Payload& frame, std::span<const std::uint8_t> extra) {
               // An abort is an SDO request-type service in CoE (ETG.1000.6 §5.6.2.7), every
               // other answer an SDO response.
               const bool abort = sdo::command_bits(frame[0]) ==
                                  static_cast<std::uint8_t>(sdo::ServerCommand::Abort);
               std::vector<std::uint8_t> r(kCoeHeaderSize);
               put_le<std::uint16_t>(
                   r.data(), coe_header(abort ? CoeService::SdoRequest : CoeService::SdoResponse));
               r.insert(r.end(), frame.begin(), frame.end());
               r.insert(r.end(), extra.begin(), extra.end());
               sdo_replies_.push_back(std::move(r));
           }) {
    // PDO assignment and mapping change only in PRE-OP (ETG.1000.6 §5.6.7.4): refused at the
    // initiate request, before any data.
    sdo_.set_access_hook([this](std::uint16_t index, std::uint8_t, sdo::Direction dir) {
        return dir == sdo::Direction::Download && preop_only(index) && state_ != AlState::PreOp
                   ? std::optional<SdoAbort>(SdoAbort::DataTransferState)
                   : std::nullopt;
    });
}

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
        // The CiA 301 SDO frame after the CoE header, then normal-transfer or segment data: the
        // one SDO server machine of sdo/ (ETG.1000.6 §5.6.2). No answer to an abort.
        state_ = state;
        sdo_replies_.clear();
        sdo_.on_request(payload.subspan(kCoeHeaderSize), TimePoint{});
        return std::move(sdo_replies_);
    }
    case CoeService::SdoInformation:
        return info(payload);
    default:
        return {};
    }
}

} // namespace codrive::sim::ecat
