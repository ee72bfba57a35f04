// SPDX-License-Identifier: Apache-2.0
// TIME_OF_DAY encoding and the TIME producer/consumer (CiA 301 §7.2.6).
#include <codrive/core/virtual_bus.hpp>
#include <codrive/sync/time.hpp>

#include <gtest/gtest.h>

namespace codrive::sync {
namespace {

using namespace std::chrono;

TEST(TimeOfDay, EncodesMillisecondsAndDaysLittleEndian) {
    const TimeOfDay t{0x0123'4567, 0xABCD};
    const auto b = encode(t);
    EXPECT_EQ(b, (std::array<std::uint8_t, 6>{0x67, 0x45, 0x23, 0x01, 0xCD, 0xAB}));
    auto back = decode_time_of_day(b);
    ASSERT_TRUE(back);
    EXPECT_EQ(*back, t);
}

TEST(TimeOfDay, ReservedBitsAreIgnoredAndBadValuesRejected) {
    const std::array<std::uint8_t, 6> reserved{0x00, 0x00, 0x00, 0xF0, 0x01, 0x00};
    auto t = decode_time_of_day(reserved);
    ASSERT_TRUE(t);
    EXPECT_EQ(t->ms_after_midnight, 0U);
    EXPECT_EQ(t->days_since_1984, 1);
    const auto too_many_ms = encode(TimeOfDay{kMsPerDay, 0});
    EXPECT_FALSE(decode_time_of_day(too_many_ms));
    EXPECT_FALSE(decode_time_of_day(std::span<const std::uint8_t>(reserved.data(), 5)));
}

TEST(TimeOfDay, WallClockRoundTrip) {
    const sys_days day = year{2026} / November / 21;
    const auto t = day + hours(5) + minutes(39) + seconds(7) + milliseconds(123);
    auto tod = to_time_of_day(t);
    ASSERT_TRUE(tod);
    EXPECT_EQ(tod->days_since_1984, (day - sys_days{year{1984} / January / 1}).count());
    EXPECT_EQ(tod->ms_after_midnight, ((5 * 60 + 39) * 60 + 7) * 1000U + 123U);
    EXPECT_EQ(to_system_time(*tod), t);
    EXPECT_EQ(to_string(*tod), "2026-11-21 05:39:07.123 UTC");
    EXPECT_EQ(to_string(TimeOfDay{0, 0}), "1984-01-01 00:00:00.000 UTC");
}

TEST(TimeOfDay, OutOfRangeDatesAreRefused) {
    EXPECT_FALSE(to_time_of_day(sys_days{year{1983} / December / 31}));
    EXPECT_FALSE(to_time_of_day(sys_days{year{2200} / January / 1}));
}

TEST(TimeService, ProducerToConsumerOverTheBus) {
    FakeClock clock;
    VirtualNetwork net{clock};
    TimeProducer producer{net.endpoint("master")};
    TimeConsumer consumer;
    VirtualBus& node = net.endpoint("node");
    node.set_frame_handler([&](const Frame& f, TimePoint t) { consumer.on_frame(f, t); });
    int calls = 0;
    consumer.set_handler([&](const TimeOfDay&, TimePoint) { ++calls; });
    EXPECT_FALSE(consumer.network_time(clock.now()));

    const auto wall = sys_days{year{2026} / November / 21} + hours(12);
    ASSERT_TRUE(producer.publish(wall));
    net.deliver();
    ASSERT_TRUE(consumer.has_time());
    EXPECT_EQ(calls, 1);
    EXPECT_EQ(to_system_time(consumer.last()), wall);
    clock.advance(milliseconds(250));
    auto now = consumer.network_time(clock.now());
    ASSERT_TRUE(now);
    EXPECT_EQ(*now, wall + milliseconds(250));
}

TEST(TimeService, MalformedTimeIsCounted) {
    FakeClock clock;
    TimeConsumer consumer;
    consumer.on_frame(Frame::make(0x100, {1, 2, 3}), clock.now());
    EXPECT_EQ(consumer.malformed(), 1U);
    EXPECT_FALSE(consumer.has_time());
}

} // namespace
} // namespace codrive::sync
