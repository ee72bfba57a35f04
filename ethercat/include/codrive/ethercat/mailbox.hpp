// SPDX-License-Identifier: Apache-2.0
// Mailbox and CoE framing (ETG.1000.6 §5.6 mailbox, §5.6.2 CoE): headers, SDO command bytes,
// SDO information opcodes, emergency payload.
#pragma once

#include <codrive/core/error.hpp>

#include <cstdint>
#include <optional>
#include <span>
#include <vector>

namespace codrive::ethercat {

inline constexpr std::size_t kMailboxHeaderSize = 6;
inline constexpr std::size_t kCoeHeaderSize = 2;
/// Mailbox header + CoE header + SDO command/index/subindex + 4 data bytes.
inline constexpr std::size_t kSdoMinimumMailbox = kMailboxHeaderSize + kCoeHeaderSize + 8;

enum class MailboxType : std::uint8_t {
    Error = 0x00,
    Aoe = 0x01,
    Eoe = 0x02,
    Coe = 0x03,
    Foe = 0x04,
    Soe = 0x05,
    Voe = 0x0F,
};

/// The 6-byte mailbox header (ETG.1000.6 Table 29).
struct MailboxHeader {
    std::uint16_t length = 0; ///< bytes after the header
    std::uint16_t address = 0;
    std::uint8_t channel = 0;
    std::uint8_t priority = 0;
    MailboxType type = MailboxType::Coe;
    std::uint8_t counter = 0; ///< 1..7, 0 = not used (ETG.1000.6 §5.6.1)

    void encode(std::uint8_t* out) const;
    static MailboxHeader decode(const std::uint8_t* in);
};

/// CoE services (ETG.1000.6 Table 37), in the top 4 bits of the CoE header.
enum class CoeService : std::uint8_t {
    Emergency = 1,
    SdoRequest = 2,
    SdoResponse = 3,
    TxPdo = 4,
    RxPdo = 5,
    TxPdoRemoteRequest = 6,
    RxPdoRemoteRequest = 7,
    SdoInformation = 8,
};

[[nodiscard]] inline std::uint16_t coe_header(CoeService s, std::uint16_t number = 0) {
    return static_cast<std::uint16_t>((number & 0x01FF) | (static_cast<unsigned>(s) << 12));
}
[[nodiscard]] inline CoeService coe_service(std::uint16_t header) {
    return static_cast<CoeService>(header >> 12);
}

/// SDO information opcodes (ETG.1000.6 Table 42), low 7 bits; bit 7 = "incomplete" (more
/// fragments follow).
namespace sdo_info {
inline constexpr std::uint8_t kGetOdListReq = 0x01;
inline constexpr std::uint8_t kGetOdListResp = 0x02;
inline constexpr std::uint8_t kGetObjectDescReq = 0x03;
inline constexpr std::uint8_t kGetObjectDescResp = 0x04;
inline constexpr std::uint8_t kGetEntryDescReq = 0x05;
inline constexpr std::uint8_t kGetEntryDescResp = 0x06;
inline constexpr std::uint8_t kErrorReq = 0x07;
inline constexpr std::uint8_t kIncomplete = 0x80;
inline constexpr std::uint16_t kListAll = 0x0001;
inline constexpr std::size_t kHeaderSize = 4; ///< opcode, reserved, fragments left (u16)
} // namespace sdo_info

/// A whole mailbox message: header plus payload. `encode` pads to the SM size of the receiver
/// (the master must write the whole SM0 buffer so its last byte marks it full).
struct MailboxMessage {
    MailboxHeader header;
    std::vector<std::uint8_t> payload;

    [[nodiscard]] std::vector<std::uint8_t> encode(std::size_t pad_to = 0) const;
    /// Decodes a mailbox buffer read from SM1. Errors: MailboxError if the header length runs
    /// past the buffer.
    static Result<MailboxMessage> decode(std::span<const std::uint8_t> buffer);
};

/// Mailbox error reply codes (ETG.1000.6 Table 30): "syntax", "unsupported protocol", ...
[[nodiscard]] const char* mailbox_error_text(std::uint16_t code);

} // namespace codrive::ethercat
