// SPDX-License-Identifier: Apache-2.0
// AF_PACKET raw socket link for EtherCAT frames (Linux packet(7)).
#include <codrive/ethercat/datagram.hpp>
#include <codrive/ethercat/error.hpp>
#include <codrive/ethercat/raw_socket_link.hpp>

#include <fmt/format.h>

#include <arpa/inet.h>
#include <cerrno>
#include <ctime>
#include <linux/if_packet.h>
#include <net/ethernet.h>
#include <net/if.h>
#include <poll.h>
#include <sys/ioctl.h>
#include <sys/socket.h>
#include <thread>
#include <unistd.h>

#ifndef PACKET_IGNORE_OUTGOING
#define PACKET_IGNORE_OUTGOING 23
#endif

namespace codrive::ethercat {

Result<std::unique_ptr<RawSocketLink>> RawSocketLink::open(const std::string& ifname) {
    const int fd = ::socket(AF_PACKET, SOCK_RAW | SOCK_NONBLOCK | SOCK_CLOEXEC, htons(kEthertype));
    if (fd < 0) {
        if (errno == EPERM || errno == EACCES) {
            return fail(EcatErrc::PermissionDenied);
        }
        return fail_errno(errno);
    }
    const unsigned index = ::if_nametoindex(ifname.c_str());
    if (index == 0) {
        ::close(fd);
        return fail(CoreErrc::NoSuchInterface);
    }
    ifreq ifr{};
    ifname.copy(ifr.ifr_name, IFNAMSIZ - 1);
    if (::ioctl(fd, SIOCGIFFLAGS, &ifr) == 0 && (ifr.ifr_flags & IFF_UP) == 0) {
        ::close(fd);
        return fail(CoreErrc::InterfaceDown);
    }
    int one = 1;
    // Our own transmissions must not come back as if the segment had answered them.
    ::setsockopt(fd, SOL_PACKET, PACKET_IGNORE_OUTGOING, &one, sizeof(one));
    int rcvbuf = 1 << 20;
    ::setsockopt(fd, SOL_SOCKET, SO_RCVBUF, &rcvbuf, sizeof(rcvbuf));
    sockaddr_ll addr{};
    addr.sll_family = AF_PACKET;
    addr.sll_protocol = htons(kEthertype);
    addr.sll_ifindex = static_cast<int>(index);
    if (::bind(fd, reinterpret_cast<sockaddr*>(&addr), sizeof(addr)) != 0) {
        const int err = errno;
        ::close(fd);
        return fail_errno(err);
    }
    return std::unique_ptr<RawSocketLink>(new RawSocketLink(fd, ifname));
}

RawSocketLink::~RawSocketLink() {
    if (fd_ >= 0) {
        ::close(fd_);
    }
}

VoidResult RawSocketLink::send(std::span<const std::uint8_t> frame) {
    if (tap_) {
        tap_(frame, true);
    }
    bool stale_checked = false;
    while (true) {
        const ssize_t n = ::send(fd_, frame.data(), frame.size(), 0);
        if (n >= 0) {
            return {};
        }
        if (errno == EINTR) {
            continue;
        }
        // ENOBUFS (the interface's queue dropped the frame) and EAGAIN (the socket's send
        // buffer is full) are returned at once: the link never waits for room. The cyclic path
        // must not block, and a transmit queue that stays full (a NIC whose transmission hangs,
        // a shaper) would hold any wait here for as long as it lasts. The master decides:
        // the cycle goes on without this frame; a blocking exchange counts it as a lost attempt.
        const int err = errno;
        if (err == ENETDOWN) {
            // The interface went down with this socket bound to it, so the kernel also left
            // ENETDOWN pending on the socket (sk_err, set by af_packet's NETDEV_DOWN notifier).
            // The next send that allocates, or receive that finds no frame, would return it:
            // the first cycle after the interface is back up would fail on the fault already
            // reported here. Reading SO_ERROR clears it. If the interface went down and came
            // back with no send in between, this error was that stale one: send once more.
            int pending = 0;
            socklen_t len = sizeof(pending);
            (void)::getsockopt(fd_, SOL_SOCKET, SO_ERROR, &pending, &len);
            if (!stale_checked && interface_up()) {
                stale_checked = true;
                continue;
            }
        }
        return fail_errno(err);
    }
}

Result<std::size_t> RawSocketLink::receive(std::span<std::uint8_t> buffer, TimePoint deadline) {
    while (true) {
        sockaddr_ll from{};
        socklen_t from_len = sizeof(from);
        const ssize_t n = ::recvfrom(fd_, buffer.data(), buffer.size(), MSG_TRUNC,
                                     reinterpret_cast<sockaddr*>(&from), &from_len);
        if (n >= 0) {
            if (from.sll_pkttype == PACKET_OUTGOING) {
                continue; // kernels without PACKET_IGNORE_OUTGOING
            }
            const auto len = std::min(static_cast<std::size_t>(n), buffer.size());
            if (tap_) {
                tap_(buffer.first(len), false);
            }
            return len;
        }
        if (errno == EINTR) {
            continue;
        }
        if (errno != EAGAIN && errno != EWOULDBLOCK) {
            return fail_errno(errno);
        }
        const auto now = SteadyClock::now();
        if (now >= deadline) {
            return fail(CoreErrc::Timeout);
        }
        const auto left = std::chrono::duration_cast<nanoseconds>(deadline - now);
        timespec ts{};
        ts.tv_sec = static_cast<time_t>(left.count() / 1'000'000'000);
        ts.tv_nsec = static_cast<long>(left.count() % 1'000'000'000);
        pollfd p{fd_, POLLIN, 0};
        ::ppoll(&p, 1, &ts, nullptr);
    }
}

bool RawSocketLink::interface_up() const {
    ifreq ifr{};
    ifname_.copy(ifr.ifr_name, sizeof(ifr.ifr_name) - 1);
    return ::ioctl(fd_, SIOCGIFFLAGS, &ifr) == 0 && (ifr.ifr_flags & IFF_UP) != 0;
}

void RawSocketLink::idle(Duration d) {
    std::this_thread::sleep_for(d);
}

std::string RawSocketLink::describe_open_error(const std::string& ifname,
                                               const std::error_code& ec) {
    if (ec == EcatErrc::PermissionDenied) {
        return fmt::format("cannot open a raw EtherCAT socket on {}: opening AF_PACKET sockets "
                           "needs CAP_NET_RAW (run as root, or `setcap cap_net_raw+ep` the binary)",
                           ifname);
    }
    if (ec == CoreErrc::NoSuchInterface) {
        return fmt::format("cannot open a raw EtherCAT socket on {}: there is no such network "
                           "interface",
                           ifname);
    }
    if (ec == CoreErrc::InterfaceDown) {
        return fmt::format("cannot open a raw EtherCAT socket on {}: the interface is down "
                           "(`ip link set {} up`)",
                           ifname, ifname);
    }
    return fmt::format("cannot open a raw EtherCAT socket on {}: {}", ifname, ec.message());
}

} // namespace codrive::ethercat
