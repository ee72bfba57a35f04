// SPDX-License-Identifier: Apache-2.0
// The EMCY message (CiA 301 §7.2.7.3.1): error code, error register, 5 manufacturer bytes.
#pragma once

#include <codrive/core/cob_id.hpp>
#include <codrive/core/error.hpp>
#include <codrive/core/frame.hpp>

#include <array>
#include <cstdint>
#include <string>

namespace codrive::emcy {

class IEmcyTextProvider;

/// One EMCY as decoded from the wire.
struct EmcyMessage {
    NodeId node = 0;
    std::uint16_t error_code = 0;               ///< bytes 0..1, little-endian
    std::uint8_t error_register = 0;            ///< byte 2 (1001h)
    std::array<std::uint8_t, 5> manufacturer{}; ///< bytes 3..7
    std::uint8_t length = 8;                    ///< bytes on the wire (CiA 301 requires 8)

    /// Error code 0000h: "error reset or no error" — the node has no active error any more.
    [[nodiscard]] bool is_reset() const { return error_code == 0; }
    friend bool operator==(const EmcyMessage&, const EmcyMessage&) = default;
};

/// Decodes an EMCY on 081h..0FFh (predefined connection set). A frame shorter than 8 bytes is
/// accepted if it has at least the error code and register (missing manufacturer bytes read 0;
/// `length` tells). Errors: InvalidFrame for other ids, RTR, extended or error frames, or fewer
/// than 3 bytes.
[[nodiscard]] Result<EmcyMessage> parse_emcy(const Frame& frame);
/// As parse_emcy for a configured COB-ID (1014h) of a known node.
[[nodiscard]] Result<EmcyMessage> parse_emcy(const Frame& frame, NodeId node);

/// The 8-byte frame on `cob_id` (default 080h + node).
[[nodiscard]] Frame make_emcy_frame(const EmcyMessage& message, std::uint32_t cob_id = 0);

/// The sentence: "node 3: EMCY 0x2310 continuous over-current (error register 0x03: generic,
/// current) [manufacturer 00 01 02 03 04]". With a provider that knows the code, its text
/// follows the standard text: "... DC link over-voltage: F2006 Bus over voltage (...)".
[[nodiscard]] std::string describe(const EmcyMessage& message,
                                   const IEmcyTextProvider* vendor = nullptr);

} // namespace codrive::emcy
