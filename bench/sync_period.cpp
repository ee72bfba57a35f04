// SPDX-License-Identifier: Apache-2.0
// SYNC period error: the codrive producer (EventLoop, timerfd absolute deadlines) next to a
// naive sleep_for(period) loop, measured in the same run on vcan0 if present, else in-process.
#include <codrive/core/event_loop.hpp>
#include <codrive/core/socket_can_bus.hpp>
#include <codrive/core/virtual_bus.hpp>
#include <codrive/sync/period_stats.hpp>
#include <codrive/sync/producer.hpp>

#include <fmt/format.h>

#include <cstdlib>
#include <cstring>
#include <memory>
#include <string>
#include <thread>
#include <vector>

namespace {

using namespace codrive;
using sync::PeriodStats;
using sync::to_us;

struct Options {
    std::uint64_t cycles = 10000;
    std::int64_t period_us = 1000;
    std::string iface = "vcan0";
};

bool parse_args(int argc, char** argv, Options& o) {
    for (int i = 1; i < argc; ++i) {
        const std::string a = argv[i];
        const bool has_value = i + 1 < argc;
        if (a == "--cycles" && has_value) {
            o.cycles = std::strtoull(argv[++i], nullptr, 10);
        } else if (a == "--period-us" && has_value) {
            o.period_us = std::strtoll(argv[++i], nullptr, 10);
        } else if ((a == "--iface" || a == "-i") && has_value) {
            o.iface = argv[++i];
        } else {
            fmt::print(stderr,
                       "usage: bench_sync_period [--cycles N] [--period-us US] [--iface IFACE]\n");
            return false;
        }
    }
    return o.cycles >= 2 && o.period_us > 0;
}

/// Interval and drift figures from a series of send times.
struct Series {
    PeriodStats interval_error{microseconds(1)}; ///< |t[k] - t[k-1] - T|
    Duration drift{0}; ///< t[last] - (origin + slot[last]·T): how far the cycle slid
};

/// `slot[k]` is the cycle index of send k (consecutive unless a producer skipped slots); only
/// consecutive slots give an interval, and drift compares with the slot's place on the grid.
Series analyse(const std::vector<TimePoint>& t, const std::vector<std::uint64_t>& slot,
               TimePoint origin, Duration period) {
    Series s;
    for (std::size_t k = 1; k < t.size(); ++k) {
        if (slot[k] != slot[k - 1] + 1) {
            continue;
        }
        const Duration e = (t[k] - t[k - 1]) - period;
        s.interval_error.add(e < Duration{0} ? -e : e);
    }
    s.drift = t.back() - (origin + period * static_cast<std::int64_t>(slot.back()));
    return s;
}

void print_row(const char* name, const Series& s) {
    fmt::print("{:<34} {:>9.1f} {:>9.1f} {:>9.1f} {:>14.1f}\n", name, to_us(s.interval_error.p50()),
               to_us(s.interval_error.p99()), to_us(s.interval_error.max()), to_us(s.drift));
}

} // namespace

int main(int argc, char** argv) {
    Options o;
    if (!parse_args(argc, argv, o)) {
        return 2;
    }
    const Duration period = microseconds(o.period_us);

    auto loop_r = EventLoop::create();
    if (!loop_r) {
        fmt::print(stderr, "bench_sync_period: cannot create the event loop: {}\n",
                   loop_r.error().message());
        return 1;
    }
    auto& loop = **loop_r;

    // The bus: vcan if this kernel has it, else the in-process network on the real clock.
    std::unique_ptr<SocketCanBus> can;
    std::unique_ptr<VirtualNetwork> net;
    ICanBus* bus = nullptr;
    std::string bus_name;
    if (socketcan_available()) {
        SocketCanOptions so;
        so.filters = {CanFilter{0x7FF, 0x7FF}}; // we only send
        if (auto b = SocketCanBus::open(o.iface, so)) {
            can = std::move(*b);
            if (auto r = can->attach(loop); !r) {
                fmt::print(stderr, "bench_sync_period: cannot attach {}: {}\n", o.iface,
                           r.error().message());
                return 1;
            }
            bus = can.get();
            bus_name = o.iface + " (SocketCAN)";
        }
    }
    if (bus == nullptr) {
        net = std::make_unique<VirtualNetwork>(RealClock::instance());
        bus = &net->endpoint("master");
        net->endpoint("sink");
        loop.add_timed(net.get());
        bus_name = "virtual network (no SocketCAN / no " + o.iface + ")";
    }

    fmt::print("SYNC period error over {} cycles at {} us on {}\n", o.cycles, o.period_us,
               bus_name);

    // 1. codrive SyncProducer on the event loop (timerfd armed at start + k·period).
    sync::SyncProducer producer(*bus);
    if (auto r = producer.configure({period, 0, 0x080}); !r) {
        fmt::print(stderr, "bench_sync_period: bad SYNC configuration: {}\n", r.error().message());
        return 1;
    }
    std::vector<TimePoint> codrive_times;
    std::vector<std::uint64_t> codrive_slots;
    codrive_times.reserve(o.cycles);
    codrive_slots.reserve(o.cycles);
    producer.set_hook([&](const sync::SyncInfo& info) {
        codrive_times.push_back(info.actual);
        codrive_slots.push_back(info.cycle);
        if (codrive_times.size() >= o.cycles) {
            producer.stop();
            loop.stop();
        }
    });
    loop.add_timed(&producer);
    const TimePoint codrive_origin = loop.now() + milliseconds(10);
    producer.start(codrive_origin);
    if (auto r = loop.run(); !r) {
        fmt::print(stderr, "bench_sync_period: event loop failed: {}\n", r.error().message());
        return 1;
    }
    loop.remove_timed(&producer);

    // 2. The naive producer: send, then sleep_for(period), on the same bus.
    std::vector<TimePoint> naive_times;
    naive_times.reserve(o.cycles);
    Frame sync_frame;
    sync_frame.id = 0x080;
    std::uint64_t naive_send_errors = 0;
    for (std::uint64_t k = 0; k < o.cycles; ++k) {
        if (!bus->send(sync_frame)) {
            ++naive_send_errors;
        }
        naive_times.push_back(SteadyClock::now());
        if (net) {
            net->deliver();
        }
        std::this_thread::sleep_for(period);
    }
    if (can) {
        can->drain(seconds(2));
    }

    std::vector<std::uint64_t> naive_slots(naive_times.size());
    for (std::size_t k = 0; k < naive_slots.size(); ++k) {
        naive_slots[k] = k;
    }
    const Series c = analyse(codrive_times, codrive_slots, codrive_origin, period);
    const Series n = analyse(naive_times, naive_slots, naive_times.front(), period);
    fmt::print(
        "\nperiod error = |t[k] - t[k-1] - period| over consecutive slots; drift = "
        "t[last] - (origin + slot[last]*period), origin = the producer's start time (naive: its "
        "first send)\n");
    fmt::print("{:<34} {:>9} {:>9} {:>9} {:>14}\n", "producer", "p50 us", "p99 us", "max us",
               "drift us");
    print_row("codrive SyncProducer (timerfd)", c);
    print_row("naive sleep_for loop", n);
    const auto& own = producer.period_error();
    fmt::print("\ncodrive producer's own statistics (send time - ideal time start + k*period):\n"
               "  {}\n",
               own.summary());
    fmt::print("  SYNC sent {}, slots skipped {}, send errors {}; naive send errors {}\n",
               producer.sent(), producer.skipped(), producer.send_errors(), naive_send_errors);
    return 0;
}
