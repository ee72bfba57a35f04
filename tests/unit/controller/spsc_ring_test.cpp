// SPDX-License-Identifier: Apache-2.0
// The lock-free ring between the cyclic and the acyclic thread: order, capacity, wrap-around.
#include "../../../controller/src/spsc_ring.hpp"

#include <gtest/gtest.h>

#include <string>

using codrive::controller::SpscRing;

TEST(SpscRing, KeepsOrderAndRefusesPushWhenFullWithoutTouchingTheValue) {
    SpscRing<std::string, 4> ring;
    for (int i = 0; i < 4; ++i) {
        std::string v = "v" + std::to_string(i);
        ASSERT_TRUE(ring.push(v));
    }
    std::string extra = "extra";
    EXPECT_FALSE(ring.push(extra));
    EXPECT_EQ(extra, "extra"); // the caller can still fail the request with it
    std::string out;
    for (int i = 0; i < 4; ++i) {
        ASSERT_TRUE(ring.pop(out));
        EXPECT_EQ(out, "v" + std::to_string(i));
    }
    EXPECT_FALSE(ring.pop(out));
    EXPECT_TRUE(ring.empty());
}

TEST(SpscRing, WrapsAroundManyTimes) {
    SpscRing<int, 8> ring;
    int next_in = 0;
    int next_out = 0;
    for (int round = 0; round < 1000; ++round) {
        for (int k = 0; k < 5; ++k) {
            int v = next_in;
            if (ring.push(v)) {
                ++next_in;
            }
        }
        int out = 0;
        for (int k = 0; k < 4 && ring.pop(out); ++k) {
            EXPECT_EQ(out, next_out++);
        }
    }
    EXPECT_GT(next_out, 3000);
}
