// SPDX-License-Identifier: Apache-2.0
// Mailbox header codec and mailbox error texts (ETG.1000.6 §5.6).
#include <codrive/ethercat/error.hpp>
#include <codrive/ethercat/mailbox.hpp>

#include <codrive/core/endian.hpp>

#include <algorithm>

namespace codrive::ethercat {

void MailboxHeader::encode(std::uint8_t* out) const {
    put_le<std::uint16_t>(out, length);
    put_le<std::uint16_t>(out + 2, address);
    out[4] = static_cast<std::uint8_t>((channel & 0x3F) | ((priority & 0x03) << 6));
    out[5] =
        static_cast<std::uint8_t>((static_cast<unsigned>(type) & 0x0F) | ((counter & 0x07) << 4));
}

MailboxHeader MailboxHeader::decode(const std::uint8_t* in) {
    MailboxHeader h;
    h.length = get_le<std::uint16_t>(in);
    h.address = get_le<std::uint16_t>(in + 2);
    h.channel = static_cast<std::uint8_t>(in[4] & 0x3F);
    h.priority = static_cast<std::uint8_t>(in[4] >> 6);
    h.type = static_cast<MailboxType>(in[5] & 0x0F);
    h.counter = static_cast<std::uint8_t>((in[5] >> 4) & 0x07);
    return h;
}

std::vector<std::uint8_t> MailboxMessage::encode(std::size_t pad_to) const {
    std::vector<std::uint8_t> out(std::max(kMailboxHeaderSize + payload.size(), pad_to), 0);
    MailboxHeader h = header;
    h.length = static_cast<std::uint16_t>(payload.size());
    h.encode(out.data());
    std::copy(payload.begin(), payload.end(), out.begin() + kMailboxHeaderSize);
    return out;
}

Result<MailboxMessage> MailboxMessage::decode(std::span<const std::uint8_t> buffer) {
    if (buffer.size() < kMailboxHeaderSize) {
        return fail(EcatErrc::MailboxError);
    }
    MailboxMessage m;
    m.header = MailboxHeader::decode(buffer.data());
    if (kMailboxHeaderSize + m.header.length > buffer.size()) {
        return fail(EcatErrc::MailboxError);
    }
    m.payload.assign(buffer.begin() + kMailboxHeaderSize,
                     buffer.begin() +
                         static_cast<std::ptrdiff_t>(kMailboxHeaderSize + m.header.length));
    return m;
}

const char* mailbox_error_text(std::uint16_t code) {
    switch (code) {
    case 0x01:
        return "syntax error in the mailbox header";
    case 0x02:
        return "unsupported mailbox protocol";
    case 0x03:
        return "invalid channel";
    case 0x04:
        return "service not supported";
    case 0x05:
        return "invalid mailbox header";
    case 0x06:
        return "mailbox data too short";
    case 0x07:
        return "no more memory in the slave";
    case 0x08:
        return "invalid data size";
    default:
        return "unknown mailbox error";
    }
}

} // namespace codrive::ethercat
