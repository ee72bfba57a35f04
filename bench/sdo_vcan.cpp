// SPDX-License-Identifier: Apache-2.0
// SDO on vcan: codrive client/server round trips and block throughput next to a raw-socket floor.
//
// Usage: bench_sdo_vcan [IFACE] [SECONDS] [FIGURE]   (default vcan0, 3 s per figure, all)
// FIGURE is all, floor, raw-sm, full, full-epoll or block: one figure alone, e.g. under
// `strace -f -c`. full-epoll is the full stack with the event loop's direct-read fast path off
// (what a loop watching a second fd gets).
// Every server runs in a forked child process on its own socket and node-ID, the clients in this
// process, so the floor (a plain request/response loop over raw sockets) pays the same process
// switches. The round-trip figures are measured in interleaved 0.25 s slices (floor, state
// machines, full stack, floor, ...) so a load change on a shared machine hits all of them alike;
// each ratio is the median of the per-slice ratios to the floor slice next to it, printed with the
// slices' extremes. The block figures alternate the same way: a 0.5 s floor slice (127-frame
// sendmmsg() bursts, each acknowledged; only acknowledged bursts count), then a 64 KiB block
// download and upload. A ratio above 1.05 to its floor fails the program: such a floor is wrong.
#include <codrive/core/event_loop.hpp>
#include <codrive/core/object_dictionary.hpp>
#include <codrive/core/socket_can_bus.hpp>
#include <codrive/sdo/client.hpp>
#include <codrive/sdo/protocol.hpp>
#include <codrive/sdo/server.hpp>

#include <fmt/format.h>

#include "floor_check.hpp"
#include "sdo_servers.hpp"

#include <linux/can.h>
#include <linux/can/raw.h>
#include <net/if.h>
#include <sys/socket.h>
#include <sys/uio.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <csignal>
#include <cstdlib>
#include <cstring>
#include <optional>
#include <string>
#include <thread>
#include <vector>

using namespace codrive;
using namespace codrive::bench;

namespace {

// One node-ID per server so that all servers can run at once.
constexpr NodeId kFullNode = 100;       ///< codrive server on EventLoop + SocketCanBus
constexpr NodeId kFloorNode = 101;      ///< raw echo server
constexpr NodeId kSmNode = 102;         ///< codrive SdoServer driven by blocking read()
constexpr NodeId kEpollNode = 103;      ///< codrive server, EventLoop direct-read fast path off
constexpr NodeId kBlockFloorNode = 104; ///< raw block-floor server (acks each 127-frame burst)
constexpr int kBlockSize = sdo::kMaxBlockSize; ///< segments per block, as codrive asks for
constexpr double kSlice = 0.25;                ///< seconds per interleaved slice

// ---- raw block floor (the expedited floor and the servers are in sdo_servers.hpp) ----------

/// The block floor's receiver: takes frames in recvmmsg() batches (as SocketCanBus does) and
/// acknowledges a burst when its last frame (sequence number kBlockSize) arrives, like a block
/// download server; a burst that lost a frame still ends with that frame's ack.
void raw_block_server(const std::string& ifname, const std::function<void()>& ready) {
    const int server = raw_socket(ifname, cob::sdo_rx(kBlockFloorNode));
    if (server < 0) {
        return;
    }
    std::array<can_frame, kBlockSize> in{};
    std::array<iovec, kBlockSize> iov{};
    std::array<mmsghdr, kBlockSize> msg{};
    for (std::size_t k = 0; k < in.size(); ++k) {
        iov[k] = {&in[k], sizeof(can_frame)};
        msg[k].msg_hdr.msg_iov = &iov[k];
        msg[k].msg_hdr.msg_iovlen = 1;
    }
    ready();
    while (true) {
        const int n = ::recvmmsg(server, msg.data(), kBlockSize, MSG_WAITFORONE, nullptr);
        if (n <= 0 && errno != EINTR) {
            return;
        }
        for (int k = 0; k < n; ++k) {
            if (in[static_cast<std::size_t>(k)].data[0] == kBlockSize) {
                raw_write(server, cob::sdo_tx(kBlockFloorNode), 0xA2);
            }
        }
    }
}

/// One-way frames per second in bursts of kBlockSize, each sent with one sendmmsg() and
/// acknowledged by one frame; only bursts whose acknowledgement came back count. `client` has a
/// receive timeout, so a lost ack costs its burst, never a hang.
double raw_block_frames(int client, double seconds) {
    std::array<can_frame, kBlockSize> out{};
    std::array<iovec, kBlockSize> iov{};
    std::array<mmsghdr, kBlockSize> msg{};
    for (std::size_t k = 0; k < out.size(); ++k) {
        out[k].can_id = cob::sdo_rx(kBlockFloorNode);
        out[k].len = 8;
        out[k].data[0] = static_cast<std::uint8_t>(k + 1);
        iov[k] = {&out[k], sizeof(can_frame)};
        msg[k].msg_hdr.msg_iov = &iov[k];
        msg[k].msg_hdr.msg_iovlen = 1;
    }
    const auto t0 = Clock::now();
    std::uint64_t frames = 0;
    while (seconds_since(t0) < seconds) {
        std::size_t sent = 0;
        while (sent < out.size()) {
            const int n =
                ::sendmmsg(client, &msg[sent], static_cast<unsigned>(out.size() - sent), 0);
            if (n > 0) {
                sent += static_cast<std::size_t>(n);
            } else if (errno != ENOBUFS && errno != EAGAIN && errno != EINTR) {
                return 0;
            } else {
                std::this_thread::yield();
            }
        }
        if (raw_read(client)) {
            frames += kBlockSize;
        }
    }
    return static_cast<double>(frames) / seconds_since(t0);
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

void raw_sm_server(const std::string& ifname, const std::function<void()>& ready) {
    const int sfd = raw_socket(ifname, cob::sdo_rx(kSmNode));
    if (sfd < 0) {
        return;
    }
    ObjectDictionary od = bench_dictionary();
    RawBus bus(sfd);
    CachedClock clock;
    sdo::ServerConfig config;
    config.node = kSmNode;
    sdo::SdoServer server(od, bus, config);
    ready();
    Frame f;
    while (bus.receive(f)) {
        clock.tick();
        (void)server.on_frame(f, clock.now());
    }
}

struct RawSmClient {
    explicit RawSmClient(int fd) : bus(fd), client(bus, clock, make_config()) { clock.tick(); }
    static sdo::ClientConfig make_config() {
        sdo::ClientConfig config;
        config.node = kSmNode;
        return config;
    }
    RawBus bus;
    CachedClock clock;
    sdo::SdoClient client;
};

/// Expedited uploads per second, SdoClient fed by blocking read(); 0 on a failed transfer.
double raw_sm_round_trips(RawSmClient& c, double seconds) {
    std::uint64_t done = 0;
    bool ok = true;
    const auto t0 = Clock::now();
    while (ok && seconds_since(t0) < seconds) {
        for (int i = 0; i < kClockEvery && ok; ++i) {
            bool finished = false;
            c.client.upload(0x1018, 0, [&](sdo::SdoResult<sdo::Bytes> r) {
                ok = r.has_value();
                finished = true;
            });
            Frame f;
            while (!finished && c.bus.receive(f)) {
                c.clock.tick();
                (void)c.client.on_frame(f, c.clock.now());
            }
            ++done;
        }
    }
    return ok ? static_cast<double>(done) / seconds_since(t0) : 0;
}

// ---- codrive ---------------------------------------------------------------------------------

struct ClientSide {
    std::unique_ptr<EventLoop> loop;
    std::unique_ptr<SocketCanBus> bus;
    std::unique_ptr<sdo::SdoClient> client;
};

std::optional<ClientSide> open_client(const std::string& ifname, NodeId node, bool direct) {
    ClientSide c;
    auto loop = EventLoop::create();
    auto bus = SocketCanBus::open(ifname, bus_options(cob::sdo_tx(node), direct));
    if (!loop || !bus) {
        return std::nullopt;
    }
    c.loop = std::move(*loop);
    c.bus = std::move(*bus);
    if (!c.bus->attach(*c.loop)) {
        return std::nullopt;
    }
    sdo::ClientConfig config;
    config.node = node;
    c.client = std::make_unique<sdo::SdoClient>(*c.bus, RealClock::instance(), config);
    sdo::SdoClient* client = c.client.get();
    c.bus->set_frame_handler(
        [client](const Frame& f, TimePoint t) { (void)client->on_frame(f, t); });
    c.loop->add_timed(client);
    return c;
}

/// Expedited uploads per second through SdoClient + EventLoop + SocketCanBus; 0 on failure.
double expedited_round_trips(ClientSide& c, double seconds) {
    std::uint64_t done = 0;
    bool failed = false;
    const auto t0 = Clock::now();
    std::function<void(sdo::SdoResult<sdo::Bytes>)> next;
    bool finished = false;
    next = [&](sdo::SdoResult<sdo::Bytes> r) {
        if (!r) {
            fmt::print(stderr, "{}\n", r.error().to_string());
            failed = true;
        }
        // The clock is read as often as in the floor's loop: the figure is the stack's.
        if (failed || (++done % kClockEvery == 0 && seconds_since(t0) >= seconds)) {
            finished = true;
            return;
        }
        c.client->upload(0x1018, 0, next);
    };
    c.client->upload(0x1018, 0, next);
    c.loop->run_until([&] { return finished; }, std::chrono::seconds(600));
    return failed ? 0 : static_cast<double>(done) / seconds_since(t0);
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
    const std::string only = argc > 3 ? argv[3] : "all";
    if (only != "all" && only != "floor" && only != "raw-sm" && only != "full" &&
        only != "full-epoll" && only != "block") {
        fmt::print(stderr, "bench_sdo_vcan: FIGURE must be all, floor, raw-sm, full, full-epoll "
                           "or block\n");
        return 2;
    }
    if (!socketcan_available()) {
        fmt::print(stderr, "bench_sdo_vcan: no SocketCAN here; run through "
                           "vcan-scripts/run-in-vcan.sh\n");
        return 2;
    }
    const auto want = [&only](const char* figure) { return only == "all" || only == figure; };
    fmt::print("SDO on {} ({} s per figure, servers in child processes)\n", ifname, seconds);

    // All servers at once (each on its own node-ID), so the figures can interleave. The
    // expedited floor runs with every round-trip figure (the ratios need it).
    const bool want_floor = only != "block";
    std::vector<std::unique_ptr<ServerProcess>> servers;
    if (want_floor) {
        servers.push_back(std::make_unique<ServerProcess>(
            [&](const auto& ready) { raw_server(ifname, kFloorNode, ready); }));
    }
    if (want("raw-sm")) {
        servers.push_back(std::make_unique<ServerProcess>(
            [&](const auto& ready) { raw_sm_server(ifname, ready); }));
    }
    if (want("full") || want("block")) {
        servers.push_back(std::make_unique<ServerProcess>(
            [&](const auto& ready) { codrive_server(ifname, kFullNode, true, ready); }));
    }
    if (want("full-epoll")) {
        servers.push_back(std::make_unique<ServerProcess>(
            [&](const auto& ready) { codrive_server(ifname, kEpollNode, false, ready); }));
    }
    if (want("block")) {
        servers.push_back(std::make_unique<ServerProcess>(
            [&](const auto& ready) { raw_block_server(ifname, ready); }));
    }
    for (const auto& s : servers) {
        if (!s->ready()) {
            fmt::print(stderr, "bench_sdo_vcan: a server could not open {}\n", ifname);
            return 2;
        }
    }
    const int floor_fd = raw_socket(ifname, cob::sdo_tx(kFloorNode));
    const int sm_fd = raw_socket(ifname, cob::sdo_tx(kSmNode));
    const int block_fd = raw_socket(ifname, cob::sdo_tx(kBlockFloorNode));
    auto client = open_client(ifname, kFullNode, true);
    auto epoll_client = open_client(ifname, kEpollNode, false);
    if (floor_fd < 0 || sm_fd < 0 || block_fd < 0 || !client || !epoll_client) {
        fmt::print(stderr, "bench_sdo_vcan: cannot open client sockets on {}\n", ifname);
        return 2;
    }
    const timeval ack_timeout{0, 200000}; // a lost block ack costs its burst, not a hang
    ::setsockopt(block_fd, SOL_SOCKET, SO_RCVTIMEO, &ack_timeout, sizeof ack_timeout);
    RawSmClient sm(sm_fd);

    std::vector<double> floor_rates;
    std::vector<double> sm_rates;
    std::vector<double> full_rates;
    std::vector<double> epoll_rates;
    const int slices = std::max(1, static_cast<int>(seconds / kSlice + 0.5));
    for (int i = 0; i < slices && only != "block"; ++i) {
        floor_rates.push_back(raw_round_trips(floor_fd, kFloorNode, kSlice));
        if (want("raw-sm")) {
            sm_rates.push_back(raw_sm_round_trips(sm, kSlice));
        }
        if (want("full")) {
            full_rates.push_back(expedited_round_trips(*client, kSlice));
        }
        if (want("full-epoll")) {
            epoll_rates.push_back(expedited_round_trips(*epoll_client, kSlice));
        }
    }
    bool floors_hold = true;
    // Each slice against the floor slice measured just before it.
    const auto ratio = [&floor_rates](const std::vector<double>& rates) {
        std::vector<double> r;
        for (std::size_t i = 0; i < rates.size() && i < floor_rates.size(); ++i) {
            r.push_back(floor_rates[i] > 0 ? rates[i] / floor_rates[i] : 0);
        }
        return bench::spread_of(r);
    };
    const auto row = [&](const char* name, const char* what, const std::vector<double>& rates) {
        const bench::Spread r = ratio(rates);
        fmt::print("  {:<36} {:>8.0f} round trips/s, ratio to floor {}\n", name,
                   bench::spread_of(rates).median, bench::describe(r));
        floors_hold = bench::floor_holds(what, r.median) && floors_hold;
    };
    if (want_floor) {
        fmt::print("  {:<36} {} round trips/s\n", "floor: raw request/response",
                   bench::describe(bench::spread_of(floor_rates), 0));
    }
    if (want("raw-sm")) {
        row("codrive SDO state machines, raw I/O", "the SDO state machines over raw I/O", sm_rates);
    }
    if (want("full")) {
        row("codrive full stack (EventLoop)", "the full SDO stack", full_rates);
        fmt::print("  (target for the full stack: ratio >= 0.90)\n");
    }
    if (want("full-epoll")) {
        row("codrive full stack, epoll path", "the full SDO stack on the epoll path", epoll_rates);
    }
    if (want("block")) {
        // Rounds of: floor for kBlockFloorSlice s, then one block download and one block upload
        // of kRoundBytes; each efficiency against the floor of its own round.
        constexpr std::size_t kRoundBytes = 64 * 1024;
        constexpr double kBlockFloorSlice = 0.5;
        const int rounds = std::max(3, static_cast<int>(seconds * 2 + 0.5));
        // A block transfer of N bytes moves ceil(N / 7) segment frames one way.
        const auto frames_per_s = [](double kib_s) { return kib_s * 1024.0 / 7.0; };
        std::vector<double> floor_frames;
        std::vector<double> down_kib;
        std::vector<double> up_kib;
        std::vector<double> down_eff;
        std::vector<double> up_eff;
        for (int i = 0; i < rounds; ++i) {
            const double f = raw_block_frames(block_fd, kBlockFloorSlice);
            const auto [down, up] = block_kib_s(*client, kRoundBytes);
            if (f <= 0 || down <= 0 || up <= 0) {
                fmt::print(stderr,
                           "bench_sdo_vcan: block round {} failed (floor {:.0f} frames/s)"
                           "\n",
                           i, f);
                return 1;
            }
            floor_frames.push_back(f);
            down_kib.push_back(down);
            up_kib.push_back(up);
            down_eff.push_back(frames_per_s(down) / f);
            up_eff.push_back(frames_per_s(up) / f);
        }
        fmt::print("  floor: raw {}-frame sendmmsg() bursts + ack  {} frames/s\n", kBlockSize,
                   bench::describe(bench::spread_of(floor_frames), 0));
        const bench::Spread de = bench::spread_of(down_eff);
        const bench::Spread ue = bench::spread_of(up_eff);
        fmt::print("  codrive block download ({} KiB per round) {} KiB/s, efficiency {}\n",
                   kRoundBytes / 1024, bench::describe(bench::spread_of(down_kib), 0),
                   bench::describe(de));
        fmt::print("  codrive block upload ({} KiB per round)   {} KiB/s, efficiency {}\n",
                   kRoundBytes / 1024, bench::describe(bench::spread_of(up_kib), 0),
                   bench::describe(ue));
        floors_hold = bench::floor_holds("the block download", de.median) && floors_hold;
        floors_hold = bench::floor_holds("the block upload", ue.median) && floors_hold;
    }
    ::close(floor_fd);
    ::close(sm_fd);
    ::close(block_fd);
    return floors_hold ? 0 : 1;
}
