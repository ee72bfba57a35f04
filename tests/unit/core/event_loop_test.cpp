// SPDX-License-Identifier: Apache-2.0
// The epoll/timerfd event loop (real time, short waits).
#include <codrive/core/event_loop.hpp>

#include <gtest/gtest.h>

#include <sys/epoll.h>
#include <sys/eventfd.h>
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
