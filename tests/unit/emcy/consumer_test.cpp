// SPDX-License-Identifier: Apache-2.0
// EMCY consumer (history, active errors, reset) and producer (inhibit time) on the virtual bus.
#include <codrive/core/virtual_bus.hpp>
#include <codrive/emcy/consumer.hpp>
#include <codrive/emcy/producer.hpp>

#include <gtest/gtest.h>

#include <vector>

namespace codrive::emcy {
namespace {

class EmcyTest : public ::testing::Test {
protected:
    FakeClock clock;
    VirtualNetwork net{clock};
    VirtualBus& master_bus = net.endpoint("master");
    VirtualBus& node_bus = net.endpoint("node3");
    EmcyConsumer consumer;
    EmcyProducer producer{node_bus, 3};
    std::vector<EmcyEvent> events;
    std::vector<TimePoint> arrivals;

    void SetUp() override {
        master_bus.set_frame_handler([this](const Frame& f, TimePoint t) {
            if (consumer.on_frame(f, t)) {
                arrivals.push_back(t);
            }
        });
        consumer.set_handler([this](const EmcyEvent& e) { events.push_back(e); });
    }
    void run_for(Duration d) { net.run_until(clock, clock.now() + d, {&producer}); }
};

TEST_F(EmcyTest, ConsumerReportsSentenceAndTracksActiveErrors) {
    ASSERT_TRUE(producer.send(0x2310, 0x03, {0, 1, 2, 3, 4}, clock.now()));
    net.deliver();
    ASSERT_EQ(events.size(), 1U);
    EXPECT_FALSE(events[0].reset);
    EXPECT_EQ(events[0].text, "node 3: EMCY 0x2310 continuous over-current (error register 0x03: "
                              "generic, current) [manufacturer 00 01 02 03 04]");
    EXPECT_TRUE(consumer.active(3).any());
    EXPECT_TRUE(consumer.active(3).contains(0x2310));
    ASSERT_TRUE(producer.send(0x4310, 0x09, {}, clock.now()));
    net.deliver();
    EXPECT_EQ(consumer.active(3).count, 2U);
    EXPECT_EQ(consumer.active(3).error_register, 0x09);
}

TEST_F(EmcyTest, ErrorResetClearsActiveStateButKeepsHistory) {
    ASSERT_TRUE(producer.send(0x8611, 0x21, {}, clock.now()));
    ASSERT_TRUE(producer.send_reset(0x00, clock.now()));
    net.deliver();
    ASSERT_EQ(events.size(), 2U);
    EXPECT_TRUE(events[1].reset);
    EXPECT_FALSE(consumer.active(3).any());
    ASSERT_EQ(consumer.history(3).size(), 2U);
    EXPECT_EQ(consumer.history(3)[0].message.error_code, 0x0000);
    EXPECT_EQ(consumer.history(3)[1].message.error_code, 0x8611);
}

TEST_F(EmcyTest, HistoryIsBoundedNewestFirst) {
    for (std::uint16_t i = 0; i < 40; ++i) {
        ASSERT_TRUE(node_bus.send(
            make_emcy_frame(EmcyMessage{3, static_cast<std::uint16_t>(0x1000 + i), 1, {}, 8})));
    }
    net.deliver();
    const auto& h = consumer.history(3);
    ASSERT_EQ(h.size(), EmcyHistory::kCapacity);
    EXPECT_EQ(h.dropped(), 40U - EmcyHistory::kCapacity);
    EXPECT_EQ(h[0].message.error_code, 0x1000 + 39);
    EXPECT_EQ(h[EmcyHistory::kCapacity - 1].message.error_code, 0x1000 + 40 - 16);
    EXPECT_EQ(consumer.active(3).count, ActiveErrors::kMaxCodes);
    EXPECT_TRUE(consumer.active(3).contains(0x1000 + 39));
    EXPECT_FALSE(consumer.active(3).contains(0x1000));
    EXPECT_TRUE(consumer.history(4).empty());
}

TEST_F(EmcyTest, InhibitTimeSpacesMessages) {
    producer.set_inhibit_time(50); // 5 ms
    const TimePoint t0 = clock.now();
    ASSERT_TRUE(producer.send(0x2310, 0x03, {}, t0));
    ASSERT_TRUE(producer.send(0x3210, 0x05, {}, t0));
    ASSERT_TRUE(producer.send(0x4310, 0x09, {}, t0));
    EXPECT_EQ(producer.queued(), 2U);
    EXPECT_EQ(producer.next_deadline(), t0 + milliseconds(5));
    run_for(milliseconds(20));
    ASSERT_EQ(arrivals.size(), 3U);
    EXPECT_EQ(arrivals[0], t0);
    EXPECT_EQ(arrivals[1], t0 + milliseconds(5));
    EXPECT_EQ(arrivals[2], t0 + milliseconds(10));
    EXPECT_EQ(events[2].message.error_code, 0x4310); // order kept
    EXPECT_EQ(producer.next_deadline(), kNever);
}

TEST_F(EmcyTest, MessageAfterInhibitTimeGoesOutImmediately) {
    producer.set_inhibit_time(10); // 1 ms
    ASSERT_TRUE(producer.send(0x2310, 0x03, {}, clock.now()));
    clock.advance(microseconds(1000));
    ASSERT_TRUE(producer.send(0x2310, 0x03, {}, clock.now()));
    EXPECT_EQ(producer.queued(), 0U);
    EXPECT_EQ(producer.sent(), 2U);
}

TEST_F(EmcyTest, FullInhibitQueueRefusesWithTxQueueFull) {
    producer.set_inhibit_time(1000);
    ASSERT_TRUE(producer.send(0x1000, 1, {}, clock.now()));
    for (std::size_t i = 0; i < EmcyProducer::kQueueCapacity; ++i) {
        ASSERT_TRUE(producer.send(0x1000, 1, {}, clock.now()));
    }
    auto r = producer.send(0x1000, 1, {}, clock.now());
    ASSERT_FALSE(r);
    EXPECT_EQ(r.error(), make_error_code(CoreErrc::TxQueueFull));
    EXPECT_EQ(producer.dropped(), 1U);
}

TEST_F(EmcyTest, PerNodeProviderOverridesDefault) {
    static constexpr EmcyTextEntry kVendor[] = {{0x2310, "vendor node 3"}};
    static constexpr EmcyTextEntry kOther[] = {{0x2310, "default vendor"}};
    consumer.set_text_provider(std::make_shared<EmcyTextTable>(kOther));
    consumer.set_text_provider(3, std::make_shared<EmcyTextTable>(kVendor));
    EmcyMessage m{3, 0x2310, 0x03, {}, 8};
    EXPECT_NE(consumer.describe(m).find("continuous over-current: vendor node 3"),
              std::string::npos);
    m.node = 4;
    EXPECT_NE(consumer.describe(m).find("continuous over-current: default vendor"),
              std::string::npos);
}

TEST_F(EmcyTest, MalformedAndForeignFramesAreCountedOrIgnored) {
    ASSERT_TRUE(node_bus.send(Frame::make(0x083, {0x10})));
    ASSERT_TRUE(node_bus.send(Frame::make(0x080, {})));        // SYNC
    ASSERT_TRUE(node_bus.send(Frame::make(0x183, {1, 2, 3}))); // TPDO
    ASSERT_TRUE(node_bus.send(Frame::make(0x083, {0x10, 0x23, 0x03})));
    net.deliver();
    EXPECT_EQ(consumer.malformed(), 1U);
    EXPECT_EQ(consumer.received(), 1U);
    EXPECT_EQ(consumer.short_frames(), 1U);
    ASSERT_EQ(events.size(), 1U);
    EXPECT_NE(events[0].text.find("(short frame: 3 bytes)"), std::string::npos);
}

} // namespace
} // namespace codrive::emcy
