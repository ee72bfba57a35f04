// SPDX-License-Identifier: Apache-2.0
// File access over EtherCAT (FoE, ETG.1000.5 §5.7 / ETG.1000.6 §5.7, mailbox type 4): opcodes,
// the 6-byte FoE header, error codes with their texts; shared by the master and the simulator.
#pragma once

#include <codrive/core/time.hpp>

#include <cstddef>
#include <cstdint>
#include <functional>
#include <optional>
#include <span>
#include <string>
#include <system_error>
#include <vector>

namespace codrive::ethercat {

/// FoE operation codes (ETG.1000.6 Table "FoE OpCode"), the first byte of every FoE message.
enum class FoeOpcode : std::uint8_t {
    ReadRequest = 1,  ///< RRQ: password, file name
    WriteRequest = 2, ///< WRQ: password, file name
    Data = 3,         ///< packet number, data
    Ack = 4,          ///< packet number
    Error = 5,        ///< error code, error text
    Busy = 6,         ///< done, entire, busy text
};

/// Opcode (1 byte), reserved (1 byte), then one 32-bit field: password (RRQ/WRQ), packet number
/// (DATA/ACK), error code (ERR) or done/entire as two 16-bit words (BUSY).
inline constexpr std::size_t kFoeHeaderSize = 6;

/// FoE error codes (ETG.1000.6 Table "FoE error codes"). Anything the slave sends is kept as
/// it came; these are the ones the standard names.
namespace foe_error {
inline constexpr std::uint32_t kNotDefined = 0x8000;
inline constexpr std::uint32_t kNotFound = 0x8001;
inline constexpr std::uint32_t kAccessDenied = 0x8002;
inline constexpr std::uint32_t kDiskFull = 0x8003;
inline constexpr std::uint32_t kIllegal = 0x8004;
inline constexpr std::uint32_t kPacketNumberWrong = 0x8005;
inline constexpr std::uint32_t kAlreadyExists = 0x8006;
inline constexpr std::uint32_t kNoUser = 0x8007;
inline constexpr std::uint32_t kBootstrapOnly = 0x8008;
inline constexpr std::uint32_t kNotBootstrap = 0x8009;
inline constexpr std::uint32_t kNoRights = 0x800A;
inline constexpr std::uint32_t kProgramError = 0x800B;
} // namespace foe_error

/// "not found", "access denied", ... ("unknown FoE error" otherwise).
[[nodiscard]] const char* foe_error_text(std::uint32_t code);
/// FoE error codes as std::error_code (value = the code on the wire).
const std::error_category& foe_category();
[[nodiscard]] inline std::error_code make_foe_error(std::uint32_t code) {
    return {static_cast<int>(code), foe_category()};
}

/// One FoE message as read from a mailbox payload.
struct FoeMessage {
    FoeOpcode opcode = FoeOpcode::Data;
    std::uint32_t value = 0;              ///< password, packet number or error code
    std::uint16_t done = 0;               ///< BUSY only (the low word of `value`)
    std::uint16_t entire = 0;             ///< BUSY only (the high word of `value`)
    std::span<const std::uint8_t> body{}; ///< file name, data, error or busy text
};

/// Decodes an FoE payload (FoE header first); nullopt if shorter than the header or the opcode
/// is not one of the six.
[[nodiscard]] std::optional<FoeMessage> decode_foe(std::span<const std::uint8_t> payload);
/// Builds an FoE payload into `out` (cleared first): header with `value`, then `body`.
void encode_foe(std::vector<std::uint8_t>& out, FoeOpcode opcode, std::uint32_t value,
                std::span<const std::uint8_t> body = {});
/// BUSY carries done/entire instead of one 32-bit value.
[[nodiscard]] inline std::uint32_t foe_busy_value(std::uint16_t done, std::uint16_t entire) {
    return static_cast<std::uint32_t>(done) | (static_cast<std::uint32_t>(entire) << 16);
}
/// Data bytes one DATA message carries in a mailbox of `mailbox_size` bytes: the mailbox minus
/// the mailbox header and the FoE header. A DATA with fewer ends the file (ETG.1000.6 §5.7).
[[nodiscard]] std::size_t foe_max_data(std::size_t mailbox_size);

/// Options of an FoE transfer.
struct FoeOptions {
    std::uint32_t password = 0; ///< sent in RRQ/WRQ; 0 when the slave asks for none
    /// Called as bytes move (from the call that processes the cycle's frame): bytes so far and
    /// the file size when known (writes), nullopt for reads.
    std::function<void(std::size_t done, std::optional<std::size_t> total)> progress;
    /// How long a slave may keep answering BUSY before the transfer fails.
    Duration busy_timeout = seconds(10);
    /// A read that grows past this fails (and the slave is told with ERR 0x8003).
    std::size_t max_read_bytes = 64U * 1024U * 1024U;
};

} // namespace codrive::ethercat
