// SPDX-License-Identifier: Apache-2.0
// SYNC period error: the codrive producer (EventLoop, timerfd absolute deadlines) next to the
// loop a careful user writes (clock_nanosleep(TIMER_ABSTIME) to start + k·period, then send),
// interleaved block by block in the same run on vcan0 if present, else in-process.
#include <codrive/core/event_loop.hpp>
#include <codrive/core/socket_can_bus.hpp>
#include <codrive/core/virtual_bus.hpp>
#include <codrive/sync/producer.hpp>

#include <fmt/format.h>

#include "floor_check.hpp"

#include <cstdlib>
#include <ctime>
#include <memory>
#include <string>
#include <sys/prctl.h>
#include <vector>

namespace {

using namespace codrive;

struct Options {
    std::uint64_t cycles = 10000;
    std::int64_t period_us = 1000;
    std::uint64_t rounds = 10;
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
        } else if (a == "--rounds" && has_value) {
            o.rounds = std::strtoull(argv[++i], nullptr, 10);
        } else if ((a == "--iface" || a == "-i") && has_value) {
            o.iface = argv[++i];
        } else {
            fmt::print(stderr, "usage: bench_sync_period [--cycles N] [--period-us US] "
                               "[--rounds N] [--iface IFACE]\n");
            return false;
        }
    }
    return o.cycles / std::max<std::uint64_t>(o.rounds, 1) >= 2 && o.period_us > 0;
}

double us(Duration d) {
    return std::chrono::duration<double, std::micro>(d).count();
}

/// One block of sends: the time each SYNC had been handed to the bus and its slot on the grid.
struct Block {
    std::vector<TimePoint> sent;
    std::vector<std::uint64_t> slot;
    TimePoint origin{};
    std::uint64_t skipped = 0;
    std::uint64_t send_errors = 0;
};

/// Everything one producer showed over all its blocks.
struct Side {
    std::vector<double> interval_error_us; ///< |t[k] - t[k-1] - T|, skipped slots included
    std::vector<double> lateness_us;       ///< t[k] - (origin + slot[k]·T)
    std::vector<double> round_p99_us;      ///< interval-error p99 per block (the spread)
    std::uint64_t sends = 0;
    std::uint64_t skipped = 0;
    std::uint64_t send_errors = 0;

    void add(const Block& b, Duration period) {
        std::vector<double> errors;
        for (std::size_t k = 0; k < b.sent.size(); ++k) {
            lateness_us.push_back(
                us(b.sent[k] - (b.origin + period * static_cast<std::int64_t>(b.slot[k]))));
            if (k > 0) {
                // A skipped slot stays in: its interval is n·T, its error (n-1)·T or more.
                const Duration e = (b.sent[k] - b.sent[k - 1]) - period;
                errors.push_back(us(e < Duration{0} ? -e : e));
            }
        }
        round_p99_us.push_back(bench::percentile(errors, 0.99));
        interval_error_us.insert(interval_error_us.end(), errors.begin(), errors.end());
        sends += b.sent.size();
        skipped += b.skipped;
        send_errors += b.send_errors;
    }
};

void print_row(const char* name, const Side& s) {
    fmt::print("{:<36} {:>8.1f} {:>8.1f} {:>8.1f} {:>10.1f} {:>10.1f} {:>8} {:>7}\n", name,
               bench::percentile(s.interval_error_us, 0.50),
               bench::percentile(s.interval_error_us, 0.99),
               bench::percentile(s.interval_error_us, 1.0), bench::percentile(s.lateness_us, 0.50),
               bench::percentile(s.lateness_us, 0.99), s.sends, s.skipped);
}

/// The careful user's loop: sleep to the absolute slot time, send, note the time after the send.
/// A wake-up later than a whole period sends once and skips the missed slots, as the producer.
Block floor_block(ICanBus& bus, VirtualNetwork* net, Duration period, std::uint64_t cycles) {
    Block b;
    b.origin = SteadyClock::now() + milliseconds(10);
    Frame sync_frame;
    sync_frame.id = 0x080;
    std::uint64_t slot = 0;
    while (b.sent.size() < cycles) {
        const TimePoint due = b.origin + period * static_cast<std::int64_t>(slot);
        const auto ns =
            std::chrono::duration_cast<std::chrono::nanoseconds>(due.time_since_epoch());
        timespec ts{};
        ts.tv_sec = static_cast<time_t>(ns.count() / 1'000'000'000);
        ts.tv_nsec = static_cast<long>(ns.count() % 1'000'000'000);
        while (::clock_nanosleep(CLOCK_MONOTONIC, TIMER_ABSTIME, &ts, nullptr) != 0) {
        }
        const TimePoint woke = SteadyClock::now();
        const auto behind = static_cast<std::uint64_t>((woke - due) / period);
        slot += behind;
        b.skipped += behind;
        if (!bus.send(sync_frame)) {
            ++b.send_errors;
        }
        b.sent.push_back(SteadyClock::now());
        b.slot.push_back(slot);
        if (net != nullptr) {
            net->deliver();
        }
        ++slot;
    }
    return b;
}

} // namespace

int main(int argc, char** argv) {
    Options o;
    if (!parse_args(argc, argv, o)) {
        return 2;
    }
    const Duration period = microseconds(o.period_us);
    const std::uint64_t per_block = o.cycles / o.rounds;
    // What a careful user does for a periodic loop on a normal-priority thread: no timer slack
    // (Linux otherwise lets a SCHED_OTHER sleep end up to 50 us late). It applies to both sides.
    ::prctl(PR_SET_TIMERSLACK, 1UL, 0UL, 0UL, 0UL);

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
    fmt::print("SYNC period error over {} cycles at {} us on {}: {} interleaved rounds of {} "
               "cycles per producer\n",
               per_block * o.rounds, o.period_us, bus_name, o.rounds, per_block);

    sync::SyncProducer producer(*bus);
    if (auto r = producer.configure({period, 0, 0x080}); !r) {
        fmt::print(stderr, "bench_sync_period: bad SYNC configuration: {}\n", r.error().message());
        return 1;
    }
    Block current;
    // Timed like the floor: after the SYNC was handed to the bus (the hook runs after send()).
    producer.set_hook([&](const sync::SyncInfo& info) {
        current.sent.push_back(SteadyClock::now());
        current.slot.push_back(info.cycle);
        if (current.sent.size() >= per_block) {
            producer.stop();
            loop.stop();
        }
    });
    loop.add_timed(&producer);

    Side codrive_side;
    Side floor_side;
    std::vector<double> ratios; ///< floor p99 / codrive p99 per round (above 1: codrive better)
    for (std::uint64_t r = 0; r < o.rounds; ++r) {
        current = Block{};
        current.sent.reserve(per_block);
        current.slot.reserve(per_block);
        const std::uint64_t skipped0 = producer.skipped();
        const std::uint64_t errors0 = producer.send_errors();
        current.origin = loop.now() + milliseconds(10);
        producer.start(current.origin);
        if (auto run = loop.run(); !run) {
            fmt::print(stderr, "bench_sync_period: event loop failed: {}\n", run.error().message());
            return 1;
        }
        current.skipped = producer.skipped() - skipped0;
        current.send_errors = producer.send_errors() - errors0;
        codrive_side.add(current, period);
        floor_side.add(floor_block(*bus, net.get(), period, per_block), period);
        if (can) {
            can->drain(seconds(2));
        }
        const double c = codrive_side.round_p99_us.back();
        ratios.push_back(c > 0 ? floor_side.round_p99_us.back() / c : 1.0);
    }
    loop.remove_timed(&producer);

    fmt::print("\nperiod error = |t[k] - t[k-1] - period| between consecutive sends (a skipped "
               "slot counts as a long interval); lateness = t[k] - (origin + slot[k]*period); "
               "t = after send()\n");
    fmt::print("{:<36} {:>8} {:>8} {:>8} {:>10} {:>10} {:>8} {:>7}\n", "producer", "p50 us",
               "p99 us", "max us", "late p50", "late p99", "sends", "skipped");
    print_row("codrive SyncProducer (timerfd)", codrive_side);
    print_row("floor: clock_nanosleep(TIMER_ABSTIME)", floor_side);
    fmt::print("per-round p99 period error, codrive: {} us\n",
               bench::describe(bench::spread_of(codrive_side.round_p99_us), 1));
    fmt::print("per-round p99 period error, floor:   {} us\n",
               bench::describe(bench::spread_of(floor_side.round_p99_us), 1));
    const bench::Spread ratio = bench::spread_of(ratios);
    fmt::print("floor p99 / codrive p99 per round: {} (1 = as good as the floor; below 1: "
               "codrive is worse)\n",
               bench::describe(ratio));
    fmt::print("send errors: codrive {}, floor {}\n", codrive_side.send_errors,
               floor_side.send_errors);
    return bench::floor_holds("the codrive SYNC period error (p99, inverted)", ratio.median) ? 0
                                                                                             : 1;
}
