// SPDX-License-Identifier: Apache-2.0
// `codrive sdo read/write` against `codrive sdo serve` in another process on vcan0, and Ctrl-C
// during a transfer.
#include <codrive/core/endian.hpp>
#include <codrive/testing/process.hpp>
#include <codrive/testing/vcan.hpp>
#include <codrive/testing/vcan_recorder.hpp>

#include <gtest/gtest.h>

#include <csignal>
#include <cstdio>
#include <fstream>
#include <iterator>
#include <string>
#include <unistd.h>
#include <vector>

using namespace std::chrono_literals;
using codrive::CanFilter;
using codrive::Frame;
using codrive::get_le;
using codrive::testing::Process;
using codrive::testing::run;
using codrive::testing::tool_path;

namespace {

// A node id no other vcan test uses, so suites sharing vcan0 do not collide.
constexpr const char* kCliNode = "85";

std::vector<std::string> sdo(std::vector<std::string> args) {
    std::vector<std::string> argv{tool_path("codrive"), "sdo"};
    argv.insert(argv.end(), args.begin(), args.end());
    return argv;
}

std::string temp_path(const std::string& name) {
    return "/tmp/codrive-sdo-vcan-" + std::to_string(::getpid()) + "-" + name;
}

std::vector<char> make_file(const std::string& path, std::size_t size) {
    std::vector<char> data(size);
    for (std::size_t i = 0; i < size; ++i) {
        data[i] = static_cast<char>((i * 131U + (i >> 10)) & 0xFFU);
    }
    std::ofstream(path, std::ios::binary).write(data.data(), static_cast<std::streamsize>(size));
    return data;
}

std::vector<char> read_file(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

class SdoVcan : public ::testing::Test {
protected:
    void SetUp() override {
        CODRIVE_REQUIRE_VCAN("vcan0");
        server_ = std::make_unique<Process>(sdo({"serve", "-i", "vcan0", "-n", kCliNode}));
        ASSERT_TRUE(server_->wait_for_output("ready", 10s)) << server_->output();
    }
    void TearDown() override {
        if (server_) {
            const auto t0 = std::chrono::steady_clock::now();
            server_->signal(15);
            const auto status = server_->wait(5s);
            EXPECT_TRUE(status.has_value()) << "sdo serve did not stop on SIGTERM";
            EXPECT_LT(std::chrono::steady_clock::now() - t0, 1s) << "stop took over a second";
            EXPECT_EQ(status.value_or(-1), 0) << server_->output();
            EXPECT_NE(server_->output().find("codrive sdo serve: stopped after"), std::string::npos)
                << server_->output();
        }
    }
    std::unique_ptr<Process> server_;
};

TEST_F(SdoVcan, ExpeditedWriteAndReadOfTypedValues) {
    auto w = run(
        sdo({"write", "-i", "vcan0", "-n", kCliNode, "0x2000:0", "--type", "u32", "0xDEADBEEF"}));
    ASSERT_EQ(w.status, 0) << w.output;
    auto r = run(sdo({"read", "-i", "vcan0", "-n", kCliNode, "2000:00", "--type", "u32"}));
    EXPECT_EQ(r.status, 0) << r.output;
    EXPECT_EQ(r.output, "3735928559\n");
    auto untyped = run(sdo({"read", "-i", "vcan0", "-n", kCliNode, "0x1018:2"}));
    EXPECT_EQ(untyped.status, 0) << untyped.output;
    EXPECT_EQ(untyped.output, "1E D2 C0 00 (0x00C0D21E = 12636702)\n");
}

TEST_F(SdoVcan, SegmentedWriteAndReadOfAString) {
    auto name = run(sdo({"read", "-i", "vcan0", "-n", kCliNode, "0x1008:0", "--type", "str"}));
    EXPECT_EQ(name.status, 0) << name.output;
    EXPECT_EQ(name.output, "codrive sdo serve\n");
    auto w = run(sdo({"write", "-i", "vcan0", "-n", kCliNode, "0x2001:0", "--type", "str",
                      "a segmented string of some length"}));
    ASSERT_EQ(w.status, 0) << w.output;
    auto r = run(sdo({"read", "-i", "vcan0", "-n", kCliNode, "0x2001:0", "--type", "str"}));
    EXPECT_EQ(r.status, 0) << r.output;
    EXPECT_EQ(r.output, "a segmented string of some length\n");
}

TEST_F(SdoVcan, SegmentedFileRoundTrip64KiB) {
    const auto in = temp_path("seg-in");
    const auto out = temp_path("seg-out");
    const auto data = make_file(in, 64 * 1024);
    auto w = run(sdo({"write", "-i", "vcan0", "-n", kCliNode, "0x2001:0", "--file", in}), 120s);
    ASSERT_EQ(w.status, 0) << w.output;
    auto r = run(sdo({"read", "-i", "vcan0", "-n", kCliNode, "0x2001:0", "-o", out}), 120s);
    ASSERT_EQ(r.status, 0) << r.output;
    EXPECT_TRUE(read_file(out) == data);
    std::remove(in.c_str());
    std::remove(out.c_str());
}

TEST_F(SdoVcan, BlockFileRoundTrip1MiB) {
    const auto in = temp_path("blk-in");
    const auto out = temp_path("blk-out");
    const auto data = make_file(in, 1024 * 1024);
    auto w = run(sdo({"write", "-i", "vcan0", "-n", kCliNode, "0x2001:0", "--file", in, "--block"}),
                 120s);
    ASSERT_EQ(w.status, 0) << w.output;
    auto r =
        run(sdo({"read", "-i", "vcan0", "-n", kCliNode, "0x2001:0", "--block", "-o", out}), 120s);
    ASSERT_EQ(r.status, 0) << r.output;
    const auto got = read_file(out);
    EXPECT_EQ(got.size(), data.size());
    EXPECT_TRUE(got == data);
    std::remove(in.c_str());
    std::remove(out.c_str());
}

TEST_F(SdoVcan, ServerAbortIsOneSentenceAndNonZeroExit) {
    auto r = run(sdo({"read", "-i", "vcan0", "-n", kCliNode, "0x6064:0"}));
    EXPECT_EQ(r.status, 1);
    EXPECT_EQ(r.output, "codrive: node 85: SDO upload 0x6064:00 aborted by server: 0x06020000 "
                        "object does not exist in the object dictionary\n");
    auto ro = run(sdo({"write", "-i", "vcan0", "-n", kCliNode, "0x1018:1", "--type", "u32", "1"}));
    EXPECT_EQ(ro.status, 1);
    EXPECT_NE(ro.output.find("0x06010002 attempt to write a read only object"), std::string::npos)
        << ro.output;
}

TEST_F(SdoVcan, MissingNodeTimesOutWithTheConfiguredTimeout) {
    auto r = run(sdo({"read", "-i", "vcan0", "-n", "86", "0x1000:0", "--timeout", "200"}));
    EXPECT_EQ(r.status, 1);
    EXPECT_EQ(r.output, "codrive: node 86: SDO upload 0x1000:00 timed out after 200 ms (no "
                        "response to initiate request)\n");
}

TEST_F(SdoVcan, TypeSizeMismatchIsReported) {
    auto r = run(sdo({"read", "-i", "vcan0", "-n", kCliNode, "0x1018:1", "--type", "u16"}));
    EXPECT_EQ(r.status, 1);
    EXPECT_EQ(r.output, "codrive: node 85: 0x1018:01: the object has 4 bytes, not the 2 of type "
                        "u16\n");
}

TEST(SdoVcanEds, ServeAnswersFromAnEdsDictionary) {
    CODRIVE_REQUIRE_VCAN("vcan0");
    Process server(sdo({"serve", "-i", "vcan0", "-n", "87", "--eds",
                        std::string(CODRIVE_SOURCE_DIR) + "/tests/data/eds/full.eds"}));
    ASSERT_TRUE(server.wait_for_output("ready", 10s)) << server.output();
    auto r = run(sdo({"read", "-i", "vcan0", "-n", "87", "0x1018:1", "--type", "u32"}));
    EXPECT_EQ(r.status, 0) << r.output;
    EXPECT_EQ(r.output, "171\n");
    server.signal(15);
    EXPECT_EQ(server.wait(5s).value_or(-1), 0) << server.output();
}

// Ctrl-C during `codrive sdo write`: the node is sent abort 0x08000000 and the command exits 130
// within a moment, naming node, object and the signal; the server is free for the next request.

// A node id no other vcan test uses.
constexpr unsigned kInterruptNode = 89;

/// The abort frames among `frames`.
std::vector<Frame> aborts_in(const std::vector<Frame>& frames) {
    std::vector<Frame> out;
    for (const Frame& f : frames) {
        if (f.len == 8 && f.data[0] == 0x80) {
            out.push_back(f);
        }
    }
    return out;
}

class SdoInterrupt : public ::testing::TestWithParam<int> {};

TEST_P(SdoInterrupt, TheNodeIsSentAnAbortAndTheCommandExitsAtOnce) {
    CODRIVE_REQUIRE_VCAN("vcan0");
    const int sig = GetParam();
    const std::string node = std::to_string(kInterruptNode);
    Process server(sdo({"serve", "-i", "vcan0", "-n", node}));
    ASSERT_TRUE(server.wait_for_output("ready", 10s)) << server.output();
    // 1 MiB segmented: one round trip per 7 bytes, far longer than the test waits.
    const std::string file =
        "/tmp/codrive-sdo-interrupt-" + std::to_string(::getpid()) + "-" + std::to_string(sig);
    {
        std::ofstream out(file, std::ios::binary);
        const std::string chunk(1024, 'x');
        for (int i = 0; i < 1024; ++i) {
            out << chunk;
        }
    }
    // The master's requests to the node (600h + node).
    codrive::testing::VcanRecorder watch("vcan0", {CanFilter{0x600 + kInterruptNode, 0x7FF}});
    Process write(sdo({"write", "-i", "vcan0", "-n", node, "0x2001:0", "--file", file}));
    // Under way: a hundred segments have gone to the node.
    ASSERT_TRUE(watch.run_until([&] { return watch.frames.size() >= 100; }, 20s))
        << watch.frames.size() << " requests; " << write.output();
    ASSERT_TRUE(aborts_in(watch.frames).empty());
    write.signal(sig);
    const auto t0 = std::chrono::steady_clock::now();
    const auto status = write.wait(5s);
    const auto took = std::chrono::steady_clock::now() - t0;
    ASSERT_TRUE(status.has_value()) << "codrive sdo write did not end on the signal";
    EXPECT_EQ(*status, 128 + sig) << write.output();
    EXPECT_LT(took, 1s);
    const std::string name = sig == SIGINT ? "SIGINT" : "SIGTERM";
    EXPECT_EQ(write.output(), "codrive: node 89: SDO segmented download 0x2001:00 failed: "
                              "cancelled (interrupted by " +
                                  name + ")\n");
    // The abort reached the bus: general error 0x08000000 for 2001h:00 (CiA 301).
    ASSERT_TRUE(watch.run_until([&] { return !aborts_in(watch.frames).empty(); }, 2s))
        << "no SDO abort after the signal; last request " << int{watch.frames.back().data[0]};
    watch.drain();
    EXPECT_EQ(aborts_in(watch.frames).size(), 1U);
    const Frame& last = watch.frames.back(); // the abort, nothing after it
    EXPECT_EQ(last.data[0], 0x80);
    EXPECT_EQ(get_le<std::uint32_t>(last.data.data() + 4), 0x08000000U);
    EXPECT_EQ(last.data[1], 0x01); // 2001h, little endian
    EXPECT_EQ(last.data[2], 0x20);
    EXPECT_EQ(last.data[3], 0x00);
    // The server is idle again: the next request is answered at once.
    auto r = run(sdo({"read", "-i", "vcan0", "-n", node, "0x1008:0", "--type", "str"}));
    EXPECT_EQ(r.status, 0) << r.output;
    EXPECT_EQ(r.output, "codrive sdo serve\n");
    server.signal(SIGTERM);
    EXPECT_EQ(server.wait(5s).value_or(-1), 0) << server.output();
    std::remove(file.c_str());
}

INSTANTIATE_TEST_SUITE_P(Signals, SdoInterrupt, ::testing::Values(SIGINT, SIGTERM),
                         [](const ::testing::TestParamInfo<int>& p) {
                             return std::string(p.param == SIGINT ? "Sigint" : "Sigterm");
                         });

} // namespace
