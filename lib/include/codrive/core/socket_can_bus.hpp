// SPDX-License-Identifier: Apache-2.0
// ICanBus over a Linux SocketCAN raw socket: non-blocking, kernel filters and timestamps, error
// frames decoded into bus events, and a transmit retry queue that never drops.
#pragma once

#include <codrive/core/can_bus.hpp>
#include <codrive/core/event_loop.hpp>

#include <array>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

namespace codrive {

/// A kernel receive filter: a frame passes if (id & mask) == (filter id & mask).
struct CanFilter {
    std::uint32_t id = 0;
    std::uint32_t mask = 0;
    bool extended = false; ///< match 29-bit frames (otherwise 11-bit only)
    bool invert = false;   ///< CAN_INV_FILTER
};

struct SocketCanOptions {
    std::vector<CanFilter> filters;       ///< empty: receive everything
    bool loopback = true;                 ///< other sockets on this host see our frames
    bool receive_own = false;             ///< we see our own frames
    bool error_frames = true;             ///< receive and decode error frames
    bool fd = false;                      ///< enable CAN FD frames
    bool timestamps = true;               ///< kernel receive timestamps
    int rcvbuf_bytes = 0;                 ///< SO_RCVBUF(FORCE) if > 0
    int sndbuf_bytes = 0;                 ///< SO_SNDBUF if > 0
    std::size_t tx_queue_capacity = 4096; ///< frames held while the kernel is full
    Duration tx_retry = std::chrono::microseconds(200); ///< retry period when EPOLLOUT is silent
    /// When this bus is all its loop waits for, the loop receives with one blocking recvmmsg()
    /// instead of epoll_wait() + recvmmsg(); this is the longest such a receive blocks (the
    /// socket's SO_RCVTIMEO), i.e. how late a cross-thread stop() may be seen. Zero: never.
    Duration direct_read_limit = std::chrono::milliseconds(20);
};

/// A raw SocketCAN socket bound to one interface. Register it with an EventLoop to receive;
/// send() works with or without a loop (without one, the retry queue drains on the next send or
/// flush()).
class SocketCanBus final : public ICanBus, public ITimed {
public:
    /// Opens and binds. Errors: NoSocketCan (kernel without CAN), NoSuchInterface, system errors.
    static Result<std::unique_ptr<SocketCanBus>> open(const std::string& ifname,
                                                      SocketCanOptions options = {});
    ~SocketCanBus() override;

    VoidResult send(const Frame& frame) override;
    /// One sendmmsg() per kTxBatch frames while the kernel takes them; what it cannot take
    /// goes through send() (queued in order, or refused).
    std::size_t send_many(std::span<const Frame> frames) override;
    void set_frame_handler(FrameHandler handler) override { frame_handler_ = std::move(handler); }
    void set_event_handler(EventHandler handler) override { event_handler_ = std::move(handler); }
    [[nodiscard]] std::size_t tx_pending() const override { return tx_count_; }
    [[nodiscard]] const BusStats& stats() const override { return stats_; }
    [[nodiscard]] const std::string& name() const override { return ifname_; }

    /// Attaches to a loop: frames are read when the socket is readable, the retry queue drains
    /// on EPOLLOUT or its retry timer.
    VoidResult attach(EventLoop& loop);
    void detach();

    /// Reads every frame waiting in the socket now and dispatches it. Returns frames read.
    std::size_t read_available();
    /// Waits up to options.direct_read_limit for a frame, then reads and dispatches it and every
    /// frame waiting behind it (the loop's direct-read fast path; one system call per batch).
    EventLoop::DirectRead read_blocking();
    /// Tries to push queued frames to the kernel. Returns the frames still queued.
    std::size_t flush();
    /// Blocks (poll) until the retry queue is empty or timeout; true if empty.
    bool drain(Duration timeout);
    /// Replaces the kernel filters.
    VoidResult set_filters(const std::vector<CanFilter>& filters);

    [[nodiscard]] int fd() const { return fd_; }

    [[nodiscard]] TimePoint next_deadline() const override;
    void on_tick(TimePoint now) override;

private:
    SocketCanBus() = default;
    bool write_one(const Frame& f, int& err);
    /// Frames per sendmmsg() in send_many().
    static constexpr std::size_t kTxBatch = 64;
    void handle_frame(const Frame& f, TimePoint rx_time);
    /// recvmmsg() batches until one comes back short; the first with `first_flags`.
    EventLoop::DirectRead read_batches(int first_flags);
    void update_epollout();
    /// Kernel receive timestamps are CLOCK_REALTIME; protocol time is CLOCK_MONOTONIC. The
    /// offset between them is sampled at most once a second (of receive timestamps): clock
    /// reads are system calls on some targets (about 90 us each in a User-Mode-Linux guest).
    TimePoint to_monotonic(std::int64_t realtime_ns);

    int fd_ = -1;
    std::string ifname_;
    SocketCanOptions opts_;
    FrameHandler frame_handler_;
    EventHandler event_handler_;
    BusStats stats_;
    EventLoop* loop_ = nullptr;
    bool want_out_ = false;
    // Fixed-capacity ring, allocated once at open(): no allocation on the send path.
    std::vector<Frame> tx_ring_;
    struct TxBatch;                     ///< send_many()'s kernel frames and message headers
    std::unique_ptr<TxBatch> tx_batch_; ///< allocated at open(), like the ring
    std::size_t tx_head_ = 0;
    std::size_t tx_count_ = 0;
    TimePoint retry_at_ = kNever;
    std::uint32_t last_drop_count_ = 0;
    BusState state_ = BusState::ErrorActive;
    std::int64_t rt_offset_ns_ = 0;
    std::int64_t rt_offset_sampled_at_ = 0; ///< realtime ns of the last sample; 0 = never
};

/// Decodes a SocketCAN error frame (CAN_ERR_FLAG set) into bus events (one frame may carry
/// several: e.g. controller problem + state change).
[[nodiscard]] std::vector<BusEvent> decode_error_frame(const Frame& f);

/// The one sentence every tool prints when SocketCanBus::open() fails: the interface, the cause
/// and what to do, e.g. "cannot open can0: this kernel has no SocketCAN support (AF_CAN
/// unavailable) (... run the tool inside a vcan guest with vcan-scripts/run-in-vcan.sh, see
/// docs/vcan.md)".
[[nodiscard]] std::string describe_can_open_error(const std::string& ifname,
                                                  const std::error_code& ec);

/// True if this kernel supports AF_CAN sockets at all.
[[nodiscard]] bool socketcan_available();

} // namespace codrive
