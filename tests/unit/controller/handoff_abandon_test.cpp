// SPDX-License-Identifier: Apache-2.0
// HandoffTransport at shutdown: accesses the executing thread never started end with a sentence
// naming the device, the object and the reason, each callback once, when the side that now owns
// the executing end abandons them; accesses already started complete as usual.
#include "../../../controller/src/handoff_transport.hpp"

#include <codrive/testing/no_cyclic_transport.hpp>

#include <gtest/gtest.h>

#include <functional>
#include <optional>
#include <string>
#include <vector>

namespace codrive::controller {
namespace {

/// The executing side's transport: remembers each started access and answers it on answer().
class ParkingTransport final : public codrive::testing::NoCyclicTransport {
public:
    [[nodiscard]] std::string name() const override { return "slave 1 (AKD2G)"; }
    void read(std::uint16_t, std::uint8_t, ReadDone done) override {
        reads.push_back(std::move(done));
    }
    void write(std::uint16_t, std::uint8_t, drives::Bytes, WriteDone done) override {
        writes.push_back(std::move(done));
    }
    std::vector<ReadDone> reads;
    std::vector<WriteDone> writes;
};

TEST(HandoffAbandon, AccessesNeverStartedEndWithTheirSentenceAndStartedOnesStillComplete) {
    ParkingTransport inner;
    HandoffTransport handoff(inner, "cyclic thread");
    std::vector<std::string> ended;
    std::optional<drives::DriveResult<drives::Bytes>> started;
    handoff.read(0x1018, 1, [&](drives::DriveResult<drives::Bytes> r) { started = std::move(r); });
    ASSERT_EQ(handoff.pump_requests(), 1U); // this one reached the wrapped transport
    handoff.read(0x6502, 0, [&](drives::DriveResult<drives::Bytes> r) {
        ASSERT_FALSE(r);
        EXPECT_EQ(r.error().code, make_error_code(drives::DriveErrc::Transport));
        ended.push_back(r.error().message);
    });
    handoff.write(0x6081, 0, drives::Bytes{0xE8, 0x03, 0, 0}, [&](drives::DriveVoid r) {
        ASSERT_FALSE(r);
        ended.push_back(r.error().message);
    });

    // The executing thread has stopped: its end now belongs to the caller.
    EXPECT_EQ(handoff.abandon_requests("the controller shut down before the slave answered"), 2U);
    EXPECT_TRUE(ended.empty()) << "callbacks run from deliver_completions(), on the requester";
    EXPECT_EQ(handoff.deliver_completions(), 2U);
    ASSERT_EQ(ended.size(), 2U);
    EXPECT_EQ(ended[0], "slave 1 (AKD2G): read of object 6502h:00h cancelled: the controller "
                        "shut down before the slave answered");
    EXPECT_EQ(ended[1], "slave 1 (AKD2G): write of object 6081h:00h cancelled: the controller "
                        "shut down before the slave answered");
    EXPECT_TRUE(inner.writes.empty()) << "an abandoned access never reaches the transport";

    // The access already started completes through its slot as before.
    ASSERT_EQ(inner.reads.size(), 1U);
    inner.reads[0](drives::Bytes{0x6A, 0, 0, 0});
    EXPECT_EQ(handoff.deliver_completions(), 1U);
    ASSERT_TRUE(started && *started);
    EXPECT_EQ(**started, (drives::Bytes{0x6A, 0, 0, 0}));

    // Every slot is free again: a full set of accesses is taken, not refused.
    std::size_t abandoned = 0;
    for (std::size_t i = 0; i < HandoffTransport::kSlots; ++i) {
        handoff.read(0x1000, 0, [&](drives::DriveResult<drives::Bytes> r) {
            ASSERT_FALSE(r);
            EXPECT_NE(r.error().message.find("cancelled: end of test"), std::string::npos)
                << r.error().message; // not "too many object accesses waiting"
            ++abandoned;
        });
    }
    EXPECT_EQ(abandoned, 0U) << "refused at once: a slot was lost";
    EXPECT_EQ(handoff.abandon_requests("end of test"), HandoffTransport::kSlots);
    EXPECT_EQ(handoff.deliver_completions(), HandoffTransport::kSlots);
    EXPECT_EQ(abandoned, HandoffTransport::kSlots);
    EXPECT_EQ(handoff.abandon_requests("nothing left"), 0U);
}

} // namespace
} // namespace codrive::controller
