// SPDX-License-Identifier: Apache-2.0
// A CAN / CAN FD frame: identifier, flags and up to 64 data bytes.
#pragma once

#include <array>
#include <cstdint>
#include <span>
#include <string>
#include <string_view>

namespace codrive {

/// One CAN or CAN FD frame. Trivially copyable, fixed size, no allocation.
struct Frame {
    static constexpr std::size_t kMaxClassicLen = 8;
    static constexpr std::size_t kMaxFdLen = 64;
    static constexpr std::uint32_t kStdMask = 0x7FF;
    static constexpr std::uint32_t kExtMask = 0x1FFFFFFF;

    enum Flags : std::uint8_t {
        kExtended = 1U << 0, ///< 29-bit identifier
        kRtr = 1U << 1,      ///< remote transmission request
        kFd = 1U << 2,       ///< CAN FD frame
        kBrs = 1U << 3,      ///< CAN FD bit-rate switch
        kError = 1U << 4,    ///< SocketCAN error frame (id holds CAN_ERR_* class bits)
    };

    std::uint32_t id = 0;
    std::uint8_t len = 0; ///< payload length in bytes (DLC 0..8, or FD length up to 64)
    std::uint8_t flags = 0;
    std::array<std::uint8_t, kMaxFdLen> data{};

    [[nodiscard]] bool extended() const { return (flags & kExtended) != 0; }
    [[nodiscard]] bool rtr() const { return (flags & kRtr) != 0; }
    [[nodiscard]] bool fd() const { return (flags & kFd) != 0; }
    [[nodiscard]] bool error() const { return (flags & kError) != 0; }
    [[nodiscard]] std::span<const std::uint8_t> payload() const { return {data.data(), len}; }
    [[nodiscard]] std::span<std::uint8_t> payload() { return {data.data(), len}; }

    /// A classic 11-bit data frame with the given bytes (at most 8; longer input is cut).
    static Frame make(std::uint32_t id, std::span<const std::uint8_t> bytes);
    static Frame make(std::uint32_t id, std::initializer_list<std::uint8_t> bytes);
    /// A classic 11-bit remote frame requesting `len` bytes.
    static Frame make_rtr(std::uint32_t id, std::uint8_t len = 0);

    /// True if id, flags, length and the used payload bytes are valid for the frame kind.
    [[nodiscard]] bool valid() const;

    friend bool operator==(const Frame& a, const Frame& b);
};

/// CAN FD DLC code (0..15) for a payload length, rounding up to the next valid FD length.
std::uint8_t fd_len_to_dlc(std::size_t len);
/// Payload length for a CAN FD DLC code.
std::size_t fd_dlc_to_len(std::uint8_t dlc);

/// candump-style text: "123#11223344", "12345678#", "123#R", "123##1AABB".
std::string to_string(const Frame& f);

/// Parses candump / cansend frame text (the inverse of to_string): "123#11223344",
/// "123#11.22.33", "1F334455#", "123#R", "123#R3", "123##1AABB". An 8-digit id is a 29-bit frame.
/// Returns false (and leaves `out` untouched) for anything else.
[[nodiscard]] bool parse_frame(std::string_view text, Frame& out);

} // namespace codrive
