// SPDX-License-Identifier: Apache-2.0
// FoE message codec and error texts (ETG.1000.6 §5.7).
#include <codrive/ethercat/foe.hpp>
#include <codrive/ethercat/mailbox.hpp>

#include <codrive/core/endian.hpp>

#include <string>

namespace codrive::ethercat {
namespace {

class FoeCategory final : public std::error_category {
public:
    const char* name() const noexcept override { return "codrive-foe"; }
    std::string message(int ev) const override {
        return foe_error_text(static_cast<std::uint32_t>(ev));
    }
};

} // namespace

const char* foe_error_text(std::uint32_t code) {
    switch (code) {
    case foe_error::kNotDefined:
        return "not defined";
    case foe_error::kNotFound:
        return "not found";
    case foe_error::kAccessDenied:
        return "access denied";
    case foe_error::kDiskFull:
        return "disk full";
    case foe_error::kIllegal:
        return "illegal";
    case foe_error::kPacketNumberWrong:
        return "packet number wrong";
    case foe_error::kAlreadyExists:
        return "already exists";
    case foe_error::kNoUser:
        return "no user";
    case foe_error::kBootstrapOnly:
        return "bootstrap only";
    case foe_error::kNotBootstrap:
        return "not bootstrap";
    case foe_error::kNoRights:
        return "no rights";
    case foe_error::kProgramError:
        return "program error";
    default:
        return "unknown FoE error";
    }
}

const std::error_category& foe_category() {
    static const FoeCategory category;
    return category;
}

std::optional<FoeMessage> decode_foe(std::span<const std::uint8_t> payload) {
    if (payload.size() < kFoeHeaderSize || payload[0] < 1 || payload[0] > 6) {
        return std::nullopt;
    }
    FoeMessage m;
    m.opcode = static_cast<FoeOpcode>(payload[0]);
    m.value = get_le<std::uint32_t>(payload.data() + 2);
    m.done = static_cast<std::uint16_t>(m.value);
    m.entire = static_cast<std::uint16_t>(m.value >> 16);
    m.body = payload.subspan(kFoeHeaderSize);
    return m;
}

void encode_foe(std::vector<std::uint8_t>& out, FoeOpcode opcode, std::uint32_t value,
                std::span<const std::uint8_t> body) {
    out.assign(kFoeHeaderSize, 0);
    out[0] = static_cast<std::uint8_t>(opcode);
    put_le<std::uint32_t>(out.data() + 2, value);
    out.insert(out.end(), body.begin(), body.end());
}

std::size_t foe_max_data(std::size_t mailbox_size) {
    const std::size_t head = kMailboxHeaderSize + kFoeHeaderSize;
    return mailbox_size > head ? mailbox_size - head : 0;
}

} // namespace codrive::ethercat
