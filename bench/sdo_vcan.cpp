// SPDX-License-Identifier: Apache-2.0
// SDO on vcan: codrive client/server round trips and block throughput next to a raw-socket floor.
//
// Usage: bench_sdo_vcan [IFACE] [SECONDS]   (default vcan0, 3 s per figure)
// Client and server live in one process on two sockets, each with its own thread, so the floor
// (a plain request/response loop over two raw sockets, same threads) pays the same scheduling.
#include <codrive/core/event_loop.hpp>
#include <codrive/core/object_dictionary.hpp>
#include <codrive/core/socket_can_bus.hpp>
#include <codrive/sdo/client.hpp>
#include <codrive/sdo/server.hpp>

#include <fmt/format.h>
#include <linux/can.h>
#include <linux/can/raw.h>
#include <net/if.h>
#include <sys/socket.h>
#include <unistd.h>

#include <atomic>
#include <cstdlib>
#include <cstring>
#include <optional>
#include <string>
#include <thread>

using namespace codrive;
using Clock = std::chrono::steady_clock;

namespace {

constexpr NodeId kNode = 100;

// ---- raw floor -----------------------------------------------------------------------------

int raw_socket(const std::string& ifname, std::uint32_t rx_id) {
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

bool raw_write(int fd, std::uint32_t id, std::uint8_t b0) {
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

bool raw_read(int fd) {
    can_frame f{};
    return ::read(fd, &f, sizeof f) == static_cast<ssize_t>(sizeof f);
}

/// Request/response pairs per second with a minimal echo server (the expedited floor), and
/// one-way frames per second in bursts of 127 acknowledged by one frame (the block floor).
struct Floor {
    double round_trips_per_s = 0;
    double block_frames_per_s = 0;
};

Floor measure_floor(const std::string& ifname, double seconds) {
    Floor out;
    const int client = raw_socket(ifname, cob::sdo_tx(kNode));
    const int server = raw_socket(ifname, cob::sdo_rx(kNode));
    if (client < 0 || server < 0) {
        return out;
    }
    std::atomic<bool> stop{false};
    std::atomic<int> mode{0}; // 0: echo every frame, 1: ack every 127th
    std::thread srv([&] {
        unsigned n = 0;
        while (!stop) {
            if (!raw_read(server)) {
                break;
            }
            if (mode == 0 || ++n % 127 == 0) {
                raw_write(server, cob::sdo_tx(kNode), 0x60);
            }
        }
    });
    auto t0 = Clock::now();
    std::uint64_t rt = 0;
    while (std::chrono::duration<double>(Clock::now() - t0).count() < seconds) {
        raw_write(client, cob::sdo_rx(kNode), 0x40);
        raw_read(client);
        ++rt;
    }
    out.round_trips_per_s =
        static_cast<double>(rt) / std::chrono::duration<double>(Clock::now() - t0).count();
    mode = 1;
    t0 = Clock::now();
    std::uint64_t frames = 0;
    while (std::chrono::duration<double>(Clock::now() - t0).count() < seconds) {
        for (int i = 0; i < 127; ++i) {
            raw_write(client, cob::sdo_rx(kNode), static_cast<std::uint8_t>(i + 1));
        }
        raw_read(client);
        frames += 127;
    }
    out.block_frames_per_s =
        static_cast<double>(frames) / std::chrono::duration<double>(Clock::now() - t0).count();
    stop = true;
    raw_write(client, cob::sdo_rx(kNode), 0); // wake the server thread
    srv.join();
    ::close(client);
    ::close(server);
    return out;
}

// ---- codrive state machines over raw sockets --------------------------------------------------
// The same SdoClient/SdoServer, driven by blocking read() loops instead of EventLoop +
// SocketCanBus: separates the SDO module's cost from the I/O layer's.

/// A clock read once per 256 frames: deadlines need milliseconds, not a system call per frame.
class CachedClock final : public IClock {
public:
    [[nodiscard]] TimePoint now() const override { return now_; }
    void tick() {
        if (++count_ % 256 == 0 || now_ == TimePoint{}) {
            now_ = SteadyClock::now();
        }
    }

private:
    TimePoint now_{};
    unsigned count_ = 0;
};

class RawBus final : public ICanBus {
public:
    explicit RawBus(int fd) : fd_(fd) {}
    VoidResult send(const Frame& frame) override {
        can_frame f{};
        f.can_id = frame.id;
        f.len = frame.len;
        std::memcpy(f.data, frame.data.data(), frame.len);
        while (::write(fd_, &f, sizeof f) != static_cast<ssize_t>(sizeof f)) {
            if (errno != ENOBUFS && errno != EAGAIN && errno != EINTR) {
                return fail_errno(errno);
            }
            std::this_thread::yield();
        }
        return {};
    }
    void set_frame_handler(FrameHandler) override {}
    void set_event_handler(EventHandler) override {}
    [[nodiscard]] std::size_t tx_pending() const override { return 0; }
    [[nodiscard]] const BusStats& stats() const override { return stats_; }
    [[nodiscard]] const std::string& name() const override { return name_; }
    /// Blocks for one frame.
    bool receive(Frame& out) const {
        can_frame f{};
        if (::read(fd_, &f, sizeof f) != static_cast<ssize_t>(sizeof f)) {
            return false;
        }
        out = Frame::make(f.can_id & CAN_SFF_MASK, std::span<const std::uint8_t>(f.data, f.len));
        return true;
    }

private:
    int fd_;
    BusStats stats_;
    std::string name_ = "raw";
};

double state_machine_round_trips(const std::string& ifname, double seconds) {
    const int cfd = raw_socket(ifname, cob::sdo_tx(kNode));
    const int sfd = raw_socket(ifname, cob::sdo_rx(kNode));
    if (cfd < 0 || sfd < 0) {
        return 0;
    }
    std::atomic<bool> stop{false};
    std::thread srv([&] {
        ObjectDictionary od;
        od.add_var(0x1018, "Vendor-ID", DataType::Unsigned32, Access::Ro,
                   Value(DataType::Unsigned32, {1, 2, 3, 4}));
        RawBus bus(sfd);
        CachedClock clock;
        sdo::ServerConfig config;
        config.node = kNode;
        sdo::SdoServer server(od, bus, config);
        Frame f;
        while (!stop && bus.receive(f)) {
            clock.tick();
            (void)server.on_frame(f, clock.now());
        }
    });
    RawBus bus(cfd);
    CachedClock clock;
    clock.tick();
    sdo::ClientConfig config;
    config.node = kNode;
    sdo::SdoClient client(bus, clock, config);
    std::uint64_t done = 0;
    bool ok = true;
    const auto t0 = Clock::now();
    while (ok && std::chrono::duration<double>(Clock::now() - t0).count() < seconds) {
        // 256 requests between clock reads, like the loops above.
        for (int i = 0; i < 256 && ok; ++i) {
            bool finished = false;
            client.upload(0x1018, 0, [&](sdo::SdoResult<sdo::Bytes> r) {
                ok = r.has_value();
                finished = true;
            });
            Frame f;
            while (!finished && bus.receive(f)) {
                clock.tick();
                (void)client.on_frame(f, clock.now());
            }
            ++done;
        }
    }
    const double rate =
        static_cast<double>(done) / std::chrono::duration<double>(Clock::now() - t0).count();
    stop = true;
    raw_write(cfd, cob::sdo_rx(kNode), 0x80); // an abort: wakes the server, changes nothing
    srv.join();
    ::close(cfd);
    ::close(sfd);
    return ok ? rate : 0;
}

// ---- codrive ---------------------------------------------------------------------------------

struct ServerThread {
    explicit ServerThread(const std::string& ifname) {
        od.add_var(0x1018, "Vendor-ID", DataType::Unsigned32, Access::Ro,
                   Value(DataType::Unsigned32, {1, 2, 3, 4}));
        od.add_var(0x2001, "Domain", DataType::Domain, Access::Rw, Value(DataType::Domain, {}));
        thread = std::thread([this, ifname] {
            auto made = EventLoop::create();
            SocketCanOptions so;
            so.filters = {CanFilter{cob::sdo_rx(kNode), 0x7FF, false, false}};
            so.error_frames = false;
            auto bus = SocketCanBus::open(ifname, so);
            if (!made || !bus || !(*bus)->attach(**made)) {
                failed = true;
                ready = true;
                return;
            }
            sdo::ServerConfig config;
            config.node = kNode;
            sdo::SdoServer server(od, **bus, config);
            (*bus)->set_frame_handler(
                [&server](const Frame& f, TimePoint t) { (void)server.on_frame(f, t); });
            (*made)->add_timed(&server);
            loop = made->get();
            ready = true;
            (void)(*made)->run();
            (*made)->remove_timed(&server);
            (*bus)->detach();
        });
        while (!ready) {
            std::this_thread::yield();
        }
    }
    ~ServerThread() {
        if (EventLoop* l = loop.load(); l != nullptr) {
            l->stop();
        }
        thread.join();
    }
    ObjectDictionary od;
    std::thread thread;
    std::atomic<bool> ready{false};
    std::atomic<bool> failed{false};
    std::atomic<EventLoop*> loop{nullptr};
};

struct ClientSide {
    std::unique_ptr<EventLoop> loop;
    std::unique_ptr<SocketCanBus> bus;
    std::unique_ptr<sdo::SdoClient> client;
};

std::optional<ClientSide> open_client(const std::string& ifname) {
    ClientSide c;
    auto loop = EventLoop::create();
    SocketCanOptions so;
    so.filters = {CanFilter{cob::sdo_tx(kNode), 0x7FF, false, false}};
    so.error_frames = false;
    auto bus = SocketCanBus::open(ifname, so);
    if (!loop || !bus) {
        return std::nullopt;
    }
    c.loop = std::move(*loop);
    c.bus = std::move(*bus);
    if (!c.bus->attach(*c.loop)) {
        return std::nullopt;
    }
    sdo::ClientConfig config;
    config.node = kNode;
    c.client = std::make_unique<sdo::SdoClient>(*c.bus, RealClock::instance(), config);
    sdo::SdoClient* client = c.client.get();
    c.bus->set_frame_handler(
        [client](const Frame& f, TimePoint t) { (void)client->on_frame(f, t); });
    c.loop->add_timed(client);
    return c;
}

double expedited_round_trips(ClientSide& c, double seconds) {
    std::uint64_t done = 0;
    bool failed = false;
    const auto t0 = Clock::now();
    const auto end =
        t0 + std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(seconds));
    std::function<void(sdo::SdoResult<sdo::Bytes>)> next;
    bool finished = false;
    next = [&](sdo::SdoResult<sdo::Bytes> r) {
        if (!r) {
            fmt::print(stderr, "{}\n", r.error().to_string());
            failed = true;
        }
        ++done;
        if (failed || Clock::now() >= end) {
            finished = true;
            return;
        }
        c.client->upload(0x1018, 0, next);
    };
    c.client->upload(0x1018, 0, next);
    c.loop->run_until([&] { return finished; }, std::chrono::seconds(600));
    return failed ? 0
                  : static_cast<double>(done) /
                        std::chrono::duration<double>(Clock::now() - t0).count();
}

/// KiB/s of one block transfer of `size` bytes (download then upload of 0x2001).
std::pair<double, double> block_kib_s(ClientSide& c, std::size_t size) {
    sdo::Bytes data(size);
    for (std::size_t i = 0; i < size; ++i) {
        data[i] = static_cast<std::uint8_t>(i * 7U);
    }
    sdo::TransferOptions o;
    o.mode = sdo::Mode::Block;
    std::optional<sdo::SdoResult<void>> w;
    auto t0 = Clock::now();
    c.client->download(
        0x2001, 0, data, [&](sdo::SdoResult<void> r) { w = r; }, o);
    c.loop->run_until([&] { return w.has_value(); }, std::chrono::seconds(600));
    const double down_s = std::chrono::duration<double>(Clock::now() - t0).count();
    if (!w || !*w) {
        fmt::print(stderr, "block download failed: {}\n", w ? w->error().to_string() : "hung");
        return {0, 0};
    }
    std::optional<sdo::SdoResult<sdo::Bytes>> r;
    t0 = Clock::now();
    c.client->upload(
        0x2001, 0, [&](sdo::SdoResult<sdo::Bytes> x) { r = std::move(x); }, o);
    c.loop->run_until([&] { return r.has_value(); }, std::chrono::seconds(600));
    const double up_s = std::chrono::duration<double>(Clock::now() - t0).count();
    if (!r || !*r || r->value() != data) {
        fmt::print(stderr, "block upload failed: {}\n",
                   r && !*r ? r->error().to_string() : std::string("data mismatch or hung"));
        return {0, 0};
    }
    const double kib = static_cast<double>(size) / 1024.0;
    return {kib / down_s, kib / up_s};
}

} // namespace

int main(int argc, char** argv) {
    const std::string ifname = argc > 1 ? argv[1] : "vcan0";
    const double seconds = argc > 2 ? std::atof(argv[2]) : 3.0;
    if (!socketcan_available()) {
        fmt::print(stderr, "bench_sdo_vcan: no SocketCAN here; run through "
                           "vcan-scripts/run-in-vcan.sh\n");
        return 2;
    }
    const Floor floor = measure_floor(ifname, seconds);
    if (floor.round_trips_per_s == 0) {
        fmt::print(stderr, "bench_sdo_vcan: cannot open raw sockets on {}\n", ifname);
        return 2;
    }
    const double sm_rt = state_machine_round_trips(ifname, seconds);
    ServerThread server(ifname);
    if (server.failed) {
        fmt::print(stderr, "bench_sdo_vcan: server could not open {}\n", ifname);
        return 2;
    }
    auto client = open_client(ifname);
    if (!client) {
        fmt::print(stderr, "bench_sdo_vcan: client could not open {}\n", ifname);
        return 2;
    }
    const double rt = expedited_round_trips(*client, seconds);
    constexpr std::size_t kBlockBytes = 1024 * 1024;
    const auto [down, up] = block_kib_s(*client, kBlockBytes);
    // A block transfer of N bytes moves ceil(N / 7) segment frames one way.
    const auto frames_per_s = [](double kib_s) { return kib_s * 1024.0 / 7.0; };

    fmt::print("SDO on {} ({} s per figure, client and server in one process, two threads)\n",
               ifname, seconds);
    fmt::print("  floor: raw request/response        {:>10.0f} round trips/s\n",
               floor.round_trips_per_s);
    fmt::print("  codrive SDO state machines, raw I/O {:>9.0f} round trips/s   ratio {:.2f} "
               "(target >= 0.90)\n",
               sm_rt, sm_rt / floor.round_trips_per_s);
    fmt::print("  codrive full stack (EventLoop)     {:>10.0f} round trips/s   ratio {:.2f}\n", rt,
               rt / floor.round_trips_per_s);
    fmt::print("  floor: raw 127-frame bursts + ack  {:>10.0f} frames/s ({:.0f} KiB/s of "
               "7-byte payload)\n",
               floor.block_frames_per_s, floor.block_frames_per_s * 7.0 / 1024.0);
    fmt::print("  codrive block download (1 MiB)    {:>10.0f} KiB/s  {:>8.0f} frames/s   "
               "efficiency {:.2f}\n",
               down, frames_per_s(down), frames_per_s(down) / floor.block_frames_per_s);
    fmt::print("  codrive block upload (1 MiB)       {:>10.0f} KiB/s  {:>8.0f} frames/s   "
               "efficiency {:.2f}\n",
               up, frames_per_s(up), frames_per_s(up) / floor.block_frames_per_s);
    return 0;
}
