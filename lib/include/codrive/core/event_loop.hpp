// SPDX-License-Identifier: Apache-2.0
// The event loop: epoll over file descriptors plus one timerfd armed at the earliest deadline.
#pragma once

#include <codrive/core/error.hpp>
#include <codrive/core/time.hpp>

#include <atomic>
#include <cstdint>
#include <functional>
#include <memory>
#include <mutex>
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

    /// Creates the epoll instance, the timerfd and the wake-up eventfd.
    static Result<std::unique_ptr<EventLoop>> create();
    ~EventLoop();
    EventLoop(const EventLoop&) = delete;
    EventLoop& operator=(const EventLoop&) = delete;

    /// Watches fd for `events` (EPOLLIN, EPOLLOUT, ...). The fd stays owned by the caller.
    VoidResult add_fd(int fd, std::uint32_t events, IoHandler handler);
    VoidResult modify_fd(int fd, std::uint32_t events);
    void remove_fd(int fd);

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
    /// Runs until pred() is true after a dispatch, or the timeout passes. True if pred held.
    bool run_until(const std::function<bool()>& pred, Duration timeout);
    /// Dispatches what is ready now, waiting at most `max_wait`.
    VoidResult poll_once(Duration max_wait);
    /// Thread-safe: makes run() return.
    void stop();

    [[nodiscard]] TimePoint now() const { return SteadyClock::now(); }

private:
    EventLoop() = default;
    void arm_timer();
    void dispatch_timers(TimePoint now);

    struct FdEntry {
        int fd;
        IoHandler handler;
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
    TimePoint last_now_{}; ///< the time of the last dispatch
    std::atomic<bool> stop_{false};
    std::mutex post_mutex_;
    std::vector<std::function<void()>> posted_;
};

} // namespace codrive
