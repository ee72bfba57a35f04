// SPDX-License-Identifier: Apache-2.0
// Shared by the SDO benchmarks: forked server processes (the raw echo floor and the codrive server
// on EventLoop + SocketCanBus) and the raw request/response floor's client loop.
#pragma once

#include <codrive/core/event_loop.hpp>
#include <codrive/core/object_dictionary.hpp>
#include <codrive/core/socket_can_bus.hpp>
#include <codrive/sdo/protocol.hpp>
#include <codrive/sdo/server.hpp>

#include <linux/can.h>
#include <linux/can/raw.h>
#include <net/if.h>
#include <sys/socket.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <csignal>
#include <functional>
#include <string>
#include <thread>

namespace codrive::bench {

using Clock = std::chrono::steady_clock;

constexpr int kClockEvery = 64; ///< round trips between clock reads in every client loop

inline double seconds_since(Clock::time_point t0) {
    return std::chrono::duration<double>(Clock::now() - t0).count();
}

/// A forked server process: `serve` runs in the child until it is killed; the constructor returns
/// once the child reported ready (serve calls the ready callback) or died.
class ServerProcess {
public:
    explicit ServerProcess(const std::function<void(const std::function<void()>& ready)>& serve) {
        int fds[2] = {-1, -1};
        if (::pipe(fds) != 0) {
            return;
        }
        pid_ = ::fork();
        if (pid_ == 0) {
            ::close(fds[0]);
            const int w = fds[1];
            serve([w] {
                const char one = 1;
                [[maybe_unused]] auto n = ::write(w, &one, 1);
            });
            ::_exit(1); // serve only returns on failure
        }
        ::close(fds[1]);
        char c = 0;
        ready_ = pid_ > 0 && ::read(fds[0], &c, 1) == 1;
        ::close(fds[0]);
    }
    ~ServerProcess() {
        if (pid_ > 0) {
            ::kill(pid_, SIGKILL);
            ::waitpid(pid_, nullptr, 0);
        }
    }
    ServerProcess(const ServerProcess&) = delete;
    ServerProcess& operator=(const ServerProcess&) = delete;
    [[nodiscard]] bool ready() const { return ready_; }

private:
    pid_t pid_ = -1;
    bool ready_ = false;
};

inline int raw_socket(const std::string& ifname, std::uint32_t rx_id) {
    const int fd = ::socket(PF_CAN, SOCK_RAW, CAN_RAW);
    if (fd < 0) {
        return -1;
    }
    can_filter f{rx_id, CAN_SFF_MASK | CAN_EFF_FLAG | CAN_RTR_FLAG};
    ::setsockopt(fd, SOL_CAN_RAW, CAN_RAW_FILTER, &f, sizeof f);
    sockaddr_can addr{};
    addr.can_family = AF_CAN;
    addr.can_ifindex = static_cast<int>(::if_nametoindex(ifname.c_str()));
    if (addr.can_ifindex == 0 ||
        ::bind(fd, reinterpret_cast<sockaddr*>(&addr), sizeof addr) != 0) { // NOLINT
        ::close(fd);
        return -1;
    }
    return fd;
}

inline bool raw_write(int fd, std::uint32_t id, std::uint8_t b0) {
    can_frame f{};
    f.can_id = id;
    f.len = 8;
    f.data[0] = b0;
    while (true) {
        if (::write(fd, &f, sizeof f) == static_cast<ssize_t>(sizeof f)) {
            return true;
        }
        if (errno != ENOBUFS && errno != EAGAIN && errno != EINTR) {
            return false;
        }
        std::this_thread::yield();
    }
}

inline bool raw_read(int fd) {
    can_frame f{};
    return ::read(fd, &f, sizeof f) == static_cast<ssize_t>(sizeof f);
}

/// Answers every request on `node`'s SDO identifiers (the expedited floor).
inline void raw_server(const std::string& ifname, NodeId node, const std::function<void()>& ready) {
    const int server = raw_socket(ifname, cob::sdo_rx(node));
    if (server < 0) {
        return;
    }
    ready();
    while (raw_read(server)) {
        raw_write(server, cob::sdo_tx(node), 0x60);
    }
}

/// Round trips per second of write() + blocking read() against raw_server() on `node`; `client`
/// is a raw_socket() receiving `node`'s responses.
inline double raw_round_trips(int client, NodeId node, double seconds) {
    const auto t0 = Clock::now();
    std::uint64_t rt = 0;
    while (seconds_since(t0) < seconds) {
        for (int i = 0; i < kClockEvery; ++i) {
            raw_write(client, cob::sdo_rx(node), 0x40);
            raw_read(client);
        }
        rt += kClockEvery;
    }
    return static_cast<double>(rt) / seconds_since(t0);
}

inline ObjectDictionary bench_dictionary() {
    ObjectDictionary od;
    od.add_var(0x1018, "Vendor-ID", DataType::Unsigned32, Access::Ro,
               Value(DataType::Unsigned32, {1, 2, 3, 4}));
    od.add_var(0x2001, "Domain", DataType::Domain, Access::Rw, Value(DataType::Domain, {}));
    return od;
}

/// SocketCanBus options for one side of `node`'s SDO channel. `direct` false turns the loop's
/// direct-read fast path off, as a second watched fd (a signalfd, another bus) would.
inline SocketCanOptions bus_options(std::uint32_t rx_id, bool direct) {
    SocketCanOptions so;
    so.filters = {CanFilter{rx_id, 0x7FF, false, false}};
    so.error_frames = false;
    if (!direct) {
        so.direct_read_limit = Duration::zero();
    }
    return so;
}

/// The codrive SDO server on EventLoop + SocketCanBus (an application's own loop).
inline void codrive_server(const std::string& ifname, NodeId node, bool direct,
                           const std::function<void()>& ready) {
    ObjectDictionary od = bench_dictionary();
    auto loop = EventLoop::create();
    auto bus = SocketCanBus::open(ifname, bus_options(cob::sdo_rx(node), direct));
    if (!loop || !bus || !(*bus)->attach(**loop)) {
        return;
    }
    sdo::ServerConfig config;
    config.node = node;
    sdo::SdoServer server(od, **bus, config);
    (*bus)->set_frame_handler(
        [&server](const Frame& f, TimePoint t) { (void)server.on_frame(f, t); });
    (*loop)->add_timed(&server);
    ready();
    (void)(*loop)->run();
}

} // namespace codrive::bench
