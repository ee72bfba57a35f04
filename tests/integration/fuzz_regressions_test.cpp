// SPDX-License-Identifier: Apache-2.0
// Regression tests for defects the fuzzers (reproducers in tests/data/fuzz/regressions/) and the
// fault-injection runs found.
#include "mini_device.hpp"

#include <codrive/core/cob_id.hpp>
#include <codrive/core/virtual_bus.hpp>
#include <codrive/ethercat/esi.hpp>
#include <codrive/master/bus_config.hpp>
#include <codrive/sdo/client.hpp>

#include <gtest/gtest.h>

#include <algorithm>
#include <fstream>
#include <functional>
#include <iterator>
#include <optional>
#include <string>
#include <vector>

using namespace codrive;

// fuzz_sdo_client, regressions/sdo_client/abort_code_zero: a server abort frame whose code
// field is 0 (a short "80 00 10" frame padded with zeros, or a device that sends code 0) ends
// the transfer with an SdoError whose `cause` is error_code(0, sdo_abort_category) — a value
// that converts to false, so `if (error.cause)` reads the failure as success.
TEST(FuzzRegression, SdoClientAbortWithCodeZeroStillCarriesAnErrorCause) {
    FakeClock clock;
    VirtualNetwork net(clock);
    VirtualBus& client_bus = net.endpoint("client");
    VirtualBus& server_bus = net.endpoint("server");
    sdo::ClientConfig config;
    config.node = 9;
    sdo::SdoClient client(client_bus, clock, config);
    client_bus.set_frame_handler([&](const Frame& f, TimePoint t) { client.on_frame(f, t); });

    std::optional<sdo::SdoResult<sdo::Bytes>> result;
    client.upload(0x1000, 0, [&](sdo::SdoResult<sdo::Bytes> r) { result = std::move(r); });
    net.deliver();
    ASSERT_TRUE(server_bus.send(Frame::make(cob::sdo_tx(9), {0x80, 0x00, 0x10})));
    net.deliver();

    ASSERT_TRUE(result.has_value()) << "the transfer did not end";
    ASSERT_FALSE(result->has_value()) << "an abort is not a success";
    const sdo::SdoError& e = result->error();
    EXPECT_TRUE(static_cast<bool>(e.cause))
        << "cause is " << e.cause.category().name() << ":" << e.cause.value()
        << ", which tests as 'no error'; text: " << e.to_string();
    EXPECT_EQ(e.to_string().rfind("node 9: SDO", 0), 0U) << e.to_string();
}

// fuzz_bus_config, regressions/bus_config/yaml_invalid_node_exception.yml: a truncated bus file
// (the example with its axes cut off mid-line) makes yaml-cpp throw YAML::InvalidNode out of
// parse_bus_config(), which must report findings instead of throwing.
TEST(FuzzRegression, BusConfigTruncatedFileGivesFindingsNotAnException) {
    const std::string path =
        std::string(CODRIVE_SOURCE_DIR) +
        "/tests/data/fuzz/regressions/bus_config/yaml_invalid_node_exception.yml";
    std::ifstream file(path, std::ios::binary);
    ASSERT_TRUE(file) << path;
    const std::string yaml((std::istreambuf_iterator<char>(file)),
                           std::istreambuf_iterator<char>());
    std::optional<master::BusConfigResult> result;
    EXPECT_NO_THROW(result = master::parse_bus_config(yaml, "bus.yml"));
    if (result) {
        EXPECT_EQ(result->config.has_value(), result->errors.empty());
    }
}

// fuzz_ecat_esi (bench/fuzz_long.sh, 1,648,666 executions), regressions/ecat_esi/
// object_defined_twice.xml: an ESI whose dictionary defines object 607Ah twice was accepted, and
// every lookup found the first definition, so the second one's entries could not be found. The
// file is refused with a sentence naming both lines.
TEST(FuzzRegression, EsiObjectDefinedTwiceIsRefusedWithBothLines) {
    const std::string path = std::string(CODRIVE_SOURCE_DIR) +
                             "/tests/data/fuzz/regressions/ecat_esi/object_defined_twice.xml";
    std::ifstream file(path, std::ios::binary);
    ASSERT_TRUE(file) << path;
    const std::string xml((std::istreambuf_iterator<char>(file)), std::istreambuf_iterator<char>());
    const auto esi = ethercat::parse_esi(xml, "fio.xml");
    ASSERT_FALSE(esi);
    EXPECT_EQ(esi.error(), "fio.xml:26: object 607Ah is defined twice (first at line 25)");
}

// Found by the bus-off fault-injection test: while the bus refuses every send (bus-off), a
// request that fails inside start() completes through finish() → start_next() → start() →
// fail() → finish(), one stack level per failed transfer. An application that re-submits from
// its completion callback (a plain retry loop) then recursed without bound: 100,000 retries
// overflowed the stack. The nesting depth of the callbacks must stay constant, and one call
// must not loop forever either (the rest of the retries run from on_tick()).
TEST(FaultRegression, SdoClientRetryFromCallbackDuringBusOffDoesNotNest) {
    FakeClock clock;
    VirtualNetwork net(clock);
    VirtualBus& client_bus = net.endpoint("client");
    (void)net.endpoint("server");
    sdo::ClientConfig config;
    config.node = 3;
    sdo::SdoClient client(client_bus, clock, config);
    net.set_bus_off(true);

    const char* first = nullptr;
    std::ptrdiff_t growth = 0;
    int failures = 0;
    constexpr int kRetries = 100'000;
    std::function<void()> submit;
    submit = [&] {
        client.upload(0x1000, 0, [&](sdo::SdoResult<sdo::Bytes> r) {
            const char marker = 0;
            const char* here = &marker;
            if (first == nullptr) {
                first = here;
            }
            growth = std::max(growth, first - here);
            EXPECT_FALSE(r.has_value());
            if (r) {
                return;
            }
            EXPECT_EQ(r.error().cause, make_error_code(sdo::SdoErrc::SendFailed));
            if (++failures < kRetries) {
                submit(); // retry at once
            }
        });
    };
    submit();
    EXPECT_LT(failures, kRetries) << "one call ran every retry: it must hand over to on_tick()";
    for (int tick = 0; tick < kRetries && failures < kRetries; ++tick) {
        ASSERT_LE(client.next_deadline(), clock.now()) << "deferred retries must be due at once";
        client.on_tick(clock.now());
    }
    EXPECT_EQ(failures, kRetries);
    EXPECT_FALSE(client.busy());
    EXPECT_LT(growth, 16 * 1024) << "the stack grew by " << growth << " bytes over " << kRetries
                                 << " retries: each retry nests inside the client";
}

// The frame storm of the 1 % loss/duplication run (hundreds of thousands of block segments in
// flight): a block upload acknowledgement delivered twice (CAN repeats a frame after an ACK
// error) made the server send a sub-block per copy, and the client acknowledge each copy.
TEST(FaultRegression, SdoBlockUploadDuplicatedAckCausesNoFrameStorm) {
    FakeClock clock;
    VirtualNetwork net(clock, microseconds(100));
    VirtualBus& client_bus = net.endpoint("client");
    VirtualBus& device_bus = net.endpoint("device");
    integration::MiniDevice device(device_bus, 2);
    device.power_on(clock.now());
    sdo::ClientConfig config;
    config.node = 2;
    config.timeout = milliseconds(200);
    sdo::SdoClient client(client_bus, clock, config);
    client_bus.set_frame_handler([&](const Frame& f, TimePoint t) { client.on_frame(f, t); });
    // Every block upload acknowledgement (client → server, A2h) arrives twice.
    net.set_fault_filter([](const std::string& from, const Frame& f) {
        FaultAction a;
        if (from == "client" && f.len == 8 && f.data[0] == 0xA2) {
            a.duplicates = 1;
        }
        return a;
    });
    std::optional<sdo::SdoResult<sdo::Bytes>> result;
    sdo::TransferOptions options;
    options.mode = sdo::Mode::Block;
    client.upload(
        integration::kReference + 7, 0, // 8192 bytes
        [&](sdo::SdoResult<sdo::Bytes> r) { result = std::move(r); }, options);
    const std::vector<ITimed*> timed{&client, &device};
    for (int i = 0; i < 2000 && !result && net.frames_sent() < 200'000; ++i) {
        net.run_until(clock, clock.now() + milliseconds(1), timed);
    }
    // 8192 bytes are 1171 segments plus a few dozen control frames.
    EXPECT_LT(net.frames_sent(), 3000U) << "frame storm";
    ASSERT_TRUE(result.has_value()) << "the transfer never ended";
    if (result->has_value()) {
        EXPECT_EQ(**result, integration::reference_pattern(8192));
    }
}

// The trigger of the frame storm: a copy of a sub-block's last segment (seqno = blksize) that
// arrives after the client acknowledged that sub-block — a CAN repeat, or a frame delayed past
// the acknowledgement. The client took it for the end of the next sub-block with a gap and
// acknowledged again (ackseq 0); the server answered with the whole sub-block a second time.
// From then on two sub-blocks were in flight, each answered by one acknowledgement that makes
// the server send another, so the surplus never drained, the second copy was stored as the next
// sub-block (wrong data, caught only by the CRC), and every further repeated last segment added
// one more sub-block: growth at the duplication rate per round trip, 360,000 frames in flight
// within 0.43 s of the 1 % run.
TEST(FaultRegression, SdoBlockUploadLateLastSegmentOfSubBlockCausesNoSecondSubBlock) {
    FakeClock clock;
    VirtualNetwork net(clock, microseconds(100));
    VirtualBus& client_bus = net.endpoint("client");
    VirtualBus& device_bus = net.endpoint("device");
    VirtualBus& ghost = net.endpoint("ghost"); // re-sends the copy, as the bus would
    integration::MiniDevice device(device_bus, 2);
    device.power_on(clock.now());
    sdo::ClientConfig config;
    config.node = 2;
    config.timeout = milliseconds(200);
    sdo::SdoClient client(client_bus, clock, config);
    client_bus.set_frame_handler([&](const Frame& f, TimePoint t) { client.on_frame(f, t); });
    std::optional<Frame> last_of_first_sub_block;
    std::uint64_t block_segments = 0;
    net.set_fault_filter([&](const std::string& from, const Frame& f) {
        if (from == "device" && f.id == 0x582) {
            ++block_segments;
            if (!last_of_first_sub_block && f.data[0] == 0x7F) { // seqno 127 of sub-block 1
                last_of_first_sub_block = f;
            }
        }
        return FaultAction{};
    });
    const std::vector<ITimed*> timed{&client, &device};
    net.run_until(clock, clock.now() + milliseconds(1), timed); // the boot-up message passes
    std::optional<sdo::SdoResult<sdo::Bytes>> result;
    sdo::TransferOptions options;
    options.mode = sdo::Mode::Block;
    client.upload(
        integration::kReference + 8, 0, // 65536 bytes: 9,363 segments
        [&](sdo::SdoResult<sdo::Bytes> r) { result = std::move(r); }, options);
    bool resent = false;
    for (int i = 0; i < 20'000 && !result && net.frames_sent() < 200'000; ++i) {
        net.run_until(clock, clock.now() + microseconds(100), timed);
        if (last_of_first_sub_block && !resent) {
            resent = true; // the first sub-block is acknowledged by now
            (void)ghost.send(*last_of_first_sub_block);
        }
    }
    ASSERT_TRUE(resent);
    ASSERT_TRUE(result.has_value()) << "the transfer never ended";
    ASSERT_TRUE(result->has_value()) << result->error().to_string();
    EXPECT_EQ(**result, integration::reference_pattern(65536));
    // Each segment once, plus the initiate response and the end frame.
    EXPECT_LE(block_segments, 9363U + 80U) << "a sub-block was sent twice";
}
