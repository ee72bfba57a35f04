// SPDX-License-Identifier: Apache-2.0
// The event loop: epoll over file descriptors plus one timerfd armed at the earliest deadline,
// and a direct-read fast path when a single socket is all there is to wait for.
#pragma once

#include <codrive/core/error.hpp>
#include <codrive/core/time.hpp>

#include <atomic>
#include <cstdint>
#include <functional>
#include <memory>
#include <mutex>
#include <optional>
#include <vector>

namespace codrive {

/// Anything with timed work: protocol services report when they next need on_tick().
class ITimed {
public:
    virtual ~ITimed() = default;
    /// The earliest time on_tick() must run, or kNever.
    [[nodiscard]] virtual TimePoint next_deadline() const = 0;
    virtual void on_tick(TimePoint now) = 0;
};

/// Single-threaded reactor. File descriptor callbacks and timed services run on the thread that
/// calls run(); post() is the one thread-safe entry point.
class EventLoop {
public:
    using IoHandler = std::function<void(std::uint32_t epoll_events)>;

    /// What a direct reader did: messages read and dispatched, and the newest receive time it
    /// knows (a kernel timestamp), which spares the loop a clock read.
    struct DirectRead {
        std::size_t count = 0;
        std::optional<TimePoint> newest;
    };
    /// Reads and dispatches what fd holds, blocking for the first message at most the fd's own
    /// receive timeout (SO_RCVTIMEO). Returns count 0 on timeout, interruption or error.
    using DirectReader = std::function<DirectRead()>;

    /// Creates the epoll instance, the timerfd and the wake-up eventfd.
    static Result<std::unique_ptr<EventLoop>> create();
    ~EventLoop();
    EventLoop(const EventLoop&) = delete;
    EventLoop& operator=(const EventLoop&) = delete;

    /// Watches fd for `events` (EPOLLIN, EPOLLOUT, ...). The fd stays owned by the caller.
    VoidResult add_fd(int fd, std::uint32_t events, IoHandler handler);
    VoidResult modify_fd(int fd, std::uint32_t events);
    void remove_fd(int fd);
    /// Fast path for a loop whose only work is one socket: while fd is the only watched fd, it
    /// waits for EPOLLIN only, post() was never called and no deadline is within
    /// 2 x `block_limit`, the loop waits in `reader` (one blocking receive) instead of
    /// epoll_wait() + a read: one system call per wake-up instead of two (each costs ~90 us in a
    /// User-Mode-Linux guest). `block_limit` must be the fd's receive timeout: it bounds how late
    /// a stop() from another thread is seen. Errors: EINVAL if fd is not watched.
    VoidResult set_direct_reader(int fd, DirectReader reader, Duration block_limit);

    /// Registers a timed service; the loop calls on_tick() when its deadline passes. The pointer
    /// must stay valid until removed.
    void add_timed(ITimed* timed);
    void remove_timed(ITimed* timed);

    /// A one-shot callback at `when` (on the loop thread). Returns an id for cancel_timer().
    std::uint64_t call_at(TimePoint when, std::function<void()> fn);
    void cancel_timer(std::uint64_t id);

    /// Thread-safe: runs fn on the loop thread soon.
    void post(std::function<void()> fn);

    /// Runs until stop(). Returns an error only if epoll itself fails.
    VoidResult run();
    /// Runs until `deadline` (or stop()).
    VoidResult run_until(TimePoint deadline);
    /// Runs until pred() is true after a dispatch, or the timeout passes (kForever: none).
    /// True if pred held.
    bool run_until(const std::function<bool()>& pred, Duration timeout);
    /// poll_once()'s "no limit": wait until an fd, a timer or posted work is ready.
    static constexpr Duration kForever = Duration::max();
    /// Dispatches what is ready now, waiting at most `max_wait`; `kForever` waits with no
    /// limit. A negative `max_wait` (a remaining time that ran out while it was computed)
    /// counts as zero: it dispatches what is ready and never blocks.
    VoidResult poll_once(Duration max_wait);
    /// Thread-safe: makes run() return (within the direct reader's block limit when the fast
    /// path is waiting).
    void stop();
    /// A handler that knows the current time without a clock read (a kernel receive timestamp)
    /// reports it, so the loop can keep using its fast path without reading the clock.
    void note_time(TimePoint t);

    [[nodiscard]] TimePoint now() const { return SteadyClock::now(); }

private:
    EventLoop() = default;
    [[nodiscard]] TimePoint earliest_deadline() const;
    void arm_timer();
    void dispatch_timers(TimePoint now);
    [[nodiscard]] bool direct_read_possible(Duration max_wait);
    void poll_direct();
    VoidResult poll_epoll(Duration max_wait);

    struct FdEntry {
        int fd;
        std::uint32_t events;
        IoHandler handler;
        DirectReader reader;
        Duration block_limit{};
    };
    struct OneShot {
        std::uint64_t id;
        TimePoint when;
        std::function<void()> fn;
    };

    int epoll_fd_ = -1;
    int timer_fd_ = -1;
    int wake_fd_ = -1;
    std::vector<std::unique_ptr<FdEntry>> fds_;
    std::vector<ITimed*> timed_;
    std::vector<OneShot> oneshots_;
    std::uint64_t next_timer_id_ = 1;
    TimePoint armed_ = kNever;
    TimePoint last_now_{};   ///< the time of the last dispatch (or a receive time noted since)
    bool now_fresh_ = false; ///< last_now_ was learnt during the current/last wake-up
    TimePoint run_deadline_ = kNever; ///< the end of the running run_until(), a deadline too
    std::atomic<bool> stop_{false};
    std::atomic<bool> posted_ever_{false};
    std::mutex post_mutex_;
    std::vector<std::function<void()>> posted_;
};

} // namespace codrive
