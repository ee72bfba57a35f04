// SPDX-License-Identifier: Apache-2.0
// The epoll/timerfd event loop: real timers, descriptors and a second thread (short waits).
#include <codrive/core/event_loop.hpp>

#include <gtest/gtest.h>

#include <sys/epoll.h>
#include <sys/eventfd.h>
#include <sys/socket.h>
#include <thread>
#include <unistd.h>

using namespace codrive;

namespace {
struct Periodic : ITimed {
    TimePoint next;
    Duration period;
    int ticks = 0;
    std::vector<TimePoint> times;
    TimePoint next_deadline() const override { return next; }
    void on_tick(TimePoint now) override {
        ++ticks;
        times.push_back(now);
        next += period;
    }
};
} // namespace

TEST(EventLoop, TicksTimedServiceAtItsDeadlinesNotBefore) {
    auto loop = EventLoop::create();
    ASSERT_TRUE(loop);
    Periodic p;
    p.period = std::chrono::milliseconds(2);
    p.next = (*loop)->now() + p.period;
    const TimePoint first = p.next;
    (*loop)->add_timed(&p);
    ASSERT_TRUE((*loop)->run_until([&] { return p.ticks >= 5; }, std::chrono::seconds(2)));
    ASSERT_GE(p.times.size(), 5U);
    for (std::size_t i = 0; i < 5; ++i) {
        EXPECT_GE(p.times[i], first + p.period * static_cast<int>(i));
    }
    (*loop)->remove_timed(&p);
}

TEST(EventLoop, DispatchesReadableFd) {
    auto loop = EventLoop::create();
    ASSERT_TRUE(loop);
    const int efd = eventfd(0, EFD_NONBLOCK);
    int calls = 0;
    ASSERT_TRUE((*loop)->add_fd(efd, EPOLLIN, [&](std::uint32_t) {
        std::uint64_t v = 0;
        ASSERT_EQ(::read(efd, &v, sizeof(v)), 8);
        calls += static_cast<int>(v);
    }));
    const std::uint64_t three = 3;
    ASSERT_EQ(::write(efd, &three, sizeof(three)), 8);
    EXPECT_TRUE((*loop)->run_until([&] { return calls == 3; }, std::chrono::seconds(1)));
    (*loop)->remove_fd(efd);
    ::close(efd);
}

TEST(EventLoop, OneShotTimersRunOnceAndCanBeCancelled) {
    auto loop = EventLoop::create();
    ASSERT_TRUE(loop);
    int a = 0;
    int b = 0;
    (*loop)->call_at((*loop)->now() + std::chrono::milliseconds(1), [&] { ++a; });
    const auto id = (*loop)->call_at((*loop)->now() + std::chrono::milliseconds(1), [&] { ++b; });
    (*loop)->cancel_timer(id);
    ASSERT_TRUE((*loop)->run_until((*loop)->now() + std::chrono::milliseconds(20)));
    EXPECT_EQ(a, 1);
    EXPECT_EQ(b, 0);
}

TEST(EventLoop, PostFromAnotherThreadAndStop) {
    auto loop = EventLoop::create();
    ASSERT_TRUE(loop);
    EventLoop& l = **loop;
    bool ran = false;
    std::thread t([&] {
        l.post([&] {
            ran = true;
            l.stop();
        });
    });
    ASSERT_TRUE(l.run());
    t.join();
    EXPECT_TRUE(ran);
}

TEST(EventLoop, DeadlineMovedEarlierByAnFdHandlerIsServedInTheSameWakeUp) {
    auto loop = EventLoop::create();
    ASSERT_TRUE(loop);
    EventLoop& l = **loop;
    Periodic p;
    p.period = std::chrono::hours(1);
    p.next = l.now() + std::chrono::seconds(30);
    l.add_timed(&p);
    const int efd = eventfd(0, EFD_NONBLOCK);
    ASSERT_TRUE(l.add_fd(efd, EPOLLIN, [&](std::uint32_t) {
        std::uint64_t v = 0;
        ASSERT_EQ(::read(efd, &v, sizeof(v)), 8);
        p.next = l.now(); // due at once
    }));
    ASSERT_TRUE(l.poll_once(Duration::zero())); // arms the timer for the 30 s deadline
    const std::uint64_t one = 1;
    ASSERT_EQ(::write(efd, &one, sizeof(one)), 8);
    ASSERT_TRUE(l.poll_once(std::chrono::seconds(1)));
    EXPECT_EQ(p.ticks, 1);
    l.remove_timed(&p);
    l.remove_fd(efd);
    ::close(efd);
}

// A remaining time that ran out while it was computed comes out negative. It must not block:
// a controller shutdown hung in epoll_wait(-1) when poll_once() took it as "no limit".
TEST(EventLoop, ANegativeWaitDispatchesWhatIsReadyAndNeverBlocks) {
    auto loop = EventLoop::create();
    ASSERT_TRUE(loop);
    EventLoop& l = **loop;
    Periodic p;
    p.period = std::chrono::hours(1);
    p.next = l.now() + std::chrono::seconds(30); // nothing due for 30 s
    l.add_timed(&p);
    const int efd = eventfd(0, EFD_NONBLOCK);
    int reads = 0;
    ASSERT_TRUE(l.add_fd(efd, EPOLLIN, [&](std::uint32_t) {
        std::uint64_t v = 0;
        ASSERT_EQ(::read(efd, &v, sizeof(v)), 8);
        ++reads;
    }));
    const auto t0 = SteadyClock::now();
    ASSERT_TRUE(l.poll_once(-std::chrono::microseconds(1)));
    ASSERT_TRUE(l.poll_once(std::chrono::milliseconds(-50)));
    EXPECT_LT(SteadyClock::now() - t0, std::chrono::seconds(10)) << "it waited for the timer";
    EXPECT_EQ(reads, 0);
    const std::uint64_t one = 1;
    ASSERT_EQ(::write(efd, &one, sizeof(one)), 8);
    ASSERT_TRUE(l.poll_once(-std::chrono::microseconds(1)));
    EXPECT_EQ(reads, 1) << "what is ready is still dispatched";
    EXPECT_EQ(p.ticks, 0);
    l.remove_timed(&p);
    l.remove_fd(efd);
    ::close(efd);
}

TEST(EventLoop, ForeverWaitsUntilWorkArrives) {
    auto loop = EventLoop::create();
    ASSERT_TRUE(loop);
    EventLoop& l = **loop;
    // Another thread posts work that sets `flag` 50 ms from now.
    const auto post_later = [&l](bool& flag) {
        return std::thread([&l, &flag] {
            std::this_thread::sleep_for(std::chrono::milliseconds(50));
            l.post([&flag] { flag = true; });
        });
    };
    bool ran = false;
    std::thread poster = post_later(ran);
    while (!ran) {
        ASSERT_TRUE(l.poll_once(EventLoop::kForever));
    }
    poster.join();
    EXPECT_TRUE(ran);
    // The same with run_until(): kForever is no deadline (now + kForever would overflow into the
    // past and return at once).
    bool again = false;
    std::thread second = post_later(again);
    EXPECT_TRUE(l.run_until([&] { return again; }, EventLoop::kForever));
    second.join();
}

namespace {

/// A datagram socket pair whose receiving end blocks at most 10 ms: a stand-in for a CAN socket
/// with a direct reader.
struct DirectSocket {
    static constexpr Duration kLimit = std::chrono::milliseconds(10);
    DirectSocket() {
        EXPECT_EQ(::socketpair(AF_UNIX, SOCK_DGRAM | SOCK_CLOEXEC, 0, fds), 0);
        timeval tv{0, 10'000};
        EXPECT_EQ(::setsockopt(fds[0], SOL_SOCKET, SO_RCVTIMEO, &tv, sizeof(tv)), 0);
    }
    ~DirectSocket() {
        ::close(fds[0]);
        ::close(fds[1]);
    }
    DirectSocket(const DirectSocket&) = delete;
    DirectSocket& operator=(const DirectSocket&) = delete;
    void send_one() const {
        const char c = 1;
        EXPECT_EQ(::send(fds[1], &c, 1, 0), 1);
    }
    /// Blocking (up to kLimit) for the first datagram, then what waits behind it.
    std::size_t receive(int flags) {
        std::size_t n = 0;
        char c = 0;
        while (::recv(fds[0], &c, 1, flags) == 1) {
            ++n;
            flags = MSG_DONTWAIT;
        }
        received += n;
        return n;
    }
    void attach(EventLoop& l) {
        ASSERT_TRUE(l.add_fd(fds[0], EPOLLIN, [this](std::uint32_t) {
            ++epoll_wakeups;
            receive(MSG_DONTWAIT);
        }));
        ASSERT_TRUE(l.set_direct_reader(
            fds[0],
            [this] {
                ++direct_reads;
                return EventLoop::DirectRead{receive(0), std::nullopt};
            },
            kLimit));
    }
    int fds[2] = {-1, -1};
    std::size_t received = 0;
    int epoll_wakeups = 0;
    int direct_reads = 0;
};

} // namespace

TEST(EventLoop, LoneSocketWithDirectReaderIsReadWithoutEpoll) {
    auto loop = EventLoop::create();
    ASSERT_TRUE(loop);
    DirectSocket s;
    s.attach(**loop);
    std::thread sender([&] {
        for (int i = 0; i < 20; ++i) {
            s.send_one();
            std::this_thread::sleep_for(std::chrono::milliseconds(1));
        }
    });
    EXPECT_TRUE((*loop)->run_until([&] { return s.received == 20; }, std::chrono::seconds(5)));
    sender.join();
    EXPECT_GT(s.direct_reads, 0);
    EXPECT_EQ(s.epoll_wakeups, 0);
}

TEST(EventLoop, TimersFireOnTimeWhileTheDirectReaderWaits) {
    auto loop = EventLoop::create();
    ASSERT_TRUE(loop);
    DirectSocket s;
    s.attach(**loop);
    Periodic p;
    p.period = std::chrono::milliseconds(60); // more than two block limits: fast path between
    p.next = (*loop)->now() + p.period;
    const TimePoint first = p.next;
    (*loop)->add_timed(&p);
    ASSERT_TRUE((*loop)->run_until([&] { return p.ticks >= 3; }, std::chrono::seconds(5)));
    for (std::size_t i = 0; i < 3; ++i) {
        const TimePoint due = first + p.period * static_cast<int>(i);
        EXPECT_GE(p.times[i], due);
        EXPECT_LT(p.times[i], due + std::chrono::milliseconds(30)) << "tick " << i << " late";
    }
    EXPECT_GT(s.direct_reads, 0);
    (*loop)->remove_timed(&p);
}

TEST(EventLoop, StopFromAnotherThreadEndsADirectReadWithinItsBlockLimit) {
    auto loop = EventLoop::create();
    ASSERT_TRUE(loop);
    DirectSocket s;
    s.attach(**loop);
    std::thread stopper([&] {
        std::this_thread::sleep_for(std::chrono::milliseconds(30));
        (*loop)->stop();
    });
    const auto t0 = std::chrono::steady_clock::now();
    ASSERT_TRUE((*loop)->run());
    stopper.join();
    EXPECT_LT(std::chrono::steady_clock::now() - t0, std::chrono::seconds(1));
    EXPECT_GT(s.direct_reads, 0);
}

TEST(EventLoop, SecondFdOrPostedWorkTurnsTheDirectReaderOff) {
    auto loop = EventLoop::create();
    ASSERT_TRUE(loop);
    EventLoop& l = **loop;
    DirectSocket s;
    s.attach(l);
    const int efd = eventfd(0, EFD_NONBLOCK);
    ASSERT_TRUE(l.add_fd(efd, EPOLLIN, [](std::uint32_t) {}));
    s.send_one();
    EXPECT_TRUE(l.run_until([&] { return s.received == 1; }, std::chrono::seconds(1)));
    EXPECT_EQ(s.direct_reads, 0) << "two fds: the eventfd would never be seen";
    l.remove_fd(efd);
    ::close(efd);

    bool ran = false;
    l.post([&] { ran = true; });
    s.send_one();
    EXPECT_TRUE(l.run_until([&] { return ran && s.received == 2; }, std::chrono::seconds(1)));
    EXPECT_EQ(s.direct_reads, 0) << "post() needs the wake-up eventfd watched";
    EXPECT_EQ(s.epoll_wakeups, 2);
}
