// SPDX-License-Identifier: Apache-2.0
// Shared helpers for `codrive` subcommands.
#include "cli_common.hpp"

#include <codrive/core/value.hpp>

#include <fmt/format.h>

#include <atomic>
#include <csignal>
#include <unistd.h>

namespace codrive::cli {

std::optional<BusSession> open_bus(const std::string& ifname, SocketCanOptions options) {
    auto loop = EventLoop::create();
    if (!loop) {
        fmt::print(stderr, "codrive: cannot create event loop: {}\n", loop.error().message());
        return std::nullopt;
    }
    auto bus = SocketCanBus::open(ifname, std::move(options));
    if (!bus) {
        fmt::print(stderr, "codrive: {}\n", describe_can_open_error(ifname, bus.error()));
        return std::nullopt;
    }
    if (auto r = (*bus)->attach(**loop); !r) {
        fmt::print(stderr, "codrive: cannot watch {}: {}\n", ifname, r.error().message());
        return std::nullopt;
    }
    return BusSession{std::move(*loop), std::move(*bus)};
}

std::optional<MasterSession> open_master(const std::string& ifname) {
    auto s = open_bus(ifname);
    if (!s) {
        return std::nullopt;
    }
    MasterSession ms;
    ms.loop = std::move(s->loop);
    ms.bus = std::move(s->bus);
    ms.master = std::make_unique<master::Master>(*ms.bus, RealClock::instance());
    ms.loop->add_timed(ms.master.get());
    return ms;
}

std::optional<unsigned> parse_node(const std::string& text, bool allow_all) {
    if (allow_all && text == "all") {
        return 0U;
    }
    auto v = parse_uint(text);
    if (!v || *v < 1 || *v > 127) {
        fmt::print(stderr, "codrive: node id must be 1..127{}, not '{}'\n",
                   allow_all ? " or 'all'" : "", text);
        return std::nullopt;
    }
    return static_cast<unsigned>(*v);
}

bool stderr_is_tty() {
    return ::isatty(2) != 0;
}

namespace {
std::atomic<int> g_stop_signal{0};
static_assert(std::atomic<int>::is_always_lock_free, "written by a signal handler");
extern "C" void on_stop_signal(int sig) {
    int none = 0;
    (void)g_stop_signal.compare_exchange_strong(none, sig);
}
} // namespace

void catch_stop_signals() {
    struct sigaction sa {};
    sa.sa_handler = on_stop_signal;
    sigemptyset(&sa.sa_mask);
    sa.sa_flags = SA_RESTART;
    (void)::sigaction(SIGINT, &sa, nullptr);
    (void)::sigaction(SIGTERM, &sa, nullptr);
}

int stop_signal() {
    return g_stop_signal.load();
}

bool stop_requested() {
    return stop_signal() != 0;
}

const char* signal_name(int sig) {
    return sig == SIGTERM ? "SIGTERM" : "SIGINT";
}

} // namespace codrive::cli
