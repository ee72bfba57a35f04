// SPDX-License-Identifier: Apache-2.0
// Decoder behaviour not covered by the golden traces: bounded memory on huge transfers, live
// filter syntax, JSON escaping.
#include <codrive/dump/decoder.hpp>
#include <codrive/dump/line_format.hpp>
#include <codrive/dump/live.hpp>
#include <codrive/dump/stats.hpp>

#include <gtest/gtest.h>

#include <limits>
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

namespace {
// Feeds frames 100 ms apart to one decoder; returns each frame's line and severity.
struct SdoFeed {
    DecoderOptions opts = [] {
        DecoderOptions o;
        o.sdo_timeout_ns = 1'000'000'000;
        return o;
    }();
    Decoder dec{opts};
    std::vector<Note> notes;
    std::int64_t ts = 1'000'000'000;
    std::pair<std::string, Severity> feed(std::uint32_t id, std::initializer_list<std::uint8_t> b) {
        TraceRecord r;
        r.has_ts = true;
        r.iface = "can0";
        r.frame = Frame::make(id, b);
        r.ts_ns = ts;
        ts += 100'000'000;
        Decoded out;
        dec.decode(r, out, notes);
        return {text(out), out.severity};
    }
};
} // namespace

TEST(DumpDecoder, SegmentAnsweringAnUploadInitiateIsAWarning) {
    SdoFeed f;
    (void)f.feed(0x655, {0x40, 0x10, 0x20, 0x0D, 0, 0, 0, 0});
    const auto [line, sev] = f.feed(0x5D5, {0x00, 0x00, 0x00, 0x00, 0, 0, 0, 0});
    EXPECT_EQ(sev, Severity::Warning) << line;
    EXPECT_NE(line.find("node 85 SDO upload segment answers upload request 2010:0D"),
              std::string::npos)
        << line;
    EXPECT_NE(line.find("expected the initiate upload response"), std::string::npos) << line;
    EXPECT_EQ(line.find("upload segment 1"), std::string::npos) << line;
}

TEST(DumpDecoder, ResponseThatFitsNoTransferNamesTheOpenOne) {
    SdoFeed f;
    (void)f.feed(0x603, {0x40, 0x17, 0x10, 0x00, 0, 0, 0, 0});
    const auto [line, sev] = f.feed(0x583, {0x60, 0x00, 0x20, 0x00, 0, 0, 0, 0});
    EXPECT_EQ(sev, Severity::Warning) << line;
    EXPECT_NE(line.find("without a matching request (open: upload 1017:00"), std::string::npos)
        << line;
}

TEST(DumpDecoder, TooShortResponseIsReportedOnceNotAgainAsTimeout) {
    SdoFeed f;
    (void)f.feed(0x603, {0x40, 0x17, 0x10, 0x00, 0, 0, 0, 0});
    const auto [line, sev] = f.feed(0x583, {0x4B, 0x17, 0x10});
    EXPECT_EQ(sev, Severity::Warning) << line;
    EXPECT_NE(line.find("SDO response frame of 3 bytes"), std::string::npos) << line;
    EXPECT_NE(line.find("in upload 1017:00"), std::string::npos) << line;
    f.ts += 5'000'000'000;
    (void)f.feed(0x080, {});
    EXPECT_TRUE(f.notes.empty()) << f.notes[0].text;
}

TEST(DumpDecoder, TransferAbandonedByTheClientIsReported) {
    SdoFeed f;
    (void)f.feed(0x603, {0x40, 0x17, 0x10, 0x00, 0, 0, 0, 0});
    const auto [line, sev] = f.feed(0x603, {0x40, 0x18, 0x10, 0x01, 0, 0, 0, 0});
    EXPECT_EQ(sev, Severity::Warning) << line;
    EXPECT_NE(line.find("SDO upload 1017:00"), std::string::npos) << line;
    EXPECT_NE(line.find("abandoned by the client after 100.0 ms; SDO upload request 1018:01"),
              std::string::npos)
        << line;
    // A normal request after a completed transfer is no anomaly.
    (void)f.feed(0x583, {0x43, 0x18, 0x10, 0x01, 1, 0, 0, 0});
    const auto [next, next_sev] = f.feed(0x603, {0x40, 0x18, 0x10, 0x02, 0, 0, 0, 0});
    EXPECT_EQ(next_sev, Severity::Info) << next;
}

TEST(DumpDecoder, NmtResetNodeSaysNodeOnce) {
    SdoFeed f;
    EXPECT_EQ(f.feed(0x000, {0x81, 0x0F}).first, "NMT reset node 15");
    EXPECT_EQ(f.feed(0x000, {0x82, 0x0F}).first, "NMT reset communication node 15");
}

TEST(DumpDecoder, TimeOfTheWrongLengthIsFlagged) {
    SdoFeed f;
    const auto [ok, ok_sev] = f.feed(0x100, {0xD2, 0x02, 0x96, 0x03, 0xB6, 0x16});
    EXPECT_EQ(ok_sev, Severity::Info) << ok;
    const auto [line, sev] = f.feed(0x100, {0xD2, 0x02, 0x96, 0x03, 0xB6, 0x16, 0x00, 0x00});
    EXPECT_EQ(sev, Severity::Warning) << line;
    EXPECT_EQ(line, "TIME 1999-12-02 16:42:42.770 UTC (8 bytes, TIME_OF_DAY has 6)");
}

TEST(DumpStats, NodeGuardingIsCountedApartFromHeartbeat) {
    Stats stats;
    Decoder dec({}, &stats);
    std::vector<Note> notes;
    std::int64_t ts = 1'000'000'000;
    auto feed = [&](Frame f) {
        TraceRecord r;
        r.has_ts = true;
        r.frame = f;
        r.ts_ns = ts;
        ts += 1'202'000'000;
        Decoded out;
        dec.decode(r, out, notes);
    };
    Frame rtr = Frame::make(0x70F, {});
    rtr.flags = Frame::kRtr;
    rtr.len = 1;
    feed(rtr);
    feed(Frame::make(0x70F, {0x05})); // operational, toggle 0
    feed(rtr);
    feed(Frame::make(0x70F, {0x85})); // toggle 1
    feed(rtr);
    feed(rtr);                        // the previous request got no reply
    feed(Frame::make(0x70F, {0x85})); // toggle 1 again: toggle error
    const auto& n = stats.node(15);
    EXPECT_EQ(n.hb.n, 0U) << "guarding replies are no heartbeat period";
    EXPECT_EQ(n.heartbeats, 0U);
    EXPECT_EQ(n.guard_requests, 4U);
    EXPECT_EQ(n.guard_replies, 3U);
    EXPECT_EQ(n.guard_unanswered, 1U);
    EXPECT_EQ(n.guard_toggle_errors, 1U);
    const auto table = stats.table();
    EXPECT_NE(table.find("node 15 guarding: 4 requests, 3 replies, 1 unanswered, 1 toggle errors"),
              std::string::npos)
        << table;
    EXPECT_EQ(table.find("1202.0 ms"), std::string::npos) << table;
}

// A remote frame carries no data: on the NMT, SYNC, TIME, EMCY and LSS COB-IDs it is one warning
// (not "TIME malformed (0 bytes)", and no SYNC counted); on a PDO it is that PDO's request.
// python-can's logfile.asc has such a frame on 100h.
TEST(DumpDecoder, RemoteFramesAreNamedNotDecodedAsData) {
    Stats stats;
    Decoder dec({}, &stats);
    std::vector<Note> notes;
    std::int64_t ts = 1'000'000'000;
    auto feed = [&](std::uint32_t id, std::uint8_t len) {
        TraceRecord r;
        r.has_ts = true;
        r.frame = Frame::make_rtr(id, len);
        r.ts_ns = ts;
        ts += 10'000'000;
        Decoded out;
        dec.decode(r, out, notes);
        return out;
    };
    const struct {
        std::uint32_t id;
        Service service;
        const char* name;
    } stray[] = {{0x000, Service::Nmt, "NMT"},        {0x080, Service::Sync, "SYNC"},
                 {0x100, Service::Time, "TIME"},      {0x085, Service::Emcy, "EMCY"},
                 {0x7E5, Service::Lss, "LSS-master"}, {0x7E4, Service::Lss, "LSS-slave"}};
    for (const auto& s : stray) {
        const auto out = feed(s.id, 0);
        EXPECT_EQ(out.service, s.service) << s.name;
        EXPECT_EQ(out.severity, Severity::Warning) << s.name;
        EXPECT_EQ(text(out), fmt::format("remote frame on the {} COB-ID (only node guarding and "
                                         "PDOs are requested by remote frames)",
                                         s.name));
    }
    EXPECT_EQ(stats.syncs(), 0U) << "a remote frame on 080h is no SYNC";
    const auto tpdo = feed(0x285, 8);
    EXPECT_EQ(tpdo.service, Service::Pdo);
    EXPECT_EQ(tpdo.node, 5);
    EXPECT_EQ(text(tpdo), "node 5 TPDO2 remote request");
    EXPECT_EQ(text(feed(0x705, 1)), "node 5 guarding request");
}

// A remote request names the PDO that uses the COB-ID now: node 3's TPDO1 moved to 285h by an
// SDO download of 1800h:01 is "node 3 TPDO1" there, and 183h then belongs to no PDO.
TEST(DumpDecoder, ARemoteRequestNamesThePdoMovedToItsCobId) {
    SdoFeed f;
    (void)f.feed(0x603, {0x23, 0x00, 0x18, 0x01, 0x85, 0x02, 0x00, 0x00});
    (void)f.feed(0x583, {0x60, 0x00, 0x18, 0x01, 0x00, 0x00, 0x00, 0x00});
    const auto rtr = [&](std::uint32_t id) {
        TraceRecord r;
        r.has_ts = true;
        r.frame = Frame::make_rtr(id, 8);
        r.ts_ns = f.ts;
        Decoded out;
        f.dec.decode(r, out, f.notes);
        return std::pair{text(out), out.node};
    };
    EXPECT_EQ(rtr(0x285), (std::pair<std::string, NodeId>{"node 3 TPDO1 remote request", 3}));
    EXPECT_EQ(rtr(0x183).first, "") << "183h is no PDO's COB-ID any more";
}

// A relative trace (TRC without STARTTIME, candump -t z, CSV) may have a heartbeat at exactly
// t = 0: it starts the period measurement like any other.
TEST(DumpStats, AHeartbeatAtTimeZeroStartsThePeriod) {
    Stats stats;
    Decoder dec({}, &stats);
    std::vector<Note> notes;
    for (const std::int64_t ts : {0LL, 100'000'000LL, 200'000'000LL}) {
        TraceRecord r;
        r.has_ts = true;
        r.frame = Frame::make(0x704, {0x05});
        r.ts_ns = ts;
        Decoded out;
        dec.decode(r, out, notes);
    }
    EXPECT_EQ(stats.node(4).hb.n, 2U) << "two periods from three heartbeats";
    EXPECT_NEAR(stats.node(4).hb.mean_ns, 100'000'000.0, 1.0);
}

namespace {
// Feeds timed frames to a decoder, keeping the notes of each step.
struct TimedFeed {
    explicit TimedFeed(Decoder& d) : dec(d) {}
    Decoder& dec;
    Decoded out;
    std::vector<Note> notes;
    std::string iface;
    void operator()(std::int64_t ts_ns, std::uint32_t id, std::initializer_list<std::uint8_t> b) {
        TraceRecord r;
        r.iface = iface;
        r.has_ts = true;
        r.ts_ns = ts_ns;
        r.frame = Frame::make(id, b);
        notes.clear();
        dec.decode(r, out, notes);
    }
};
constexpr std::int64_t kSec = 1'000'000'000;
constexpr std::int64_t kMilli = 1'000'000;
} // namespace

// Two captures in one file, the second with relative times starting again at 0: one warning,
// then the open transfer waits for its timeout from the new time instead of until the time
// passes the first capture's end, and a request of the second capture times out in it. Frames a
// little out of order are not a step.
TEST(DumpDecoder, AStepBackInTimeIsOneWarningAndTimeoutsGoOn) {
    DecoderOptions o;
    o.sdo_timeout_ns = 500 * kMilli;
    Stats stats;
    Decoder dec(o, &stats);
    TimedFeed feed(dec);
    feed(100 * kSec, 0x603, {0x40, 0x17, 0x10, 0x00, 0, 0, 0, 0});
    feed(100 * kSec + 200 * kMilli, 0x080, {});
    EXPECT_TRUE(feed.notes.empty());
    feed(0, 0x080, {});
    ASSERT_EQ(feed.notes.size(), 1U);
    EXPECT_EQ(feed.notes[0].event, "time step");
    EXPECT_EQ(feed.notes[0].severity, Severity::Warning);
    EXPECT_EQ(feed.notes[0].text.rfind("time goes back 100.200 s", 0), 0U) << feed.notes[0].text;
    feed(400 * kMilli, 0x080, {});
    EXPECT_TRUE(feed.notes.empty()) << "node 3 waits from the step: 400 ms";
    feed(600 * kMilli, 0x080, {});
    ASSERT_EQ(feed.notes.size(), 1U);
    EXPECT_EQ(feed.notes[0].event, "timeout");
    EXPECT_EQ(feed.notes[0].ts_ns, 500 * kMilli);
    EXPECT_EQ(feed.notes[0].text.rfind("node 3 SDO upload 1017:00", 0), 0U) << feed.notes[0].text;
    feed(700 * kMilli, 0x605, {0x40, 0x18, 0x10, 0x01, 0, 0, 0, 0});
    feed(1300 * kMilli, 0x080, {});
    ASSERT_EQ(feed.notes.size(), 1U);
    EXPECT_EQ(feed.notes[0].event, "timeout");
    EXPECT_EQ(feed.notes[0].text.rfind("node 5 SDO upload 1018:01", 0), 0U) << feed.notes[0].text;
    feed(1250 * kMilli, 0x080, {}); // 50 ms out of order: no step
    EXPECT_TRUE(feed.notes.empty());
    EXPECT_EQ(stats.duration_ns(), 200 * kMilli + 1300 * kMilli);
    // On the report's timeline the second capture follows the first.
    EXPECT_EQ(stats.on_timeline(0), 100 * kSec + 200 * kMilli);
    EXPECT_EQ(stats.timeline_last_ns(), 100 * kSec + 1500 * kMilli);
}

// Interfaces are not compared with each other: two captures of the same second concatenated
// (`cat can0.log can1.log`), or a clock 2 s apart, interleave without a step, and a transfer
// on one goes on across frames of the other.
TEST(DumpDecoder, InterfacesOutOfStepWithEachOtherAreNoStepBack) {
    Stats stats;
    Decoder dec(DecoderOptions{}, &stats);
    TimedFeed feed(dec);
    const auto line = [&] { return std::string(feed.out.text.data(), feed.out.text.size()); };
    // The other interface 2 s behind, then 2 s ahead: neither is a step, and neither times out
    // the transfer of can0.
    for (const std::int64_t other : {98 * kSec, 102 * kSec}) {
        SCOPED_TRACE(other);
        feed.iface = "can0";
        feed(100 * kSec, 0x603, {0x40, 0x17, 0x10, 0x00, 0, 0, 0, 0});
        feed.iface = "can1";
        feed(other, 0x701, {0x05});
        EXPECT_TRUE(feed.notes.empty());
        feed.iface = "can0";
        feed(100 * kSec + 5 * kMilli, 0x583, {0x43, 0x17, 0x10, 0x00, 1, 2, 3, 4});
        EXPECT_TRUE(feed.notes.empty());
        EXPECT_NE(line().find("(4 bytes, expedited, 5.0 ms)"), std::string::npos) << line();
    }
    // Both interfaces stepping back (two two-interface captures appended) is one new stretch,
    // and a transfer of can0 started between the two steps keeps its duration.
    feed(1 * kSec, 0x080, {});
    ASSERT_EQ(feed.notes.size(), 1U);
    EXPECT_EQ(feed.notes[0].text.rfind("can0: time goes back 99.005 s", 0), 0U)
        << feed.notes[0].text;
    feed(1 * kSec + 2 * kMilli, 0x603, {0x40, 0x17, 0x10, 0x00, 0, 0, 0, 0});
    feed.iface = "can1";
    feed(1 * kSec + 1 * kMilli, 0x701, {0x05});
    ASSERT_EQ(feed.notes.size(), 1U);
    EXPECT_EQ(feed.notes[0].text.rfind("can1: time goes back 100.999 s", 0), 0U)
        << feed.notes[0].text;
    feed.iface = "can0";
    feed(1 * kSec + 7 * kMilli, 0x583, {0x43, 0x17, 0x10, 0x00, 1, 2, 3, 4});
    EXPECT_NE(line().find("(4 bytes, expedited, 5.0 ms)"), std::string::npos) << line();
    EXPECT_EQ(stats.duration_ns(), 4 * kSec + 7 * kMilli); // 98..102 s and 1.000..1.007 s
}

// `cat can0.log can1.log` of the same minute: can1's unanswered request times out in can1's
// time, although can0's frames have gone past it.
TEST(DumpDecoder, ATransferOfAnInterfaceBehindTheOthersTimesOutInItsOwnTime) {
    Decoder dec;
    TimedFeed feed(dec);
    feed.iface = "can0";
    for (std::int64_t t = 100 * kSec; t <= 160 * kSec; t += 100 * kMilli) {
        feed(t, 0x080, {});
    }
    feed.iface = "can1";
    feed(110 * kSec, 0x605, {0x40, 0x17, 0x10, 0x00, 0, 0, 0, 0});
    EXPECT_TRUE(feed.notes.empty());
    feed(111500 * kMilli, 0x605, {0x40, 0x17, 0x10, 0x00, 0, 0, 0, 0});
    ASSERT_EQ(feed.notes.size(), 1U);
    EXPECT_EQ(feed.notes[0].event, "timeout");
    EXPECT_EQ(feed.notes[0].ts_ns, 111 * kSec);
}

// Times as far apart as readers allow (up to the year 2255) sum without overflow.
TEST(DumpDecoder, StretchesAsLongAsTracesAllowSumWithoutOverflow) {
    Stats stats;
    Decoder dec(DecoderOptions{}, &stats);
    TimedFeed feed(dec);
    for (const std::int64_t t : {kSec, kMaxTraceTimeNs, std::int64_t{0}, kMaxTraceTimeNs}) {
        feed(t, 0x080, {});
    }
    EXPECT_EQ(stats.duration_ns(), std::numeric_limits<std::int64_t>::max());
    EXPECT_EQ(stats.timeline_last_ns(), kMaxTraceTimeNs);
}

// Ten seconds at about 13 % load, twice, the second capture appended with times from 0 again:
// the one-second windows restart at the step, so the peak stays near the mean (before, every
// frame of the second capture fell into one window of the first and the peak read 100s of %).
TEST(DumpDecoder, AStepBackRestartsTheLoadWindow) {
    // The first capture from 100 s or, as `-t z` writes both, from 0 like the second.
    for (const std::int64_t first : {100 * kSec, std::int64_t{0}}) {
        SCOPED_TRACE(first);
        Stats stats(125'000);
        Decoder dec(DecoderOptions{}, &stats);
        TimedFeed feed(dec);
        for (const std::int64_t start : {first, std::int64_t{0}}) {
            for (std::int64_t t = 0; t < 10 * kSec; t += 5 * kMilli) {
                feed(start + t, 0x181, {1, 2, 3, 4}); // 86 bits with stuffing
            }
        }
        EXPECT_EQ(stats.duration_ns(), 2 * (10 * kSec - 5 * kMilli));
        EXPECT_NEAR(stats.bus_load(), 86.0 * 200 / 125'000 * 100, 0.2);
        EXPECT_NEAR(stats.peak_load_so_far(), stats.bus_load(), 0.2);
        EXPECT_EQ(stats.timeline_last_ns(), first + 2 * (10 * kSec - 5 * kMilli));
    }
}

// A frame without a timestamp in a timed trace (records from two sources) does not restart an
// open transfer's clock: its timeout still counts from the last timed frame.
TEST(DumpDecoder, AnUntimedFrameLeavesATransfersClockAlone) {
    DecoderOptions o;
    o.sdo_timeout_ns = 500 * kMilli;
    Decoder dec(o);
    TimedFeed feed(dec);
    feed(10 * kSec, 0x603, {0x40, 0x08, 0x10, 0x00, 0, 0, 0, 0});
    TraceRecord untimed;
    untimed.has_ts = false;
    untimed.frame = Frame::make(0x583, {0x41, 0x08, 0x10, 0x00, 20, 0, 0, 0});
    dec.decode(untimed, feed.out, feed.notes);
    EXPECT_TRUE(feed.notes.empty());
    feed(10 * kSec + 400 * kMilli, 0x080, {});
    EXPECT_TRUE(feed.notes.empty()) << "400 ms since the request";
    feed(10 * kSec + 600 * kMilli, 0x080, {});
    ASSERT_EQ(feed.notes.size(), 1U);
    EXPECT_EQ(feed.notes[0].ts_ns, 10 * kSec + 500 * kMilli);
    EXPECT_NE(feed.notes[0].text.find("(abandoned)"), std::string::npos) << feed.notes[0].text;
}
