// SPDX-License-Identifier: Apache-2.0
// Frames per second through VirtualBus and through SocketCanBus on vcan, next to a
// sendmmsg()/recvmmsg() loop on the same interface in the same run (the floor), interleaved.
//   bench_can_bus [IFACE] [FRAMES] [ROUNDS]   (IFACE default vcan0; fails if it cannot be opened)
#include <codrive/core/socket_can_bus.hpp>
#include <codrive/core/virtual_bus.hpp>

#include <fmt/format.h>

#include "floor_check.hpp"

#include <algorithm>
#include <array>
#include <chrono>
#include <cstring>
#include <linux/can.h>
#include <linux/can/raw.h>
#include <net/if.h>
#include <string>
#include <sys/socket.h>
#include <sys/uio.h>
#include <unistd.h>
#include <vector>

using namespace codrive;

namespace {

constexpr std::size_t kBurst = 64;

double seconds_since(std::chrono::steady_clock::time_point t0) {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

double bench_virtual(std::size_t frames) {
    FakeClock clock;
    VirtualNetwork net(clock);
    auto& a = net.endpoint("a");
    auto& b = net.endpoint("b");
    std::size_t got = 0;
    b.set_frame_handler([&](const Frame&, TimePoint) { ++got; });
    const Frame f = Frame::make(0x181, {1, 2, 3, 4, 5, 6, 7, 8});
    const auto t0 = std::chrono::steady_clock::now();
    for (std::size_t i = 0; i < frames; i += kBurst) {
        for (std::size_t k = 0; k < kBurst; ++k) {
            (void)a.send(f);
        }
        net.deliver();
    }
    const double s = seconds_since(t0);
    return static_cast<double>(got) / s;
}

int raw_socket(const std::string& ifname) {
    const int fd = ::socket(PF_CAN, SOCK_RAW, CAN_RAW);
    if (fd < 0) {
        return -1;
    }
    sockaddr_can addr{};
    addr.can_family = AF_CAN;
    addr.can_ifindex = static_cast<int>(if_nametoindex(ifname.c_str()));
    if (::bind(fd, reinterpret_cast<sockaddr*>(&addr), sizeof(addr)) < 0) {
        ::close(fd);
        return -1;
    }
    const int size = 4 * 1024 * 1024;
    setsockopt(fd, SOL_SOCKET, SO_RCVBUFFORCE, &size, sizeof(size));
    return fd;
}

// The floor: the best system calls Linux offers for this: one sendmmsg() of a whole burst on one
// socket, recvmmsg() batches on another until the burst is back. 0 on a socket error.
double bench_raw(const std::string& ifname, std::size_t frames) {
    const int tx = raw_socket(ifname);
    const int rx = raw_socket(ifname);
    if (tx < 0 || rx < 0) {
        return 0;
    }
    std::array<can_frame, kBurst> out{};
    std::array<can_frame, kBurst> in{};
    std::array<iovec, kBurst> out_iov{};
    std::array<iovec, kBurst> in_iov{};
    std::array<mmsghdr, kBurst> out_msg{};
    std::array<mmsghdr, kBurst> in_msg{};
    for (std::size_t k = 0; k < kBurst; ++k) {
        out[k].can_id = 0x181;
        out[k].len = 8;
        out_iov[k] = {&out[k], sizeof(can_frame)};
        in_iov[k] = {&in[k], sizeof(can_frame)};
        out_msg[k].msg_hdr.msg_iov = &out_iov[k];
        out_msg[k].msg_hdr.msg_iovlen = 1;
        in_msg[k].msg_hdr.msg_iov = &in_iov[k];
        in_msg[k].msg_hdr.msg_iovlen = 1;
    }
    const auto t0 = std::chrono::steady_clock::now();
    std::size_t got = 0;
    bool ok = true;
    for (std::size_t i = 0; ok && i < frames; i += kBurst) {
        std::size_t sent = 0;
        while (ok && sent < kBurst) {
            const int n = ::sendmmsg(tx, &out_msg[sent], static_cast<unsigned>(kBurst - sent), 0);
            ok = n > 0;
            sent += n > 0 ? static_cast<std::size_t>(n) : 0;
        }
        std::size_t back = 0;
        while (ok && back < kBurst) {
            // Blocks for the first frame, then takes whatever has arrived.
            const int n = ::recvmmsg(rx, in_msg.data(), static_cast<unsigned>(kBurst - back),
                                     MSG_WAITFORONE, nullptr);
            ok = n > 0;
            back += n > 0 ? static_cast<std::size_t>(n) : 0;
        }
        got += back;
    }
    const double s = seconds_since(t0);
    ::close(tx);
    ::close(rx);
    return ok ? static_cast<double>(got) / s : 0;
}

/// SocketCanBus both ways: bursts through send() frame by frame, or through send_many() (one
/// sendmmsg() per burst, as the controller sends a cycle's SYNC and RPDOs); received with
/// read_blocking() (the event loop's direct-read path: blocking recvmmsg() batches).
double bench_socketcan(const std::string& ifname, std::size_t frames, bool batched) {
    SocketCanOptions o;
    o.rcvbuf_bytes = 4 * 1024 * 1024;
    auto tx = SocketCanBus::open(ifname, o);
    auto rx = SocketCanBus::open(ifname, o);
    if (!tx || !rx) {
        return 0;
    }
    std::size_t got = 0;
    (*rx)->set_frame_handler([&](const Frame&, TimePoint) { ++got; });
    std::array<Frame, kBurst> burst{};
    burst.fill(Frame::make(0x181, {1, 2, 3, 4, 5, 6, 7, 8}));
    const auto t0 = std::chrono::steady_clock::now();
    for (std::size_t i = 0; i < frames; i += kBurst) {
        if (batched) {
            if ((*tx)->send_many(burst) != kBurst) {
                return 0;
            }
        } else {
            for (const Frame& f : burst) {
                if (!(*tx)->send(f)) {
                    return 0;
                }
            }
        }
        const std::size_t want = got + kBurst;
        while (got < want) {
            if ((*rx)->read_blocking().count == 0) {
                return 0; // nothing within the receive timeout: a frame was lost
            }
        }
    }
    const double s = seconds_since(t0);
    return static_cast<double>(got) / s;
}

} // namespace

int main(int argc, char** argv) {
    const std::string ifname = argc > 1 ? argv[1] : "vcan0";
    const std::size_t frames = argc > 2 ? std::stoul(argv[2]) : 200000;
    const std::size_t rounds = argc > 3 ? std::stoul(argv[3]) : 10;
    fmt::print("codrive bus benchmark: {} frames per path in bursts of {}, {} interleaved rounds\n",
               frames, kBurst, rounds);
    const double virt = bench_virtual(frames * 10);
    fmt::print("  VirtualBus (in-process)          {:>12.0f} frames/s\n", virt);
    auto probe = SocketCanBus::open(ifname);
    if (!probe) {
        fmt::print(stderr,
                   "bench_can_bus: cannot open {} ({}), so the SocketCAN figure and its floor "
                   "were not measured; run it where vcan exists: vcan-scripts/run-in-vcan.sh "
                   "{}\n",
                   ifname, probe.error().message(), argv[0]);
        return 1;
    }
    probe->reset();
    // Floor and stack alternate round by round so machine noise hits both alike; each round's
    // ratio is taken against the floor measured just before it.
    std::vector<double> raw_rates;
    std::vector<double> one_rates;
    std::vector<double> many_rates;
    std::vector<double> one_ratios;
    std::vector<double> many_ratios;
    const std::size_t per_round =
        std::max<std::size_t>(kBurst, frames / std::max<std::size_t>(rounds, 1));
    for (std::size_t round = 0; round < rounds; ++round) {
        const double raw = bench_raw(ifname, per_round);
        const double one = bench_socketcan(ifname, per_round, false);
        const double many = bench_socketcan(ifname, per_round, true);
        if (raw <= 0 || one <= 0 || many <= 0) {
            fmt::print(stderr, "bench_can_bus: a socket on {} failed or lost a frame in round {}\n",
                       ifname, round);
            return 1;
        }
        raw_rates.push_back(raw);
        one_rates.push_back(one);
        many_rates.push_back(many);
        one_ratios.push_back(one / raw);
        many_ratios.push_back(many / raw);
    }
    const bench::Spread one_ratio = bench::spread_of(one_ratios);
    const bench::Spread many_ratio = bench::spread_of(many_ratios);
    fmt::print("  sendmmsg()/recvmmsg() floor on {}         {} frames/s\n", ifname,
               bench::describe(bench::spread_of(raw_rates), 0));
    fmt::print("  SocketCanBus send() per frame on {}       {} frames/s\n", ifname,
               bench::describe(bench::spread_of(one_rates), 0));
    fmt::print("  SocketCanBus send_many() per burst on {}  {} frames/s\n", ifname,
               bench::describe(bench::spread_of(many_rates), 0));
    fmt::print("  send() per frame / floor = {}\n", bench::describe(one_ratio));
    fmt::print("  send_many() / floor      = {}  (target >= 0.80)\n", bench::describe(many_ratio));
    const bool one_ok = bench::floor_holds("SocketCanBus send() throughput", one_ratio.median);
    const bool many_ok =
        bench::floor_holds("SocketCanBus send_many() throughput", many_ratio.median);
    return one_ok && many_ok ? 0 : 1;
}
