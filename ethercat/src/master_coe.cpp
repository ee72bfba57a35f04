// SPDX-License-Identifier: Apache-2.0
// Master mailbox (SM0/SM1) and CoE: SDO upload/download, SDO information, emergencies
// (ETG.1000.6 §5.6.2).
#include "coe_transfer.hpp"

#include <codrive/ethercat/error.hpp>
#include <codrive/ethercat/master.hpp>
#include <codrive/ethercat/registers.hpp>

#include <codrive/core/sdo_abort.hpp>

#include <fmt/format.h>

#include <algorithm>

namespace codrive::ethercat {

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
        error_text() = fmt::format("{}: malformed mailbox header", slave_label(slave));
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
    const std::uint8_t want = SyncManager::repeat_request_after(*activate);
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
        error_text() = fmt::format("{}: the slave has no mailbox", slave_label(slave));
        return fail(EcatErrc::MailboxNotSupported);
    }
    const TimePoint deadline = clock_.now() + timeout;
    // Shared with the slave's mailbox channel: a repeat it requested in the cyclic frame may
    // have put a copy into SM1 that this read finds.
    bool& repeated = channel(slave).repeated;
    // At least this many repeats in all, so a read with no time left (a poll) still recovers a
    // message that is already out; more while the read has time.
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
                error_text() = fmt::format("{}: mailbox error 0x{:04X} ({})", slave_label(slave),
                                           code, mailbox_error_text(code));
                return fail(EcatErrc::MailboxError);
            }
            return std::move(m);
        }
        if (lost && (repeats_left-- > 0 || clock_.now() < deadline)) {
            // A read whose frame did not come back may have emptied SM1 on its way: ask the
            // slave for that message again instead of losing it (ETG.1000.4 §6.7.2), after
            // every such read while the read has time, as the cyclic channel does. Flagged
            // first: a request whose answer is lost may have been taken all the same.
            repeated = true;
            if (auto r = mailbox_repeat(slave); !r) {
                return fail(r.error());
            }
            continue;
        }
        if (clock_.now() >= deadline) {
            error_text() = fmt::format("{}: no mailbox answer within {:.0f} ms", slave_label(slave),
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

std::size_t Master::poll_mailboxes() {
    std::size_t read = 0;
    for (std::size_t i = 0; i < slaves_.size(); ++i) {
        if (!slaves_[i].sii.has_coe() || slaves_[i].state == AlState::Init ||
            mailbox_transfers(i) > 0) {
            continue; // a running transfer reads its own answers (and emergencies)
        }
        for (std::size_t n = 0; n < kPolledMessagesPerSlave; ++n) {
            auto m = mailbox_read(i, Duration::zero());
            if (!m) {
                break;
            }
            ++read;
            if (m->header.type == MailboxType::Coe && m->payload.size() >= kCoeHeaderSize &&
                coe_service(get_le<std::uint16_t>(m->payload.data())) == CoeService::Emergency) {
                dispatch_emergency(i, m->payload);
            }
        }
    }
    return read;
}

Result<std::vector<std::uint8_t>> Master::sdo_upload(std::size_t slave, std::uint16_t index,
                                                     std::uint8_t subindex, bool complete_access) {
    return run_transfer(slave, detail::make_sdo_upload(index, subindex, complete_access));
}

VoidResult Master::sdo_download(std::size_t slave, std::uint16_t index, std::uint8_t subindex,
                                std::span<const std::uint8_t> data, bool complete_access) {
    const std::size_t mbx = slave < slaves_.size() ? slaves_[slave].sii.rx_mailbox_size : 0;
    auto r = run_transfer(
        slave, detail::make_sdo_download(index, subindex,
                                         std::vector<std::uint8_t>(data.begin(), data.end()),
                                         complete_access, mbx));
    if (!r) {
        return fail(r.error());
    }
    return {};
}

Result<std::vector<std::uint8_t>> Master::sdo_info_request(std::size_t slave,
                                                           std::vector<std::uint8_t> request,
                                                           std::uint8_t response_opcode) {
    return run_transfer(slave,
                        detail::make_sdo_info(static_cast<std::uint8_t>(response_opcode - 1),
                                              std::move(request), "SDO information request"));
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
        error_text() =
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
        error_text() = fmt::format("{}: entry description of 0x{:04X}:{:02X} too short",
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
