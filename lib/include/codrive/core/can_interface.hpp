// SPDX-License-Identifier: Apache-2.0
// CAN interface control through libsocketcan: bitrate, state, restart, error counters.
#pragma once

#include <codrive/core/can_bus.hpp>
#include <codrive/core/error.hpp>

#include <cstdint>
#include <optional>
#include <string>

namespace codrive {

struct CanInterfaceInfo {
    std::string name;
    bool up = false;
    std::optional<std::uint32_t> bitrate; ///< nullopt where the device has none (vcan)
    std::optional<BusState> state;        ///< nullopt where the device reports none (vcan)
    std::optional<std::uint16_t> tx_errors;
    std::optional<std::uint16_t> rx_errors;
    std::optional<std::uint32_t> restart_ms;
};

/// Control of one CAN network interface. Each call names the interface and the cause on error:
/// NotPermitted (needs CAP_NET_ADMIN), NotSupported (e.g. vcan has no bitrate), NoSuchInterface.
class CanInterface {
public:
    explicit CanInterface(std::string name) : name_(std::move(name)) {}
    [[nodiscard]] Result<CanInterfaceInfo> info() const;
    [[nodiscard]] VoidResult set_bitrate(std::uint32_t bitrate) const;
    [[nodiscard]] VoidResult set_up(bool up) const;
    [[nodiscard]] VoidResult restart() const;
    [[nodiscard]] VoidResult set_restart_ms(std::uint32_t ms) const;
    [[nodiscard]] bool exists() const;
    [[nodiscard]] const std::string& name() const { return name_; }

private:
    std::string name_;
};

/// A readable sentence for an interface-control error: "vcan0: cannot set bitrate: not supported
/// by this device (virtual CAN has no bitrate)".
[[nodiscard]] std::string describe_interface_error(const std::string& ifname,
                                                   std::string_view action,
                                                   const std::error_code& ec);

} // namespace codrive
