// SPDX-License-Identifier: Apache-2.0
// epoll + timerfd reactor: one timerfd armed (absolute, CLOCK_MONOTONIC) at the earliest deadline;
// the clock is read only when a deadline may be due, and a lone socket is waited on directly.
#include <codrive/core/event_loop.hpp>

#include <algorithm>
#include <cerrno>
#include <limits>
#include <sys/epoll.h>
#include <sys/eventfd.h>
#include <sys/timerfd.h>
#include <unistd.h>

namespace codrive {
namespace {

timespec to_timespec(TimePoint t) {
    const auto ns = std::chrono::duration_cast<nanoseconds>(t.time_since_epoch()).count();
    timespec ts{};
    ts.tv_sec = static_cast<time_t>(ns / 1'000'000'000);
    ts.tv_nsec = static_cast<long>(ns % 1'000'000'000);
    return ts;
}

} // namespace

Result<std::unique_ptr<EventLoop>> EventLoop::create() {
    std::unique_ptr<EventLoop> loop(new EventLoop());
    loop->epoll_fd_ = epoll_create1(EPOLL_CLOEXEC);
    if (loop->epoll_fd_ < 0) {
        return fail_errno(errno);
    }
    loop->timer_fd_ = timerfd_create(CLOCK_MONOTONIC, TFD_NONBLOCK | TFD_CLOEXEC);
    if (loop->timer_fd_ < 0) {
        return fail_errno(errno);
    }
    loop->wake_fd_ = eventfd(0, EFD_NONBLOCK | EFD_CLOEXEC);
    if (loop->wake_fd_ < 0) {
        return fail_errno(errno);
    }
    for (int fd : {loop->timer_fd_, loop->wake_fd_}) {
        epoll_event ev{};
        ev.events = EPOLLIN;
        ev.data.ptr = nullptr;
        ev.data.fd = fd;
        if (epoll_ctl(loop->epoll_fd_, EPOLL_CTL_ADD, fd, &ev) < 0) {
            return fail_errno(errno);
        }
    }
    return loop;
}

EventLoop::~EventLoop() {
    for (int fd : {epoll_fd_, timer_fd_, wake_fd_}) {
        if (fd >= 0) {
            ::close(fd);
        }
    }
}

VoidResult EventLoop::add_fd(int fd, std::uint32_t events, IoHandler handler) {
    auto entry = std::make_unique<FdEntry>(FdEntry{fd, events, std::move(handler), {}, {}});
    epoll_event ev{};
    ev.events = events;
    ev.data.fd = fd;
    if (epoll_ctl(epoll_fd_, EPOLL_CTL_ADD, fd, &ev) < 0) {
        return fail_errno(errno);
    }
    fds_.push_back(std::move(entry));
    return {};
}

VoidResult EventLoop::modify_fd(int fd, std::uint32_t events) {
    epoll_event ev{};
    ev.events = events;
    ev.data.fd = fd;
    if (epoll_ctl(epoll_fd_, EPOLL_CTL_MOD, fd, &ev) < 0) {
        return fail_errno(errno);
    }
    for (auto& e : fds_) {
        if (e->fd == fd) {
            e->events = events;
        }
    }
    return {};
}

VoidResult EventLoop::set_direct_reader(int fd, DirectReader reader, Duration block_limit) {
    for (auto& e : fds_) {
        if (e->fd == fd) {
            e->reader = std::move(reader);
            e->block_limit = block_limit;
            return {};
        }
    }
    return fail_errno(EINVAL);
}

void EventLoop::remove_fd(int fd) {
    epoll_ctl(epoll_fd_, EPOLL_CTL_DEL, fd, nullptr);
    // Keep the entry object alive until the end of the current dispatch: mark it dead.
    for (auto& e : fds_) {
        if (e && e->fd == fd) {
            e->fd = -1;
            e->handler = nullptr;
            e->reader = nullptr;
        }
    }
}

void EventLoop::add_timed(ITimed* timed) {
    if (std::find(timed_.begin(), timed_.end(), timed) == timed_.end()) {
        timed_.push_back(timed);
    }
}

void EventLoop::remove_timed(ITimed* timed) {
    std::replace(timed_.begin(), timed_.end(), timed, static_cast<ITimed*>(nullptr));
}

std::uint64_t EventLoop::call_at(TimePoint when, std::function<void()> fn) {
    const std::uint64_t id = next_timer_id_++;
    oneshots_.push_back(OneShot{id, when, std::move(fn)});
    return id;
}

void EventLoop::cancel_timer(std::uint64_t id) {
    for (auto& o : oneshots_) {
        if (o.id == id) {
            o.fn = nullptr;
            o.when = kNever;
        }
    }
}

void EventLoop::post(std::function<void()> fn) {
    // From now on the loop waits in epoll_wait(), where the wake-up eventfd is seen at once.
    posted_ever_ = true;
    {
        std::lock_guard lock(post_mutex_);
        posted_.push_back(std::move(fn));
    }
    const std::uint64_t one = 1;
    [[maybe_unused]] auto n = ::write(wake_fd_, &one, sizeof(one));
}

void EventLoop::stop() {
    stop_ = true;
    const std::uint64_t one = 1;
    [[maybe_unused]] auto n = ::write(wake_fd_, &one, sizeof(one));
}

void EventLoop::note_time(TimePoint t) {
    last_now_ = std::max(last_now_, t);
    now_fresh_ = true;
}

TimePoint EventLoop::earliest_deadline() const {
    TimePoint earliest = run_deadline_;
    for (ITimed* t : timed_) {
        if (t != nullptr) {
            earliest = std::min(earliest, t->next_deadline());
        }
    }
    for (const auto& o : oneshots_) {
        earliest = std::min(earliest, o.when);
    }
    return earliest;
}

void EventLoop::arm_timer() {
    const TimePoint earliest = earliest_deadline();
    // Re-arm only when the earliest deadline moved earlier. A timer armed earlier than needed
    // just wakes the loop once for nothing, which is cheaper than a timerfd_settime() per
    // frame (every SDO request moves its timeout later).
    if (earliest >= armed_) {
        return;
    }
    armed_ = earliest;
    itimerspec spec{};
    if (earliest != kNever) {
        spec.it_value = to_timespec(earliest);
        if (spec.it_value.tv_sec == 0 && spec.it_value.tv_nsec == 0) {
            spec.it_value.tv_nsec = 1; // zero would disarm
        }
    }
    timerfd_settime(timer_fd_, TFD_TIMER_ABSTIME, &spec, nullptr);
}

void EventLoop::dispatch_timers(TimePoint now) {
    // Index loop: services may add or remove services while ticking.
    for (std::size_t i = 0; i < timed_.size(); ++i) {
        ITimed* t = timed_[i];
        if (t != nullptr && t->next_deadline() <= now) {
            t->on_tick(now);
        }
    }
    for (std::size_t i = 0; i < oneshots_.size(); ++i) {
        if (oneshots_[i].fn && oneshots_[i].when <= now) {
            auto fn = std::move(oneshots_[i].fn);
            oneshots_[i].fn = nullptr;
            oneshots_[i].when = kNever;
            fn();
        }
    }
    std::erase_if(oneshots_, [](const OneShot& o) { return !o.fn; });
    std::erase(timed_, nullptr);
}

VoidResult EventLoop::poll_once(Duration max_wait) {
    // Only kForever waits without a limit; a wait that ran out while the caller computed it
    // must not turn into one (a controller shutdown once hung so, docs/reliability.md).
    max_wait = std::max(max_wait, Duration::zero());
    if (direct_read_possible(max_wait)) {
        poll_direct();
        return {};
    }
    return poll_epoll(max_wait);
}

bool EventLoop::direct_read_possible(Duration max_wait) {
    if (fds_.size() != 1 || !fds_[0]->reader || fds_[0]->events != EPOLLIN || posted_ever_ ||
        stop_) {
        return false;
    }
    const Duration limit = fds_[0]->block_limit;
    if (max_wait != kForever && max_wait < limit) {
        return false;
    }
    const TimePoint earliest = earliest_deadline();
    if (earliest == kNever) {
        return true;
    }
    // The time must be current to the last wake-up: a stale time would let a deadline slip by
    // up to a block limit. One clock read when entering the fast path; receive times keep it
    // current afterwards.
    if (!now_fresh_) {
        last_now_ = now();
        now_fresh_ = true;
    }
    return earliest > last_now_ + 2 * limit;
}

void EventLoop::poll_direct() {
    // Keep the entry (and so the reader) alive even if a frame handler removes the fd.
    FdEntry* e = fds_[0].get();
    auto reader = e->reader;
    const DirectRead r = reader();
    if (r.count > 0 && r.newest) {
        note_time(*r.newest);
    } else {
        // Timed out (no frame for a block limit), interrupted or failed: a real clock read.
        note_time(now());
    }
    std::erase_if(fds_, [](const std::unique_ptr<FdEntry>& x) { return x->fd < 0; });
    // Only deadlines at or before a known time are dispatched; one a little later makes the
    // next wait an epoll_wait() on the timerfd (the fast path needs 2 block limits of room).
    if (earliest_deadline() <= last_now_) {
        dispatch_timers(last_now_);
    }
}

VoidResult EventLoop::poll_epoll(Duration max_wait) {
    arm_timer();
    std::array<epoll_event, 32> events{};
    // epoll_wait() counts whole milliseconds; a longer finite wait than it can take is cut to
    // its largest (about 24 days), never turned into "no limit".
    const auto ms = std::chrono::duration_cast<milliseconds>(max_wait).count();
    const int timeout_ms =
        max_wait == kForever
            ? -1
            : static_cast<int>(std::min<long long>(ms, std::numeric_limits<int>::max()));
    now_fresh_ = false;
    const int n = epoll_wait(epoll_fd_, events.data(), static_cast<int>(events.size()), timeout_ms);
    if (n < 0) {
        if (errno == EINTR) {
            return {};
        }
        return fail_errno(errno);
    }
    // The clock is read only when a deadline may be due: the wait timed out, the timer fired, or
    // a handler moved a deadline earlier than the armed one. Otherwise every deadline is at or
    // after the armed timer, which has not fired, so none is due.
    bool need_clock = n == 0;
    for (int i = 0; i < n; ++i) {
        const int fd = events[static_cast<std::size_t>(i)].data.fd;
        if (fd == timer_fd_) {
            std::uint64_t expirations = 0;
            [[maybe_unused]] auto r = ::read(timer_fd_, &expirations, sizeof(expirations));
            armed_ = kNever; // a fired absolute timer is no longer armed
            need_clock = true;
            continue;
        }
        if (fd == wake_fd_) {
            std::uint64_t count = 0;
            [[maybe_unused]] auto r = ::read(wake_fd_, &count, sizeof(count));
            std::vector<std::function<void()>> work;
            {
                std::lock_guard lock(post_mutex_);
                work.swap(posted_);
            }
            for (auto& fn : work) {
                fn();
            }
            continue;
        }
        for (std::size_t k = 0; k < fds_.size(); ++k) {
            FdEntry* e = fds_[k].get();
            if (e->fd == fd && e->handler) {
                auto handler = e->handler; // the handler may remove itself
                handler(events[static_cast<std::size_t>(i)].events);
                break;
            }
        }
    }
    std::erase_if(fds_, [](const std::unique_ptr<FdEntry>& e) { return e->fd < 0; });
    // Deadlines are checked after every wake-up that may have made one due, not only on timer
    // expiry, so a service whose deadline moved earlier while handling a frame is served without
    // another round trip.
    if (need_clock || earliest_deadline() < armed_) {
        last_now_ = now();
        now_fresh_ = true;
        dispatch_timers(last_now_);
    }
    return {};
}

VoidResult EventLoop::run() {
    stop_ = false;
    while (!stop_) {
        if (auto r = poll_once(kForever); !r) {
            return r;
        }
    }
    return {};
}

namespace {

/// Makes a run_until() deadline one of the loop's deadlines for its duration (the timerfd then
/// ends the wait, so the loop needs no clock read per wake-up to notice it), restoring the outer
/// one for nested calls.
class RunDeadline {
public:
    RunDeadline(TimePoint& slot, TimePoint deadline) : slot_(slot), saved_(slot) {
        slot_ = std::min(saved_, deadline);
    }
    ~RunDeadline() { slot_ = saved_; }
    RunDeadline(const RunDeadline&) = delete;
    RunDeadline& operator=(const RunDeadline&) = delete;

private:
    TimePoint& slot_;
    TimePoint saved_;
};

} // namespace

VoidResult EventLoop::run_until(TimePoint deadline) {
    stop_ = false;
    const RunDeadline scope(run_deadline_, deadline);
    last_now_ = now();
    now_fresh_ = true;
    while (!stop_) {
        const TimePoint t = last_now_;
        if (t >= deadline) {
            break;
        }
        if (auto r = poll_once(std::min<Duration>(deadline - t, seconds(1)) + milliseconds(1));
            !r) {
            return r;
        }
    }
    return {};
}

bool EventLoop::run_until(const std::function<bool()>& pred, Duration timeout) {
    last_now_ = now();
    now_fresh_ = true;
    // kForever (or any timeout past the clock's end) is no deadline, not an overflow.
    const TimePoint deadline = timeout >= kNever - last_now_ ? kNever : last_now_ + timeout;
    const RunDeadline scope(run_deadline_, deadline);
    stop_ = false;
    // The time comes from the loop's own clock reads and receive times: a clock read only when
    // a deadline (this one included) may be due, not one per wake-up.
    while (!pred()) {
        const TimePoint t = last_now_;
        if (t >= deadline || stop_) {
            return pred();
        }
        if (!poll_once(std::min<Duration>(deadline - t, milliseconds(50)) + milliseconds(1))) {
            return pred();
        }
    }
    return true;
}

} // namespace codrive
