// SPDX-License-Identifier: Apache-2.0
// Master mailbox (SM0/SM1) and CoE: SDO upload/download, SDO information, emergencies
// (ETG.1000.6 §5.6.2).
#include <codrive/ethercat/error.hpp>
#include <codrive/ethercat/master.hpp>
#include <codrive/ethercat/registers.hpp>

#include <codrive/core/sdo_abort.hpp>

#include <fmt/format.h>

#include <algorithm>

namespace codrive::ethercat {
namespace {

constexpr std::size_t kSdoHeader = kCoeHeaderSize + 4; // CoE header + command + index + sub

std::vector<std::uint8_t> sdo_request(std::uint8_t cmd, std::uint16_t index,
                                      std::uint8_t subindex) {
    std::vector<std::uint8_t> p(kCoeHeaderSize + 8, 0);
    put_le<std::uint16_t>(p.data(), coe_header(CoeService::SdoRequest));
    p[2] = cmd;
    put_le<std::uint16_t>(p.data() + 3, index);
    p[5] = subindex;
    return p;
}

std::error_code abort_code(std::uint32_t code) {
    return {static_cast<int>(code), sdo_abort_category()};
}

} // namespace

std::uint8_t Master::next_counter(std::size_t slave) {
    // Counter 1..7, 0 is reserved (ETG.1000.6 §5.6.1).
    auto& c = slaves_[slave].mailbox_counter;
    c = static_cast<std::uint8_t>(c % 7 + 1);
    return c;
}

VoidResult Master::mailbox_write(std::size_t slave, MailboxMessage message) {
    if (auto c = check_slave(slave); !c) {
        return c;
    }
    const SiiInfo& sii = slaves_[slave].sii;
    if (!sii.has_mailbox()) {
        return set_error(make_error_code(EcatErrc::MailboxNotSupported),
                         fmt::format("{}: the slave has no mailbox", slave_label(slave)));
    }
    message.header.counter = next_counter(slave);
    auto bytes = message.encode(sii.rx_mailbox_size);
    if (bytes.size() > sii.rx_mailbox_size) {
        return set_error(make_error_code(EcatErrc::MailboxError),
                         fmt::format("{}: a {}-byte mailbox message does not fit the {}-byte "
                                     "mailbox",
                                     slave_label(slave), bytes.size(), sii.rx_mailbox_size));
    }
    const TimePoint deadline = clock_.now() + config_.mailbox_timeout;
    while (true) {
        std::array<Datagram, 1> d{Datagram::physical(Command::Fpwr, slaves_[slave].station_address,
                                                     sii.rx_mailbox_offset, bytes)};
        if (auto e = exchange(d); !e) {
            return e;
        }
        if (d[0].wkc == 1) {
            return {};
        }
        // WKC 0: the slave has not read the previous message yet (SM0 still full).
        if (clock_.now() >= deadline) {
            return set_error(make_error_code(EcatErrc::MailboxTimeout),
                             fmt::format("{}: the receive mailbox (SM0) stayed full for {:.0f} ms",
                                         slave_label(slave), to_ms(config_.mailbox_timeout)));
        }
        link_.idle(config_.mailbox_poll);
    }
}

Result<std::optional<MailboxMessage>> Master::mailbox_read_once(std::size_t slave, bool& lost) {
    const SiiInfo& sii = slaves_[slave].sii;
    // Reading the whole SM1 buffer empties it; WKC 0 means nothing was there.
    std::array<Datagram, 1> d{Datagram::physical(Command::Fprd, slaves_[slave].station_address,
                                                 sii.tx_mailbox_offset, sii.tx_mailbox_size)};
    if (auto e = exchange(d); !e) {
        return fail(e.error());
    }
    lost = last_exchange_lost_ > 0;
    if (d[0].wkc != 1) {
        return std::optional<MailboxMessage>{};
    }
    auto m = MailboxMessage::decode(d[0].data);
    if (!m) {
        last_error_ = fmt::format("{}: malformed mailbox header", slave_label(slave));
        return fail(m.error());
    }
    return std::optional<MailboxMessage>(std::move(*m));
}

VoidResult Master::mailbox_repeat(std::size_t slave) {
    if (auto c = check_slave(slave); !c) {
        return c;
    }
    const auto activate_reg = static_cast<std::uint16_t>(reg::sm(1) + SyncManager::kActivateOffset);
    const auto pdi_reg = static_cast<std::uint16_t>(reg::sm(1) + SyncManager::kPdiControlOffset);
    auto activate = read_register<std::uint8_t>(slave, activate_reg);
    if (!activate) {
        return fail(activate.error());
    }
    const auto want = static_cast<std::uint8_t>(*activate ^ SyncManager::kActivateRepeatRequest);
    if (auto w = write_register<std::uint8_t>(slave, activate_reg, want); !w) {
        return w;
    }
    ++mailbox_repeats_;
    const bool toggle = (want & SyncManager::kActivateRepeatRequest) != 0;
    const TimePoint deadline = clock_.now() + config_.mailbox_timeout;
    while (true) {
        auto pdi = read_register<std::uint8_t>(slave, pdi_reg);
        if (!pdi) {
            return fail(pdi.error());
        }
        if (((*pdi & SyncManager::kPdiRepeatAck) != 0) == toggle) {
            return {};
        }
        if (clock_.now() >= deadline) {
            return set_error(make_error_code(EcatErrc::MailboxTimeout),
                             fmt::format("{}: mailbox repeat request not acknowledged within "
                                         "{:.0f} ms",
                                         slave_label(slave), to_ms(config_.mailbox_timeout)));
        }
        link_.idle(config_.mailbox_poll);
    }
}

Result<MailboxMessage> Master::mailbox_read(std::size_t slave, Duration timeout) {
    if (auto c = check_slave(slave); !c) {
        return fail(c.error());
    }
    const SiiInfo& sii = slaves_[slave].sii;
    if (!sii.has_mailbox()) {
        last_error_ = fmt::format("{}: the slave has no mailbox", slave_label(slave));
        return fail(EcatErrc::MailboxNotSupported);
    }
    const TimePoint deadline = clock_.now() + timeout;
    bool repeated = false;
    int repeats_left = std::max(1, config_.frame_retries);
    while (true) {
        bool lost = false;
        auto read = mailbox_read_once(slave, lost);
        if (!read) {
            return fail(read.error());
        }
        if (read->has_value()) {
            MailboxMessage& m = **read;
            auto& last = slaves_[slave].mailbox_rx_counter;
            // After a repeat the slave may hand over the message we already have (the lost
            // frame never reached it): same counter, so it is dropped (ETG.1000.6 §5.6.1).
            const bool duplicate = repeated && m.header.counter != 0 && m.header.counter == last;
            last = m.header.counter;
            repeated = false;
            if (duplicate) {
                continue;
            }
            if (m.header.type == MailboxType::Error) {
                const std::uint16_t code =
                    m.payload.size() >= 4 ? get_le<std::uint16_t>(m.payload.data() + 2) : 0;
                last_error_ = fmt::format("{}: mailbox error 0x{:04X} ({})", slave_label(slave),
                                          code, mailbox_error_text(code));
                return fail(EcatErrc::MailboxError);
            }
            return std::move(m);
        }
        if (lost && repeats_left-- > 0) {
            // A read whose frame did not come back may have emptied SM1 on its way: ask the
            // slave for that message again instead of losing it (ETG.1000.4 §6.7.2).
            if (auto r = mailbox_repeat(slave); !r) {
                return fail(r.error());
            }
            repeated = true;
            continue;
        }
        if (clock_.now() >= deadline) {
            last_error_ = fmt::format("{}: no mailbox answer within {:.0f} ms", slave_label(slave),
                                      to_ms(timeout));
            return fail(EcatErrc::MailboxTimeout);
        }
        link_.idle(config_.mailbox_poll);
    }
}

std::string Master::describe_emergency(std::size_t slave, const emcy::EmcyMessage& m,
                                       const emcy::IEmcyTextProvider* vendor) const {
    std::string text = emcy::describe(m, vendor);
    // emcy::describe starts with "node N: "; EtherCAT names the slave instead.
    if (const auto colon = text.find(": "); colon != std::string::npos) {
        text = text.substr(colon + 2);
    }
    return fmt::format("{}: {}", slave_label(slave), text);
}

Result<MailboxMessage> Master::read_coe_reply(std::size_t slave, CoeService service) {
    const TimePoint deadline = clock_.now() + config_.mailbox_timeout;
    while (true) {
        const auto left = std::max(Duration::zero(), deadline - clock_.now());
        auto m = mailbox_read(slave, left);
        if (!m) {
            return m;
        }
        if (m->header.type != MailboxType::Coe || m->payload.size() < kCoeHeaderSize) {
            continue; // another protocol's message; not ours
        }
        const CoeService got = coe_service(get_le<std::uint16_t>(m->payload.data()));
        if (got == CoeService::Emergency) {
            if (m->payload.size() >= kCoeHeaderSize + 8) {
                emcy::EmcyMessage e;
                e.node = static_cast<NodeId>(std::min<std::size_t>(slave + 1, 127));
                e.error_code = get_le<std::uint16_t>(m->payload.data() + 2);
                e.error_register = m->payload[4];
                std::copy_n(m->payload.begin() + 5, 5, e.manufacturer.begin());
                if (emergency_handler_) {
                    emergency_handler_(slave, e);
                }
            }
            continue;
        }
        // The server's SDO abort travels as an SDO *request* (ETG.1000.6 §5.6.2.7).
        const bool sdo_abort = service == CoeService::SdoResponse &&
                               got == CoeService::SdoRequest && m->payload.size() > 2 &&
                               (m->payload[2] & sdo_cmd::kSpecifierMask) == sdo_cmd::kAbort;
        if (got == service || sdo_abort) {
            return m;
        }
    }
}

void Master::poll_mailboxes() {
    for (std::size_t i = 0; i < slaves_.size(); ++i) {
        if (!slaves_[i].sii.has_coe() || slaves_[i].state == AlState::Init) {
            continue;
        }
        while (true) {
            auto m = mailbox_read(i, Duration::zero());
            if (!m) {
                break;
            }
            if (m->header.type == MailboxType::Coe && m->payload.size() >= kCoeHeaderSize + 8 &&
                coe_service(get_le<std::uint16_t>(m->payload.data())) == CoeService::Emergency) {
                emcy::EmcyMessage e;
                e.node = static_cast<NodeId>(std::min<std::size_t>(i + 1, 127));
                e.error_code = get_le<std::uint16_t>(m->payload.data() + 2);
                e.error_register = m->payload[4];
                std::copy_n(m->payload.begin() + 5, 5, e.manufacturer.begin());
                if (emergency_handler_) {
                    emergency_handler_(i, e);
                }
            }
        }
    }
}

VoidResult Master::mailbox_exchange_sdo(std::size_t slave, std::vector<std::uint8_t> payload,
                                        MailboxMessage& reply, std::uint16_t index,
                                        std::uint8_t subindex, const char* what) {
    if (auto c = check_slave(slave); !c) {
        return c;
    }
    if (!slaves_[slave].sii.has_coe()) {
        return set_error(make_error_code(EcatErrc::MailboxNotSupported),
                         fmt::format("{}: the slave does not support CoE", slave_label(slave)));
    }
    MailboxMessage m;
    m.header.type = MailboxType::Coe;
    m.payload = std::move(payload);
    if (auto w = mailbox_write(slave, std::move(m)); !w) {
        return w;
    }
    auto r = read_coe_reply(slave, CoeService::SdoResponse);
    if (!r) {
        if (r.error() == EcatErrc::MailboxTimeout) {
            last_error_ = fmt::format("{}: SDO {} 0x{:04X}:{:02X}: no CoE answer within {:.0f} ms "
                                      "(mailbox timeout)",
                                      slave_label(slave), what, index, subindex,
                                      to_ms(config_.mailbox_timeout));
        }
        return fail(r.error());
    }
    if (r->payload.size() < kSdoHeader) {
        return set_error(make_error_code(EcatErrc::ProtocolError),
                         fmt::format("{}: SDO {} 0x{:04X}:{:02X}: the CoE answer is too short",
                                     slave_label(slave), what, index, subindex));
    }
    if ((r->payload[2] & sdo_cmd::kSpecifierMask) == sdo_cmd::kAbort) {
        const std::uint32_t code =
            r->payload.size() >= kSdoHeader + 4 ? get_le<std::uint32_t>(r->payload.data() + 6) : 0;
        return set_error(abort_code(code),
                         fmt::format("{}: SDO {} 0x{:04X}:{:02X} aborted 0x{:08X} ({})",
                                     slave_label(slave), what, index, subindex, code,
                                     sdo_abort_describe(code)));
    }
    reply = std::move(*r);
    return {};
}

Result<std::vector<std::uint8_t>> Master::sdo_upload(std::size_t slave, std::uint16_t index,
                                                     std::uint8_t subindex, bool complete_access) {
    const auto protocol_error = [&](const char* why) {
        last_error_ = fmt::format("{}: SDO upload 0x{:04X}:{:02X}: {}", slave_label(slave), index,
                                  subindex, why);
        return fail(EcatErrc::ProtocolError);
    };
    MailboxMessage reply;
    const std::uint8_t cmd =
        sdo_cmd::kUploadInitiateReq | (complete_access ? sdo_cmd::kCompleteAccess : 0);
    if (auto r = mailbox_exchange_sdo(slave, sdo_request(cmd, index, subindex), reply, index,
                                      subindex, "upload");
        !r) {
        return fail(r.error());
    }
    const auto& p = reply.payload;
    if ((p[2] & sdo_cmd::kSpecifierMask) != sdo_cmd::kUploadInitiateResp ||
        get_le<std::uint16_t>(p.data() + 3) != index) {
        return protocol_error("the answer does not match the request");
    }
    if ((p[2] & sdo_cmd::kExpedited) != 0) {
        std::size_t n = 4;
        if ((p[2] & sdo_cmd::kSizeIndicated) != 0) {
            n = 4U - ((p[2] >> 2) & 0x03U);
        }
        if (p.size() < kSdoHeader + n) {
            return protocol_error("the expedited answer is too short");
        }
        return std::vector<std::uint8_t>(p.begin() + kSdoHeader,
                                         p.begin() + static_cast<long>(kSdoHeader + n));
    }
    if (p.size() < kSdoHeader + 4) {
        return protocol_error("the answer has no size");
    }
    const std::uint32_t size = get_le<std::uint32_t>(p.data() + kSdoHeader);
    std::vector<std::uint8_t> data(p.begin() + kSdoHeader + 4, p.end());
    if (data.size() >= size) {
        data.resize(size);
        return data;
    }
    // Segmented upload: the rest comes in upload segments (CiA 301 §7.2.4.3.6).
    std::uint8_t toggle = 0;
    while (data.size() < size) {
        std::vector<std::uint8_t> req(kCoeHeaderSize + 8, 0);
        put_le<std::uint16_t>(req.data(), coe_header(CoeService::SdoRequest));
        req[2] = static_cast<std::uint8_t>(sdo_cmd::kUploadSegmentReq | toggle);
        if (auto r = mailbox_exchange_sdo(slave, std::move(req), reply, index, subindex, "upload");
            !r) {
            return fail(r.error());
        }
        const auto& s = reply.payload;
        if ((s[2] & sdo_cmd::kSpecifierMask) != sdo_cmd::kUploadSegmentResp) {
            return protocol_error("expected an upload segment");
        }
        if ((s[2] & sdo_cmd::kToggle) != toggle) {
            return protocol_error("the segment toggle bit is wrong");
        }
        std::size_t n = s.size() - 3;
        if (s.size() == kCoeHeaderSize + 8) {
            n = 7U - ((s[2] >> 1) & 0x07U); // short segment: size from the command byte
        }
        data.insert(data.end(), s.begin() + 3, s.begin() + 3 + static_cast<long>(n));
        if ((s[2] & sdo_cmd::kLastSegment) != 0) {
            break;
        }
        toggle ^= sdo_cmd::kToggle;
    }
    if (data.size() != size) {
        return protocol_error("the segments do not add up to the announced size");
    }
    return data;
}

VoidResult Master::sdo_download(std::size_t slave, std::uint16_t index, std::uint8_t subindex,
                                std::span<const std::uint8_t> data, bool complete_access) {
    if (auto c = check_slave(slave); !c) {
        return c;
    }
    const std::uint8_t ca = complete_access ? sdo_cmd::kCompleteAccess : 0;
    const auto protocol_error = [&](const char* why) {
        return set_error(make_error_code(EcatErrc::ProtocolError),
                         fmt::format("{}: SDO download 0x{:04X}:{:02X}: {}", slave_label(slave),
                                     index, subindex, why));
    };
    MailboxMessage reply;
    if (!data.empty() && data.size() <= 4) {
        auto req = sdo_request(
            static_cast<std::uint8_t>(sdo_cmd::kDownloadInitiateReq | ca | sdo_cmd::kExpedited |
                                      sdo_cmd::kSizeIndicated | ((4U - data.size()) << 2)),
            index, subindex);
        std::copy(data.begin(), data.end(), req.begin() + kSdoHeader);
        if (auto r =
                mailbox_exchange_sdo(slave, std::move(req), reply, index, subindex, "download");
            !r) {
            return r;
        }
        if ((reply.payload[2] & sdo_cmd::kSpecifierMask) != sdo_cmd::kDownloadInitiateResp) {
            return protocol_error("the answer does not match the request");
        }
        return {};
    }
    const std::size_t mbx = slaves_[slave].sii.rx_mailbox_size;
    const std::size_t first_room = mbx - kMailboxHeaderSize - kSdoHeader - 4;
    const std::size_t first = std::min(first_room, data.size());
    auto req =
        sdo_request(sdo_cmd::kDownloadInitiateReq | ca | sdo_cmd::kSizeIndicated, index, subindex);
    put_le<std::uint32_t>(req.data() + kSdoHeader, static_cast<std::uint32_t>(data.size()));
    req.resize(kSdoHeader + 4);
    req.insert(req.end(), data.begin(), data.begin() + static_cast<long>(first));
    if (auto r = mailbox_exchange_sdo(slave, std::move(req), reply, index, subindex, "download");
        !r) {
        return r;
    }
    if ((reply.payload[2] & sdo_cmd::kSpecifierMask) != sdo_cmd::kDownloadInitiateResp) {
        return protocol_error("the answer does not match the request");
    }
    std::size_t sent = first;
    std::uint8_t toggle = 0;
    const std::size_t seg_room = mbx - kMailboxHeaderSize - kCoeHeaderSize - 1;
    while (sent < data.size()) {
        const std::size_t n = std::min(seg_room, data.size() - sent);
        const bool last = sent + n == data.size();
        std::vector<std::uint8_t> seg(kCoeHeaderSize + 1, 0);
        put_le<std::uint16_t>(seg.data(), coe_header(CoeService::SdoRequest));
        seg[2] = static_cast<std::uint8_t>(sdo_cmd::kDownloadSegmentReq | toggle |
                                           (last ? sdo_cmd::kLastSegment : 0) |
                                           (n < 7 ? ((7U - n) << 1) : 0U));
        seg.insert(seg.end(), data.begin() + static_cast<long>(sent),
                   data.begin() + static_cast<long>(sent + n));
        if (seg.size() < kCoeHeaderSize + 8) {
            seg.resize(kCoeHeaderSize + 8, 0); // segments carry at least 7 data bytes
        }
        if (auto r =
                mailbox_exchange_sdo(slave, std::move(seg), reply, index, subindex, "download");
            !r) {
            return r;
        }
        if ((reply.payload[2] & sdo_cmd::kSpecifierMask) != sdo_cmd::kDownloadSegmentResp ||
            (reply.payload[2] & sdo_cmd::kToggle) != toggle) {
            return protocol_error("the segment answer does not match (toggle)");
        }
        sent += n;
        toggle ^= sdo_cmd::kToggle;
    }
    return {};
}

Result<std::vector<std::uint8_t>> Master::sdo_info_request(std::size_t slave,
                                                           std::vector<std::uint8_t> request,
                                                           std::uint8_t response_opcode) {
    if (auto c = check_slave(slave); !c) {
        return fail(c.error());
    }
    if (!slaves_[slave].sii.has_coe()) {
        last_error_ = fmt::format("{}: the slave does not support CoE", slave_label(slave));
        return fail(EcatErrc::MailboxNotSupported);
    }
    std::vector<std::uint8_t> payload(kCoeHeaderSize + sdo_info::kHeaderSize, 0);
    put_le<std::uint16_t>(payload.data(), coe_header(CoeService::SdoInformation));
    payload[2] = static_cast<std::uint8_t>(response_opcode - 1); // requests are odd opcodes
    payload.insert(payload.end(), request.begin(), request.end());
    MailboxMessage m;
    m.header.type = MailboxType::Coe;
    m.payload = std::move(payload);
    if (auto w = mailbox_write(slave, std::move(m)); !w) {
        return fail(w.error());
    }
    std::vector<std::uint8_t> data;
    while (true) {
        auto r = read_coe_reply(slave, CoeService::SdoInformation);
        if (!r) {
            if (r.error() == EcatErrc::MailboxTimeout) {
                last_error_ = fmt::format("{}: no SDO information answer within {:.0f} ms",
                                          slave_label(slave), to_ms(config_.mailbox_timeout));
            }
            return fail(r.error());
        }
        const auto& p = r->payload;
        if (p.size() < kCoeHeaderSize + sdo_info::kHeaderSize) {
            last_error_ = fmt::format("{}: SDO information answer too short", slave_label(slave));
            return fail(EcatErrc::ProtocolError);
        }
        const std::uint8_t opcode = p[2] & 0x7F;
        if (opcode == sdo_info::kErrorReq) {
            const std::uint32_t code = p.size() >= 10 ? get_le<std::uint32_t>(p.data() + 6) : 0;
            last_error_ = fmt::format("{}: SDO information request refused 0x{:08X} ({})",
                                      slave_label(slave), code, sdo_abort_describe(code));
            return fail(abort_code(code));
        }
        if (opcode != response_opcode) {
            last_error_ =
                fmt::format("{}: unexpected SDO information opcode {}", slave_label(slave), opcode);
            return fail(EcatErrc::ProtocolError);
        }
        data.insert(data.end(), p.begin() + kCoeHeaderSize + sdo_info::kHeaderSize, p.end());
        if ((p[2] & sdo_info::kIncomplete) == 0) {
            return data;
        }
    }
}

Result<std::vector<std::uint16_t>> Master::sdo_info_object_list(std::size_t slave) {
    std::vector<std::uint8_t> req(2);
    put_le<std::uint16_t>(req.data(), sdo_info::kListAll);
    auto d = sdo_info_request(slave, std::move(req), sdo_info::kGetOdListResp);
    if (!d) {
        return fail(d.error());
    }
    std::vector<std::uint16_t> out;
    for (std::size_t i = 2; i + 2 <= d->size(); i += 2) {
        out.push_back(get_le<std::uint16_t>(d->data() + i));
    }
    return out;
}

Result<ObjectDescription> Master::sdo_info_object(std::size_t slave, std::uint16_t index) {
    std::vector<std::uint8_t> req(2);
    put_le<std::uint16_t>(req.data(), index);
    auto d = sdo_info_request(slave, std::move(req), sdo_info::kGetObjectDescResp);
    if (!d) {
        return fail(d.error());
    }
    if (d->size() < 6) {
        last_error_ =
            fmt::format("{}: object description of 0x{:04X} too short", slave_label(slave), index);
        return fail(EcatErrc::ProtocolError);
    }
    ObjectDescription o;
    o.index = get_le<std::uint16_t>(d->data());
    o.data_type = get_le<std::uint16_t>(d->data() + 2);
    o.max_subindex = (*d)[4];
    o.object_code = (*d)[5];
    o.name.assign(d->begin() + 6, d->end());
    return o;
}

Result<EntryDescription> Master::sdo_info_entry(std::size_t slave, std::uint16_t index,
                                                std::uint8_t subindex) {
    std::vector<std::uint8_t> req{static_cast<std::uint8_t>(index),
                                  static_cast<std::uint8_t>(index >> 8), subindex, 0};
    auto d = sdo_info_request(slave, std::move(req), sdo_info::kGetEntryDescResp);
    if (!d) {
        return fail(d.error());
    }
    if (d->size() < 10) {
        last_error_ = fmt::format("{}: entry description of 0x{:04X}:{:02X} too short",
                                  slave_label(slave), index, subindex);
        return fail(EcatErrc::ProtocolError);
    }
    EntryDescription e;
    e.index = get_le<std::uint16_t>(d->data());
    e.subindex = (*d)[2];
    e.data_type = get_le<std::uint16_t>(d->data() + 4);
    e.bit_length = get_le<std::uint16_t>(d->data() + 6);
    e.access = get_le<std::uint16_t>(d->data() + 8);
    e.name.assign(d->begin() + 10, d->end());
    return e;
}

} // namespace codrive::ethercat
