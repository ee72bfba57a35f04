// SPDX-License-Identifier: Apache-2.0
// Vector BLF reader: every CAN object kind, zlib and stored containers, objects across container
// boundaries, skipped objects, and corrupt files (one sentence with the byte offset, no crash).
#include "blf_test_writer.hpp"
#include "dump_test_util.hpp"

#include <codrive/core/socket_can_bus.hpp>
#include <codrive/dump/blf_reader.hpp>
#include <codrive/dump/error_frame_build.hpp>

#include <gtest/gtest.h>
#include <linux/can/error.h>

#include <algorithm>
#include <cstdlib>
#include <fstream>

using namespace codrive;
using namespace codrive::dump;
using codrive::dump::testing::blf_event_object;
using codrive::dump::testing::blf_file;
using codrive::dump::testing::blf_object;
using codrive::dump::testing::BlfEvent;
using codrive::dump::testing::BlfWriteOptions;
using codrive::dump::testing::frames_of;
using codrive::dump::testing::read_trace;
using codrive::dump::testing::ReadItem;
using codrive::dump::testing::slurp;
using codrive::dump::testing::trace_path;

namespace {

std::vector<ReadItem> conversation() {
    return frames_of(read_trace(slurp(trace_path("formats/conversation.log"))));
}

std::vector<BlfEvent> events_of(const std::vector<ReadItem>& items, BlfObjectType type) {
    std::vector<BlfEvent> events;
    for (const auto& i : items) {
        events.push_back({i.frame, i.ts_ns, 1, type});
    }
    return events;
}

void expect_same_frames(const std::vector<ReadItem>& got, const std::vector<ReadItem>& want,
                        const std::string& what) {
    ASSERT_EQ(got.size(), want.size()) << what;
    for (std::size_t i = 0; i < got.size(); ++i) {
        ASSERT_EQ(got[i].status, ReadStatus::Frame) << what << ": " << got[i].error;
        EXPECT_EQ(got[i].frame, want[i].frame) << what << " frame " << i;
        EXPECT_EQ(got[i].ts_ns, want[i].ts_ns) << what << " frame " << i;
        EXPECT_EQ(got[i].iface, "can1") << what;
    }
}

// The last step of reading `bytes`: End, or Fatal with its sentence.
ReadItem last_step(const std::string& bytes) {
    auto in = BufferedInput::from_memory(bytes);
    BlfReader reader(*in);
    TraceRecord r;
    for (std::size_t steps = 0; steps <= bytes.size() + 2; ++steps) {
        const auto s = reader.next(r);
        if (s == ReadStatus::End || s == ReadStatus::Fatal) {
            return {s, r.frame, r.ts_ns, r.has_ts, {}, std::string(reader.error())};
        }
    }
    ADD_FAILURE() << "the reader does not advance";
    return {};
}

Frame frame_with(std::uint32_t id, std::uint8_t flags, std::uint8_t len) {
    Frame f;
    f.id = id;
    f.flags = flags;
    f.len = len;
    for (std::uint8_t i = 0; i < len && (flags & Frame::kRtr) == 0; ++i) {
        f.data[i] = static_cast<std::uint8_t>(0xA0 + i);
    }
    return f;
}

} // namespace

TEST(DumpBlf, EveryCanObjectKindCarriesTheConversationWithItsTimestamps) {
    const auto want = conversation();
    ASSERT_EQ(want.size(), 12U);
    for (const auto type : {BlfObjectType::CanMessage, BlfObjectType::CanMessage2,
                            BlfObjectType::CanFdMessage, BlfObjectType::CanFdMessage64}) {
        for (const bool compress : {true, false}) {
            for (const int version : {1, 2}) {
                BlfWriteOptions o;
                o.compress = compress;
                o.header_version = static_cast<std::uint16_t>(version);
                o.container_bytes = 100; // objects of 48..120 bytes: most span two containers
                TraceFormat format{};
                const auto got = read_trace(blf_file(events_of(want, type), o), &format);
                EXPECT_EQ(format, TraceFormat::VectorBlf);
                expect_same_frames(got, want,
                                   "type " + std::to_string(static_cast<int>(type)) +
                                       (compress ? " zlib" : " stored") + " header v" +
                                       std::to_string(version));
            }
        }
    }
}

TEST(DumpBlf, TenMicrosecondTimestampsCountFromTheMeasurementStart) {
    auto want = conversation();
    BlfWriteOptions o;
    o.ten_micros = true;
    const auto got = frames_of(read_trace(blf_file(events_of(want, BlfObjectType::CanMessage), o)));
    expect_same_frames(got, want, "10 us units"); // the conversation is on a 10 us grid
    EXPECT_EQ(got[3].ts_ns, 1'795'478'400'021'000'000LL);
}

TEST(DumpBlf, CanFdBrsRemoteExtendedAndErrorFrames) {
    const std::int64_t t0 = 1'795'478'400'000'000'000LL;
    const Frame fd64 = frame_with(0x123, Frame::kFd | Frame::kBrs, 64);
    const Frame fd12 = frame_with(0x1ABCDEF, Frame::kFd | Frame::kExtended, 12);
    const Frame classic = frame_with(0x181, 0, 8);
    const Frame remote = frame_with(0x705, Frame::kRtr, 1);
    const std::vector<BlfEvent> events = {
        {fd64, t0 + 1000, 2, BlfObjectType::CanFdMessage},
        {fd12, t0 + 2000, 2, BlfObjectType::CanFdMessage64},
        {classic, t0 + 3000, 2, BlfObjectType::CanFdMessage64},
        {remote, t0 + 4000, 2, BlfObjectType::CanFdMessage64},
        {remote, t0 + 5000, 2, BlfObjectType::CanFdMessage},
        {Frame{}, t0 + 6000, 3, BlfObjectType::CanErrorExt},
        {Frame{}, t0 + 7000, 3, BlfObjectType::CanError},
    };
    const auto got = read_trace(blf_file(events));
    ASSERT_EQ(got.size(), events.size());
    for (std::size_t i = 0; i < 5; ++i) {
        ASSERT_EQ(got[i].status, ReadStatus::Frame) << i << ": " << got[i].error;
        EXPECT_EQ(got[i].frame, events[i].frame) << i;
        EXPECT_EQ(got[i].ts_ns, events[i].ts_ns) << i;
        EXPECT_EQ(got[i].iface, "can2");
    }
    for (std::size_t i = 5; i < 7; ++i) {
        ASSERT_EQ(got[i].status, ReadStatus::Frame) << i << ": " << got[i].error;
        EXPECT_TRUE(got[i].frame.error()) << i;
        EXPECT_EQ(got[i].iface, "can3");
    }
}

TEST(DumpBlf, OtherObjectsAreSkippedEvenWhenTheySpanManyContainers) {
    const auto want = conversation();
    const std::int64_t start = want.front().ts_ns;
    BlfWriteOptions o;
    o.container_bytes = 4096;
    std::string stream = blf_object(65, std::string(300, 'x'), 0); // APP_TEXT
    stream += blf_object(65, std::string(200'000, 'y'), 0);        // 49 containers long
    for (const auto& e : events_of(want, BlfObjectType::CanMessage)) {
        stream += blf_event_object(e, start, o);
        stream += blf_object(10, std::string(20, 'z'), 0); // a container inside: not ours
    }
    const auto got = read_trace(blf_file(start, stream, o));
    expect_same_frames(got, want, "with other objects between");
}

TEST(DumpBlf, AnUndecodableObjectIsNamedAndReadingGoesOn) {
    const auto want = conversation();
    const std::int64_t start = want.front().ts_ns;
    BlfWriteOptions o;
    std::string bad;
    bad += std::string("\x01\x00\x00\x08\x00\x08\x00\x00", 8); // channel 1, dlc 8, id 0x800
    bad += std::string(8, '\0');
    std::string stream = blf_object(BlfObjectType::CanMessage, bad, 5);
    stream += blf_object(BlfObjectType::CanMessage, "short", 6);
    stream += blf_object(BlfObjectType::CanMessage, std::string(16, '\0'), 7, 2, 3);
    stream += blf_event_object(events_of(want, BlfObjectType::CanMessage)[0], start, o);
    const auto got = read_trace(blf_file(start, stream, o));
    ASSERT_EQ(got.size(), 4U);
    EXPECT_EQ(got[0].status, ReadStatus::Malformed);
    EXPECT_EQ(got[0].error,
              "BLF object 1 at byte 0 of the object stream (reading the container at file "
              "offset 144) (CAN_MESSAGE): identifier 0x800 out of range");
    EXPECT_EQ(got[1].status, ReadStatus::Malformed);
    EXPECT_NE(got[1].error.find("BLF object 2 at byte 48 "), std::string::npos) << got[1].error;
    EXPECT_NE(got[1].error.find("5 data bytes, at least 16 expected"), std::string::npos);
    EXPECT_NE(got[2].error.find("object header version 3"), std::string::npos) << got[2].error;
    ASSERT_EQ(got[3].status, ReadStatus::Frame);
    EXPECT_EQ(got[3].frame, want[0].frame);
}

TEST(DumpBlf, CorruptFilesEndWithOneSentenceGivingTheByteOffset) {
    const auto good = blf_file(events_of(conversation(), BlfObjectType::CanMessage));
    ASSERT_EQ(last_step(good).status, ReadStatus::End);

    auto bad_magic = good;
    bad_magic[3] = 'X';
    EXPECT_EQ(last_step(bad_magic).error, "not a BLF file (no 'LOGG' signature at byte offset 0)");

    auto bad_header_size = good;
    bad_header_size[6] = '\x70'; // 0x700090 bytes
    EXPECT_NE(last_step(bad_header_size).error.find("file header size 7340176 at byte offset 4"),
              std::string::npos);

    auto bad_object = good;
    bad_object[144] = 'X'; // "XOBJ"
    EXPECT_EQ(last_step(bad_object).error, "BLF: no object signature 'LOBJ' at file offset 144");

    auto absurd = good;
    absurd[144 + 11] = '\x7F'; // the container claims 2 GiB
    EXPECT_NE(last_step(absurd).error.find("BLF object at file offset 144 claims 2130706"),
              std::string::npos)
        << last_step(absurd).error;

    auto method = good;
    method[144 + 16] = '\x07';
    EXPECT_EQ(last_step(method).error, "BLF container at file offset 144: compression method 7 "
                                       "is not supported (0 stored, 2 zlib)");

    auto bad_zlib = good;
    bad_zlib[144 + 32] = '\x00'; // the zlib header's first byte
    const auto z = last_step(bad_zlib);
    EXPECT_EQ(z.status, ReadStatus::Fatal);
    EXPECT_NE(z.error.find("BLF container at file offset 144: bad zlib data"), std::string::npos)
        << z.error;

    auto size_lie = good;
    size_lie[144 + 24] = '\x01'; // the uncompressed size, low byte
    EXPECT_NE(last_step(size_lie).error.find("gave 576 bytes, its header says 513"),
              std::string::npos)
        << last_step(size_lie).error;
}

TEST(DumpBlf, EveryTruncationEndsWithoutACrashAndSaysTruncatedInsideAContainer) {
    BlfWriteOptions o;
    o.container_bytes = 200;
    for (const bool compress : {true, false}) {
        o.compress = compress;
        const auto good = blf_file(events_of(conversation(), BlfObjectType::CanMessage2), o);
        // Where the containers end (a cut there is a shorter, valid file unless an object goes on
        // in the next container).
        std::vector<std::size_t> ends = {144};
        while (ends.back() < good.size()) {
            const auto* p = reinterpret_cast<const std::uint8_t*>(good.data()) + ends.back();
            const std::size_t size = p[8] | (p[9] << 8) | (p[10] << 16);
            const auto end = ends.back() + size;
            for (auto pad = end; pad < (end + 3) / 4 * 4; ++pad) {
                ends.push_back(pad); // the padding after it may be missing
            }
            ends.push_back((end + 3) / 4 * 4);
        }
        ASSERT_GT(ends.size(), 4U);
        for (std::size_t cut = 0; cut < good.size(); ++cut) {
            const auto step = last_step(good.substr(0, cut));
            if (std::find(ends.begin(), ends.end(), cut) != ends.end() &&
                step.status == ReadStatus::End) {
                continue; // no object was cut
            }
            ASSERT_EQ(step.status, ReadStatus::Fatal) << "cut at " << cut;
            EXPECT_TRUE(step.error.find("truncated") != std::string::npos ||
                        step.error.find("cut short") != std::string::npos ||
                        step.error.find("not a BLF file") != std::string::npos)
                << "cut at " << cut << ": " << step.error;
        }
    }
}

// tests/data/traces/formats/conversation.blf is conversation.log written by blf_file() (zlib,
// containers of 128 bytes, CAN_MESSAGE and CAN_MESSAGE2); CODRIVE_UPDATE_GOLDEN=1 rewrites it.
TEST(DumpBlf, ConversationSampleHoldsTheCandumpLog) {
    const auto want = conversation();
    const auto path = trace_path("formats/conversation.blf");
    const char* update = std::getenv("CODRIVE_UPDATE_GOLDEN");
    if (update != nullptr && std::string(update) == "1") {
        auto events = events_of(want, BlfObjectType::CanMessage);
        for (std::size_t i = 0; i < events.size(); i += 2) {
            events[i].type = BlfObjectType::CanMessage2;
        }
        BlfWriteOptions o;
        o.container_bytes = 128;
        std::ofstream(path, std::ios::binary) << blf_file(events, o);
    }
    expect_same_frames(read_trace(slurp(path)), want, path);
}

namespace {

// A CAN_MESSAGE payload: channel 1, no flags, `id` with DLC 1 and the byte 0x05.
std::string can_message_payload(std::uint32_t id) {
    std::string p("\x01\x00\x00\x01", 4);
    for (int shift = 0; shift < 32; shift += 8) {
        p += static_cast<char>((id >> shift) & 0xFF);
    }
    return p + std::string("\x05\0\0\0\0\0\0\0", 8);
}

} // namespace

// Some writers leave the measurement start empty (1970) and put the time since 1970 in each
// object; python-can's test files hold times 78 years after the start. Every time a trace may
// carry (to the year 2255, kMaxTraceTimeNs) is read; a later one is named.
TEST(DumpBlf, TimesFarFromTheMeasurementStartAreKeptUpToTheYear2255) {
    using codrive::dump::testing::kStart;
    BlfWriteOptions o;
    const auto ts = static_cast<std::uint64_t>(kStart); // 2023, counted from 1970
    std::string stream = blf_object(BlfObjectType::CanMessage, can_message_payload(0x705), ts);
    stream += blf_object(BlfObjectType::CanMessage, can_message_payload(0x705), ts / 10'000, 1);
    stream += blf_object(BlfObjectType::CanMessage, can_message_payload(0x705),
                         0x2222222222222222ULL); // python-can's test_CanMessage.blf
    stream +=
        blf_object(BlfObjectType::CanMessage, can_message_payload(0x705), 0x8000000000000000ULL);
    stream += blf_object(BlfObjectType::CanMessage, can_message_payload(0x705),
                         0x0100000000000000ULL, 1); // 10 µs units: far past 2255
    const auto got = read_trace(blf_file(0, stream, o));
    ASSERT_EQ(got.size(), 5U);
    for (std::size_t i = 0; i < 3; ++i) {
        ASSERT_EQ(got[i].status, ReadStatus::Frame) << i << ": " << got[i].error;
        EXPECT_EQ(got[i].frame, Frame::make(0x705, {0x05}));
    }
    EXPECT_EQ(got[0].ts_ns, kStart);
    EXPECT_EQ(got[1].ts_ns, kStart);
    EXPECT_EQ(got[2].ts_ns, 0x2222222222222222LL);
    EXPECT_EQ(got[3].status, ReadStatus::Malformed);
    EXPECT_NE(got[3].error.find("(CAN_MESSAGE): timestamp 9223372036854775808 (ns) is past the "
                                "year 2255"),
              std::string::npos)
        << got[3].error;
    EXPECT_NE(got[4].error.find("timestamp 72057594037927936 (10 µs units) is past the year 2255"),
              std::string::npos)
        << got[4].error;
}

// TSMaster writes CAN_FD_MESSAGE_64 objects of 64-byte frames with a valid length of 64 and only
// 48 bytes stored (python-can issue 1905, a real file). CANoe shows the missing bytes as 00, and
// so does this reader; a valid length short of the DLC stays an error.
TEST(DumpBlf, ACanFd64ObjectStoringFewerBytesThanItsDlcKeepsTheFrame) {
    const auto payload = [](std::uint8_t valid, std::size_t stored, std::uint8_t ext_offset) {
        std::string p;
        p += '\x07';                             // channel
        p += '\x0F';                             // DLC 15: 64 bytes
        p += static_cast<char>(valid);           // valid payload length
        p += '\0';                               // tx count
        p += std::string("\xA9\x06\x00\x00", 4); // id 6A9h
        p += std::string(4, '\0');               // frame length
        p += std::string("\x00\x30\x00\x00", 4); // flags: EDL, BRS
        p += std::string(16, '\0');              // bit timings, BRS and CRC offsets
        p += std::string("\x00\x00\x00", 3);     // bit count, direction
        p += static_cast<char>(ext_offset);      // extended data offset
        p += std::string(4, '\0');               // CRC
        return p + std::string(stored, '\xFF');
    };
    std::string stream = blf_object(BlfObjectType::CanFdMessage64, payload(64, 48, 0), 1000);
    // The extended data (8 bytes here) starts 32 + 40 + 56 bytes into the object.
    stream += blf_object(BlfObjectType::CanFdMessage64, payload(64, 64, 128), 2000);
    stream += blf_object(BlfObjectType::CanFdMessage64, payload(40, 48, 0), 3000);
    const auto got = read_trace(blf_file(0, stream, BlfWriteOptions{}));
    ASSERT_EQ(got.size(), 3U);
    for (std::size_t i = 0; i < 2; ++i) {
        ASSERT_EQ(got[i].status, ReadStatus::Frame) << i << ": " << got[i].error;
        EXPECT_TRUE(got[i].frame.fd() && (got[i].frame.flags & Frame::kBrs) != 0);
        EXPECT_EQ(got[i].frame.id, 0x6A9U);
        EXPECT_EQ(got[i].frame.len, 64);
        const std::size_t stored = i == 0 ? 48 : 56;
        for (std::size_t b = 0; b < 64; ++b) {
            EXPECT_EQ(got[i].frame.data[b], b < stored ? 0xFF : 0x00) << i << " byte " << b;
        }
    }
    EXPECT_EQ(got[2].status, ReadStatus::Malformed);
    EXPECT_NE(got[2].error.find("DLC 15 needs 64 data bytes, the object has 40"), std::string::npos)
        << got[2].error;
}

// Vector's converter fills the rest of a container with zeros after the last object
// (vector_blf's events_from_converter/test_GlobalMarker.blf: 27 after a 571-byte marker): every
// zero byte between objects, in a container or after the last one in the file, is padding.
TEST(DumpBlf, RunsOfZerosBetweenObjectsAndAtTheEndAreSkipped) {
    const auto want = conversation();
    const std::int64_t start = want.front().ts_ns / 1'000'000 * 1'000'000;
    BlfWriteOptions o;
    o.container_bytes = 200; // the zeros fall inside, across and at the end of containers
    std::string stream;
    for (const auto& e : events_of(want, BlfObjectType::CanMessage)) {
        stream += blf_event_object(e, start, o) + std::string(27, '\0');
    }
    const auto file = blf_file(start, stream + std::string(300, '\0'), o) + std::string(50, '\0');
    const auto got = read_trace(file);
    expect_same_frames(got, want, "with zeros after every object");
    EXPECT_EQ(last_step(file).status, ReadStatus::End) << last_step(file).error;
}

// The CAN error objects beyond CAN_ERROR(_EXT) that Vector's loggers write (vector_blf's test
// files have each): an overload frame, the controller's error counters, an error frame on a CAN
// FD channel. Each becomes the SocketCAN error frame a live capture would show.
TEST(DumpBlf, OverloadDriverErrorAndCanFdErrorObjectsAreErrorFrames) {
    const std::int64_t t0 = 1'795'478'400'000'000'000LL;
    const Frame passive = state_error_frame(TraceBusState::Passive, 130, 5);
    const Frame warning = state_error_frame(TraceBusState::Warning, 0, 100);
    const std::vector<BlfEvent> events = {
        {Frame{}, t0 + 1000, 4, BlfObjectType::CanOverload},
        {passive, t0 + 2000, 4, BlfObjectType::CanDriverError},
        {warning, t0 + 3000, 4, BlfObjectType::CanDriverErrorExt},
        {Frame{}, t0 + 4000, 4, BlfObjectType::CanFdError64},
    };
    const auto got = read_trace(blf_file(events));
    ASSERT_EQ(got.size(), events.size());
    for (const auto& g : got) {
        ASSERT_EQ(g.status, ReadStatus::Frame) << g.error;
        EXPECT_EQ(g.iface, "can4");
    }
    EXPECT_EQ(got[0].frame, protocol_error_frame(CAN_ERR_PROT_OVERLOAD, false, 0));
    EXPECT_EQ(got[1].frame, passive);
    EXPECT_EQ(got[2].frame, warning);
    EXPECT_EQ(got[3].frame, protocol_error_frame(0, false, 0));
    EXPECT_EQ(got[3].ts_ns, t0 + 4000);
}

// The header's SYSTEMTIME start is a calendar date: 29 February 2024 is one, 29 February 2023 is
// not. An impossible date gives no start (times count from the start of the measurement) rather
// than 1 March.
TEST(DumpBlf, AnImpossibleStartDateIsNoStartAndALeapDayIsOne) {
    const std::int64_t leap_day = 1'709'164'800'000'000'000LL; // 2024-02-29 00:00:00 UTC
    const std::vector<BlfEvent> events{
        {Frame::make(0x705, {0x05}), leap_day, 1, BlfObjectType::CanMessage},
        {Frame::make(0x705, {0x05}), leap_day + 1'500'000, 1, BlfObjectType::CanMessage}};
    auto file = blf_file(events, BlfWriteOptions{});
    auto got = frames_of(read_trace(file));
    ASSERT_EQ(got.size(), 2U);
    EXPECT_EQ(got[0].ts_ns, leap_day);
    EXPECT_EQ(got[1].ts_ns, leap_day + 1'500'000);
    ASSERT_EQ(static_cast<unsigned char>(file[40]) | static_cast<unsigned char>(file[41]) << 8,
              2024); // SYSTEMTIME year
    file[40] = static_cast<char>(2023 & 0xFF);
    file[41] = static_cast<char>(2023 >> 8);
    got = frames_of(read_trace(file));
    ASSERT_EQ(got.size(), 2U);
    EXPECT_EQ(got[0].ts_ns, 0);
    EXPECT_EQ(got[1].ts_ns, 1'500'000);
}

// CAN_ERROR_EXT carries the error register: flag 1 an SJA1000 ECC (what Vector's converter
// writes for the ASC line "ErrorFrame ECC: 10100010"), flag 2 the CAN-Core register. Without
// either flag the error is unspecified.
TEST(DumpBlf, ErrorExtObjectsGiveTheErrorTheirRegisterHolds) {
    const auto payload = [](std::uint32_t flags, std::uint8_t ecc) {
        std::string p(32, '\0');
        p[0] = 1; // channel 1
        p[2] = 6; // length
        for (int i = 0; i < 4; ++i) {
            p[static_cast<std::size_t>(4 + i)] = static_cast<char>(flags >> (8 * i));
        }
        p[8] = static_cast<char>(ecc);
        return p;
    };
    std::string stream;
    stream += blf_object(BlfObjectType::CanErrorExt, payload(1, 0xA2), 1'000'000);
    stream += blf_object(BlfObjectType::CanErrorExt, payload(0xE, 0x82), 2'000'000);
    stream += blf_object(BlfObjectType::CanErrorExt, payload(2, 0x43), 3'000'000);
    stream += blf_object(BlfObjectType::CanErrorExt, payload(0, 0xA2), 4'000'000);
    const auto got = read_trace(blf_file(0, stream, BlfWriteOptions{}));
    ASSERT_EQ(got.size(), 4U);
    std::vector<std::string> texts;
    for (const auto& i : got) {
        ASSERT_EQ(i.status, ReadStatus::Frame) << i.error;
        EXPECT_EQ(i.iface, "can1");
        std::string all;
        for (const auto& e : decode_error_frame(i.frame)) {
            all += (all.empty() ? "" : "; ") + to_string(e);
        }
        texts.push_back(all);
    }
    EXPECT_EQ(texts[0], "protocol error: stuff error in the identifier bits 28-21 (11-bit: 10-3)");
    EXPECT_EQ(texts[1], "protocol error: stuff error");
    EXPECT_EQ(texts[2], "protocol error: on transmission in the ACK slot; transmission not "
                        "acknowledged (no other node on the bus?)");
    EXPECT_EQ(texts[3], "protocol error: unspecified");
}
