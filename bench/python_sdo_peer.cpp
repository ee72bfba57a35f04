// SPDX-License-Identifier: Apache-2.0
// The C++ side of bench/python_sdo.py: the servers, the C++ blocking client and the raw floor,
// each figure measured on request so the Python script can interleave them with its own.
//
// Usage: bench_python_sdo_peer FLOOR_IFACE CPP_IFACE [SERVER_IFACE...]
// Starts, in forked child processes, a raw echo server for node kNode on FLOOR_IFACE and a codrive
// SDO server (EventLoop + SocketCanBus) for kNode on CPP_IFACE and on each SERVER_IFACE (one for
// every Python client measured); prints "ready <node>" once they all listen. Then reads commands
// from stdin, one per line, and answers each with one line holding round trips per second (0 when a
// transfer failed):
//   cpp SECONDS    expedited uploads of 1018h:00 through sdo::BlockingSdo (what `codrive sdo`
//                  and the Python module use) on CPP_IFACE
//   floor SECONDS  write() + blocking read() on raw sockets on FLOOR_IFACE
// End of input ends the program and its servers. Each figure has an interface of its own, so no
// socket ever holds another figure's frames (BlockingSdo and the Python bus receive every frame
// of their interface).
#include <codrive/sdo/blocking.hpp>

#include <fmt/format.h>
#include <fmt/ranges.h>

#include "sdo_servers.hpp"

#include <cstdio>
#include <iostream>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

using namespace codrive;
using namespace codrive::bench;

namespace {

constexpr NodeId kNode = 100;

/// Expedited uploads per second through the blocking client; 0 when one failed.
double blocking_round_trips(sdo::BlockingSdo& sdo, double seconds) {
    std::uint64_t done = 0;
    const auto t0 = Clock::now();
    while (seconds_since(t0) < seconds) {
        for (int i = 0; i < kClockEvery; ++i) {
            auto r = sdo.read<std::uint32_t>(kNode, 0x1018, 0);
            if (!r) {
                fmt::print(stderr, "bench_python_sdo_peer: {}\n", r.error().to_string());
                return 0;
            }
        }
        done += kClockEvery;
    }
    return static_cast<double>(done) / seconds_since(t0);
}

} // namespace

int main(int argc, char** argv) {
    if (argc < 3) {
        fmt::print(stderr,
                   "usage: bench_python_sdo_peer FLOOR_IFACE CPP_IFACE [SERVER_IFACE...]\n");
        return 2;
    }
    const std::string floor_if = argv[1];
    const std::string cpp_if = argv[2];
    const std::vector<std::string> server_ifs(argv + 2, argv + argc); // CPP_IFACE and the rest
    if (!socketcan_available()) {
        fmt::print(stderr, "bench_python_sdo_peer: no SocketCAN here; run through "
                           "vcan-scripts/run-in-vcan.sh\n");
        return 2;
    }
    std::vector<std::unique_ptr<ServerProcess>> servers;
    servers.push_back(std::make_unique<ServerProcess>(
        [&](const auto& ready) { raw_server(floor_if, kNode, ready); }));
    for (const std::string& ifname : server_ifs) {
        servers.push_back(std::make_unique<ServerProcess>(
            [&](const auto& ready) { codrive_server(ifname, kNode, true, ready); }));
    }
    for (const auto& s : servers) {
        if (!s->ready()) {
            fmt::print(stderr,
                       "bench_python_sdo_peer: a server could not open its interface "
                       "(floor {}, codrive {})\n",
                       floor_if, fmt::join(server_ifs, ", "));
            return 2;
        }
    }
    auto sdo = sdo::BlockingSdo::open(cpp_if);
    const int floor_fd = raw_socket(floor_if, cob::sdo_tx(kNode));
    if (!sdo || floor_fd < 0) {
        fmt::print(stderr, "bench_python_sdo_peer: cannot open the client sockets\n");
        return 2;
    }
    fmt::print("ready {}\n", kNode);
    std::fflush(stdout);
    std::string line;
    while (std::getline(std::cin, line)) {
        std::istringstream in(line);
        std::string what;
        double seconds = 0;
        in >> what >> seconds;
        double rate = -1;
        if (what == "cpp") {
            rate = blocking_round_trips(**sdo, seconds);
        } else if (what == "floor") {
            rate = raw_round_trips(floor_fd, kNode, seconds);
        } else {
            fmt::print(stderr, "bench_python_sdo_peer: unknown command '{}'\n", line);
            return 2;
        }
        fmt::print("{:.1f}\n", rate);
        std::fflush(stdout);
    }
    ::close(floor_fd);
    return 0;
}
