// SPDX-License-Identifier: Apache-2.0
// epoll + timerfd reactor: one timerfd armed (absolute, CLOCK_MONOTONIC) at the earliest deadline.
#include <codrive/core/event_loop.hpp>

#include <algorithm>
#include <cerrno>
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
    auto entry = std::make_unique<FdEntry>(FdEntry{fd, std::move(handler)});
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
    return {};
}

void EventLoop::remove_fd(int fd) {
    epoll_ctl(epoll_fd_, EPOLL_CTL_DEL, fd, nullptr);
    // Keep the entry object alive until the end of the current dispatch: mark it dead.
    for (auto& e : fds_) {
        if (e && e->fd == fd) {
            e->fd = -1;
            e->handler = nullptr;
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

void EventLoop::arm_timer() {
    TimePoint earliest = kNever;
    for (ITimed* t : timed_) {
        if (t != nullptr) {
            earliest = std::min(earliest, t->next_deadline());
        }
    }
    for (const auto& o : oneshots_) {
        earliest = std::min(earliest, o.when);
    }
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
    arm_timer();
    std::array<epoll_event, 32> events{};
    const auto ms = std::chrono::duration_cast<milliseconds>(max_wait).count();
    const int timeout_ms =
        max_wait < Duration::zero() ? -1 : static_cast<int>(std::max<long>(0, ms));
    const int n = epoll_wait(epoll_fd_, events.data(), static_cast<int>(events.size()), timeout_ms);
    if (n < 0) {
        if (errno == EINTR) {
            return {};
        }
        return fail_errno(errno);
    }
    bool timer_fired = false;
    for (int i = 0; i < n; ++i) {
        const int fd = events[static_cast<std::size_t>(i)].data.fd;
        if (fd == timer_fd_) {
            std::uint64_t expirations = 0;
            [[maybe_unused]] auto r = ::read(timer_fd_, &expirations, sizeof(expirations));
            armed_ = kNever; // a fired absolute timer is no longer armed
            timer_fired = true;
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
    (void)timer_fired;
    // Deadlines are checked after every wake-up, not only on timer expiry, so a service whose
    // deadline moved earlier while handling a frame is served without another round trip.
    last_now_ = now();
    dispatch_timers(last_now_);
    return {};
}

VoidResult EventLoop::run() {
    stop_ = false;
    while (!stop_) {
        if (auto r = poll_once(Duration(-1)); !r) {
            return r;
        }
    }
    return {};
}

VoidResult EventLoop::run_until(TimePoint deadline) {
    stop_ = false;
    while (!stop_) {
        const TimePoint t = now();
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
    const TimePoint deadline = last_now_ + timeout;
    stop_ = false;
    // The time comes from the clock read each poll_once() makes anyway: one clock read per
    // iteration (a system call on some targets).
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
