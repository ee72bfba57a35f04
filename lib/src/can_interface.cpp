// SPDX-License-Identifier: Apache-2.0
// CAN interface control via libsocketcan (netlink), with errors that say what is missing.
#include <codrive/core/can_interface.hpp>

#include <cerrno>
#include <fmt/format.h>
#include <libsocketcan.h>
#include <linux/can/netlink.h>
#include <net/if.h>
#include <sys/ioctl.h>
#include <sys/socket.h>
#include <unistd.h>

namespace codrive {
namespace {

// libsocketcan returns -1 and leaves errno from the netlink exchange (often 0 when the device
// simply lacks the attribute, as vcan lacks bit timing).
std::error_code interface_error(const std::string& name) {
    if (if_nametoindex(name.c_str()) == 0) {
        return make_error_code(CoreErrc::NoSuchInterface);
    }
    if (errno == EPERM || errno == EACCES) {
        return make_error_code(CoreErrc::NotPermitted);
    }
    return make_error_code(CoreErrc::NotSupported);
}

bool link_up(const std::string& name) {
    const int fd = ::socket(AF_INET, SOCK_DGRAM | SOCK_CLOEXEC, 0);
    if (fd < 0) {
        return false;
    }
    ifreq req{};
    name.copy(req.ifr_name, IFNAMSIZ - 1);
    const bool up = ::ioctl(fd, SIOCGIFFLAGS, &req) == 0 && (req.ifr_flags & IFF_UP) != 0;
    ::close(fd);
    return up;
}

} // namespace

bool CanInterface::exists() const {
    return if_nametoindex(name_.c_str()) != 0;
}

Result<CanInterfaceInfo> CanInterface::info() const {
    if (!exists()) {
        return fail(CoreErrc::NoSuchInterface);
    }
    CanInterfaceInfo info;
    info.name = name_;
    info.up = link_up(name_);
    can_bittiming bt{};
    if (can_get_bittiming(name_.c_str(), &bt) == 0 && bt.bitrate != 0) {
        info.bitrate = bt.bitrate;
    }
    int state = 0;
    if (can_get_state(name_.c_str(), &state) == 0) {
        switch (state) {
        case CAN_STATE_ERROR_ACTIVE:
            info.state = BusState::ErrorActive;
            break;
        case CAN_STATE_ERROR_WARNING:
            info.state = BusState::ErrorWarning;
            break;
        case CAN_STATE_ERROR_PASSIVE:
            info.state = BusState::ErrorPassive;
            break;
        case CAN_STATE_BUS_OFF:
            info.state = BusState::BusOff;
            break;
        default:
            break;
        }
    }
    can_berr_counter bc{};
    if (can_get_berr_counter(name_.c_str(), &bc) == 0) {
        info.tx_errors = bc.txerr;
        info.rx_errors = bc.rxerr;
    }
    __u32 restart_ms = 0;
    if (can_get_restart_ms(name_.c_str(), &restart_ms) == 0) {
        info.restart_ms = restart_ms;
    }
    return info;
}

VoidResult CanInterface::set_bitrate(std::uint32_t bitrate) const {
    errno = 0;
    if (can_set_bitrate(name_.c_str(), bitrate) != 0) {
        return fail(interface_error(name_));
    }
    return {};
}

VoidResult CanInterface::set_up(bool up) const {
    errno = 0;
    const int r = up ? can_do_start(name_.c_str()) : can_do_stop(name_.c_str());
    if (r != 0) {
        return fail(interface_error(name_));
    }
    return {};
}

VoidResult CanInterface::restart() const {
    errno = 0;
    if (can_do_restart(name_.c_str()) != 0) {
        return fail(interface_error(name_));
    }
    return {};
}

VoidResult CanInterface::set_restart_ms(std::uint32_t ms) const {
    errno = 0;
    if (can_set_restart_ms(name_.c_str(), ms) != 0) {
        return fail(interface_error(name_));
    }
    return {};
}

std::string describe_interface_error(const std::string& ifname, std::string_view action,
                                     const std::error_code& ec) {
    std::string hint;
    if (ec == CoreErrc::NotSupported && ifname.rfind("vcan", 0) == 0) {
        hint = " (a virtual CAN interface has no bit timing or controller state)";
    } else if (ec == CoreErrc::NotPermitted) {
        hint = " (run as root or grant CAP_NET_ADMIN)";
    } else if (ec == CoreErrc::NoSuchInterface) {
        hint = " (check `ip link show`)";
    }
    return fmt::format("{}: cannot {}: {}{}", ifname, action, ec.message(), hint);
}

} // namespace codrive
