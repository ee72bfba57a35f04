// SPDX-License-Identifier: Apache-2.0
// Decoder behaviour not covered by the golden traces: bounded memory on huge transfers, live
// filter syntax, JSON escaping.
#include <codrive/dump/decoder.hpp>
#include <codrive/dump/line_format.hpp>
#include <codrive/dump/live.hpp>

#include <gtest/gtest.h>

#include <string>

using namespace codrive;
using namespace codrive::dump;

namespace {
std::string text(const Decoded& d) {
    return {d.text.data(), d.text.size()};
}
} // namespace

TEST(DumpDecoder, HugeSegmentedUploadIsCountedInFullButKeptBounded) {
    Decoder dec;
    Decoded out;
    std::vector<Note> notes;
    TraceRecord r;
    r.has_ts = true;
    r.iface = "can0";
    std::int64_t ts = 1'000'000'000;
    auto feed = [&](std::uint32_t id, std::initializer_list<std::uint8_t> b) {
        r.frame = Frame::make(id, b);
        r.ts_ns = ts;
        ts += 100'000;
        dec.decode(r, out, notes);
    };
    constexpr std::uint32_t kSize = 7 * 20000; // 140 kB in 20000 segments
    feed(0x604, {0x40, 0x00, 0x20, 0x00, 0, 0, 0, 0});
    feed(0x584, {0x41, 0x00, 0x20, 0x00, static_cast<std::uint8_t>(kSize),
                 static_cast<std::uint8_t>(kSize >> 8), static_cast<std::uint8_t>(kSize >> 16), 0});
    bool toggle = false;
    for (unsigned i = 0; i < 20000; ++i) {
        const auto t = static_cast<std::uint8_t>(toggle ? 0x10 : 0);
        feed(0x604, {static_cast<std::uint8_t>(0x60 | t), 0, 0, 0, 0, 0, 0, 0});
        const bool last = i + 1 == 20000;
        feed(0x584,
             {static_cast<std::uint8_t>(t | (last ? 1 : 0)), 'a', 'b', 'c', 'd', 'e', 'f', 'g'});
        toggle = !toggle;
    }
    const auto s = text(out);
    EXPECT_NE(s.find("node 4 upload 2000:00 = \"abcdefg"), std::string::npos) << s;
    EXPECT_NE(s.find("(140000 bytes, segmented,"), std::string::npos) << s;
    EXPECT_LT(s.size(), 300U) << "the value is cut for display";
    EXPECT_TRUE(notes.empty());
}

TEST(DumpDecoder, RequestWithoutAnswerBecomesATimeoutNote) {
    DecoderOptions o;
    o.sdo_timeout_ns = 500'000'000;
    Decoder dec(o);
    Decoded out;
    std::vector<Note> notes;
    TraceRecord r;
    r.has_ts = true;
    r.frame = Frame::make(0x603, {0x40, 0x17, 0x10, 0x00, 0, 0, 0, 0});
    r.ts_ns = 1'000'000'000;
    dec.decode(r, out, notes);
    r.frame = Frame::make(0x080, {});
    r.ts_ns = 1'400'000'000;
    dec.decode(r, out, notes);
    EXPECT_TRUE(notes.empty());
    r.ts_ns = 1'600'000'000;
    dec.decode(r, out, notes);
    ASSERT_EQ(notes.size(), 1U);
    EXPECT_EQ(notes[0].ts_ns, 1'500'000'000);
    EXPECT_EQ(notes[0].event, "timeout");
    EXPECT_EQ(notes[0].text, "node 3 SDO upload 1017:00 Producer heartbeat time: no response "
                             "within 500 ms (timeout)");
}

TEST(DumpLive, CandumpFilterSyntax) {
    std::string err;
    auto s = parse_live_spec("vcan0,0x580:0x780,181~7FF,12345678:1FFFFFFF", err);
    ASSERT_TRUE(s) << err;
    EXPECT_EQ(s->iface, "vcan0");
    ASSERT_EQ(s->filters.size(), 3U);
    EXPECT_EQ(s->filters[0].id, 0x580U);
    EXPECT_EQ(s->filters[0].mask, 0x780U);
    EXPECT_FALSE(s->filters[0].invert);
    EXPECT_TRUE(s->filters[1].invert);
    EXPECT_EQ(s->filters[1].id, 0x181U);
    EXPECT_TRUE(s->filters[2].extended);
    EXPECT_FALSE(parse_live_spec("vcan0,0x580", err));
    EXPECT_NE(err.find("ID:MASK"), std::string::npos);
    EXPECT_FALSE(parse_live_spec(",0x1:0x2", err));
}

TEST(DumpLineFormat, JsonStringsAreEscaped) {
    fmt::memory_buffer b;
    append_json_string(b, "a\"b\\c\n\x01");
    EXPECT_EQ(std::string(b.data(), b.size()), "\"a\\\"b\\\\c\\u000A\\u0001\"");
}
