// SPDX-License-Identifier: Apache-2.0
// The soak's wire counter (tests/support soak.hpp): a TPDO that is late at the window's end is
// not lost, a TPDO that never comes is, whatever the lateness around it.
#include <codrive/testing/soak.hpp>

#include <gtest/gtest.h>

namespace {

using codrive::Frame;
using codrive::TimePoint;
using codrive::testing::soak_detail::WireCounter;

Frame frame(std::uint32_t id) {
    Frame f;
    f.id = id;
    f.len = id == 0x080 ? 0 : 2;
    return f;
}

/// Feeds `syncs` SYNCs; after SYNC k the TPDO 0x181 answers every SYNC whose turn `answers(k)`
/// says (how many frames of the stream follow SYNC k).
template <typename F>
WireCounter run(std::uint64_t limit, std::uint64_t syncs, F answers) {
    WireCounter w;
    w.limit = limit;
    TimePoint t{};
    for (std::uint64_t k = 1; k <= syncs && !w.done; ++k) {
        w.on_frame(frame(0x080), t);
        for (int n = answers(k); n > 0; --n) {
            w.on_frame(frame(0x181), t);
        }
        t += std::chrono::milliseconds(2);
    }
    w.close_now();
    return w;
}

TEST(SoakWireCounter, OnTimeStreamHasNoDeficit) {
    const auto w = run(100, 200, [](std::uint64_t) { return 1; });
    EXPECT_TRUE(w.done);
    EXPECT_EQ(w.syncs, 100U);
    EXPECT_EQ(w.in_window[0x181], 100U);
    EXPECT_EQ(w.min_deficit[0x181], 0);
    EXPECT_EQ(w.late[0x181], 0U);
}

TEST(SoakWireCounter, StreamLateByOneAtTheWindowsEndIsNotLost) {
    // From SYNC 95 on the answer comes one interval late (nothing after SYNC 95, two after 97),
    // and the stream trails by one across the window's end until SYNC 120, where it catches up.
    const auto w = run(100, 200, [](std::uint64_t k) {
        if (k == 95) {
            return 0;
        }
        return k == 120 ? 2 : 1;
    });
    EXPECT_EQ(w.deficit_at_close[0x181], 1) << "one answer still in flight at the end";
    EXPECT_EQ(w.min_deficit[0x181], 0) << "caught up during the grace intervals: nothing lost";
    EXPECT_EQ(w.late[0x181], 1U);
}

TEST(SoakWireCounter, AnswerThatNeverComesIsLostEvenWhenTheStreamIsLateAroundIt) {
    // SYNC 40 is never answered; later the stream is late by one for a while and catches up.
    const auto w = run(100, 200, [](std::uint64_t k) {
        if (k == 40 || k == 98) {
            return 0;
        }
        return k == 130 ? 2 : 1;
    });
    EXPECT_EQ(w.min_deficit[0x181], 1);
}

TEST(SoakWireCounter, AnswersToTheSyncBeforeTheWindowAreNotCounted) {
    WireCounter w;
    w.limit = 10;
    w.on_frame(frame(0x181), TimePoint{}); // before the first SYNC: not counted at all
    const auto fed = run(10, 100, [](std::uint64_t k) { return k == 1 ? 2 : 1; });
    EXPECT_EQ(fed.leading_extra[0x181], 1U);
    EXPECT_EQ(fed.min_deficit[0x181], 0);
    EXPECT_EQ(w.total[0x181], 0U);
}

} // namespace
