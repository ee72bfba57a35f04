// SPDX-License-Identifier: Apache-2.0
// SDO transfer failures: client-side error codes and SdoError, which reads as one sentence.
#pragma once

#include <codrive/core/cob_id.hpp>
#include <codrive/core/error.hpp>
#include <codrive/core/sdo_abort.hpp>
#include <codrive/core/time.hpp>

#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <system_error>

namespace codrive::sdo {

/// Failures the client detects itself (server aborts use the core SdoAbort category).
enum class SdoErrc {
    Timeout = 1,        ///< no response within the request timeout
    NodeRebooted,       ///< boot-up message from the node during the transfer
    WrongObject,        ///< response for a different index/subindex
    ProtocolError,      ///< invalid response; the client aborted with the code in SdoError
    SendFailed,         ///< the bus refused the request
    Cancelled,          ///< cancelled by the application or the client was destroyed
    LocalTransferError, ///< the caller's data sink or source failed
    SizeMismatch,       ///< typed read: the object has a different size than the type
    TooLarge,           ///< more than 4 GiB - 1 bytes (the SDO size field is 32 bits)
};

const std::error_category& sdo_category();
std::error_code make_error_code(SdoErrc e);

/// Direction of a transfer, seen from the client (CiA 301 wording).
enum class Direction : std::uint8_t { Upload, Download };
/// The SDO protocol a transfer used. Unknown: an upload whose initiate response never came.
enum class Protocol : std::uint8_t { Unknown, Expedited, Segmented, Block };

[[nodiscard]] std::string_view to_string(Direction d); ///< "upload", "download"
[[nodiscard]] std::string_view to_string(Protocol p);  ///< "expedited", "segmented", "block", ""

/// Who ended the transfer with an abort frame, if anyone.
enum class AbortOrigin : std::uint8_t { None, Server, Client };

/// A failed SDO transfer with everything needed to explain it.
struct SdoError {
    NodeId node = 0;
    std::uint16_t index = 0;
    std::uint8_t subindex = 0;
    Direction direction = Direction::Upload;
    Protocol protocol = Protocol::Unknown;
    /// SdoErrc, or an SdoAbort (sdo_abort_category, any 32-bit value incl. vendor codes).
    std::error_code cause;
    AbortOrigin origin = AbortOrigin::None;
    Duration timeout{0}; ///< the timeout that expired (SdoErrc::Timeout)
    std::string detail;  ///< the phase or the discrepancy, without a trailing period

    /// The abort code sent or received, if the transfer ended with an abort frame.
    [[nodiscard]] std::optional<std::uint32_t> abort_code() const;

    /// One sentence, e.g. "node 4: SDO upload 0x6064:00 timed out after 1000 ms (no response
    /// to initiate request)" or "node 4: SDO upload 0x6064:00 aborted by server: 0x06020000
    /// object does not exist in the object dictionary".
    [[nodiscard]] std::string to_string() const;
};

} // namespace codrive::sdo

template <>
struct std::is_error_code_enum<codrive::sdo::SdoErrc> : std::true_type {};
