// SPDX-License-Identifier: Apache-2.0
// CAN interface control via libsocketcan (netlink), with errors that say what is missing.
#include <codrive/core/can_interface.hpp>

#include <cerrno>
#include <cstring>
#include <fmt/format.h>
#include <libsocketcan.h>
#include <linux/can/netlink.h>
#include <linux/if_link.h>
#include <linux/netlink.h>
#include <linux/rtnetlink.h>
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

// The link kind rtnetlink reports (IFLA_LINKINFO / IFLA_INFO_KIND): "can" for a can-dev
// controller, "vcan", "vxcan", ...; empty if it cannot be read. Only "can" links carry the CAN
// link data (bit timing, state, error counters) libsocketcan asks for: for any other kind
// libsocketcan prints "no link data found" to stderr once per query, so those are not asked.
std::string link_kind(const std::string& name) {
    const unsigned index = if_nametoindex(name.c_str());
    const int fd = ::socket(AF_NETLINK, SOCK_RAW | SOCK_CLOEXEC, NETLINK_ROUTE);
    if (index == 0 || fd < 0) {
        if (fd >= 0) {
            ::close(fd);
        }
        return {};
    }
    struct {
        nlmsghdr header;
        ifinfomsg info;
    } request{};
    request.header.nlmsg_len = NLMSG_LENGTH(sizeof(ifinfomsg));
    request.header.nlmsg_type = RTM_GETLINK;
    request.header.nlmsg_flags = NLM_F_REQUEST;
    request.header.nlmsg_seq = 1;
    request.info.ifi_family = AF_UNSPEC;
    request.info.ifi_index = static_cast<int>(index);
    std::string kind;
    alignas(nlmsghdr) char buffer[16384];
    if (::send(fd, &request, request.header.nlmsg_len, 0) >= 0) {
        const ssize_t got = ::recv(fd, buffer, sizeof buffer, 0);
        auto* h = reinterpret_cast<nlmsghdr*>(buffer);
        if (got > 0 && NLMSG_OK(h, static_cast<unsigned>(got)) && h->nlmsg_type == RTM_NEWLINK) {
            auto* info = static_cast<ifinfomsg*>(NLMSG_DATA(h));
            int len = static_cast<int>(h->nlmsg_len) - static_cast<int>(NLMSG_LENGTH(sizeof *info));
            for (auto* a = IFLA_RTA(info); RTA_OK(a, len); a = RTA_NEXT(a, len)) {
                if (a->rta_type != IFLA_LINKINFO) {
                    continue;
                }
                int inner = static_cast<int>(RTA_PAYLOAD(a));
                for (auto* k = static_cast<rtattr*>(RTA_DATA(a)); RTA_OK(k, inner);
                     k = RTA_NEXT(k, inner)) {
                    if (k->rta_type == IFLA_INFO_KIND) {
                        kind.assign(
                            static_cast<const char*>(RTA_DATA(k)),
                            ::strnlen(static_cast<const char*>(RTA_DATA(k)), RTA_PAYLOAD(k)));
                    }
                }
            }
        }
    }
    ::close(fd);
    return kind;
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
    if (link_kind(name_) != "can") {
        return info; // vcan, vxcan: no bit timing, state or error counters to report
    }
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
