// SPDX-License-Identifier: Apache-2.0
// The statistics behind `--report` on made-up data (no clock, no files): exact bit stuffing,
// time buckets that merge instead of growing, histograms, SYNC period and SYNC→TPDO latency,
// and the report's JSON built from a decoded conversation.
#include "dump_test_util.hpp"

#include <codrive/dump/dumper.hpp>
#include <codrive/dump/frame_bits.hpp>
#include <codrive/dump/report_data.hpp>
#include <codrive/dump/stats.hpp>

#include <gtest/gtest.h>

#include <cstdint>
#include <random>
#include <string>

using namespace codrive;
using namespace codrive::dump;
using codrive::dump::testing::kMs;
using codrive::dump::testing::kStart;
using codrive::dump::testing::kUs;
using codrive::dump::testing::rec;

TEST(FrameBits, AllDominantFrameHasTheStuffBitsCountedByHand) {
    // SYNC-like id 0, no data: SOF, 11 id bits, RTR, IDE, r0, DLC 0000 are 19 dominant bits and
    // the CRC of all-zero bits is 0, so 34 dominant bits in a row get a stuff bit after every
    // five: 6 stuff bits. 34 + 6 + 13 = 53 bits (the worst-case formula says 55).
    EXPECT_EQ(frame_bits_exact(Frame::make(0x000, {})), 53U);
    EXPECT_EQ(frame_bits_worst_case(Frame::make(0x000, {})), 55U);
}

TEST(FrameBits, FramesWithCrcAndStuffBitsWorkedOutByAnIndependentModel) {
    // Lengths from a separate model of ISO 11898-1 (bit layout, CRC-15 checked against the
    // catalogue value 0x059E of "123456789", stuffing from SOF to the CRC end) + 13 tail bits.
    EXPECT_EQ(frame_bits_exact(Frame::make(0x7FF, {})), 50U);           // CRC 0x272F
    EXPECT_EQ(frame_bits_exact(Frame::make(0x181, {1, 2, 3, 4})), 86U); // CRC 0x04FF
    Frame ext = Frame::make(0x18FF0001, {0xAA, 0xAA, 0xAA, 0xAA, 0xAA, 0xAA, 0xAA, 0xAA});
    ext.flags |= Frame::kExtended;
    EXPECT_EQ(frame_bits_exact(ext), 136U); // CRC 0x169E
}

TEST(FrameBits, EveryFrameLiesBetweenUnstuffedAndWorstCase) {
    std::mt19937 rng(42);
    for (int i = 0; i < 5000; ++i) {
        const bool ext = (i % 3) == 0;
        const auto len = static_cast<std::uint8_t>(rng() % 9);
        std::array<std::uint8_t, 8> data{};
        for (auto& b : data) {
            b = static_cast<std::uint8_t>(rng());
        }
        Frame f = Frame::make(ext ? (rng() & 0x1FFFFFFFU) : (rng() & 0x7FFU),
                              std::span<const std::uint8_t>(data.data(), len));
        if (ext) {
            f.flags |= Frame::kExtended;
        }
        const std::uint32_t unstuffed = (ext ? 67U : 47U) + 8U * len;
        EXPECT_GE(frame_bits_exact(f), unstuffed) << i;
        EXPECT_LE(frame_bits_exact(f), frame_bits_worst_case(f)) << i;
    }
}

TEST(FrameBits, RemoteFrameSendsNoDataWhateverItsDlc) {
    // A guarding request with DLC 1: no data field on the bus (CRC 0x79E0).
    EXPECT_EQ(frame_bits_exact(Frame::make_rtr(0x701, 1)), 51U);
}

TEST(Timeline, MergesBucketsInsteadOfGrowing) {
    Timeline t;
    // One frame every ms for 10 s: 10000 ms do not fit in 512 buckets of 1 ms; the width
    // doubles (to 32 ms) and every count is kept.
    std::uint64_t frames = 0;
    for (std::int64_t ms = 0; ms < 10'000; ++ms) {
        ++t.bus(t.bucket(kStart + ms * kMs)).frames;
        ++frames;
    }
    EXPECT_EQ(t.width_ns(), 32 * kMs);
    EXPECT_LE(t.used(), Timeline::kBuckets);
    std::uint64_t sum = 0;
    for (std::size_t i = 0; i < t.used(); ++i) {
        sum += t.bus(i).frames;
    }
    EXPECT_EQ(sum, frames);
    EXPECT_EQ(t.bus(0).frames, 32U); // the first 32 ms
    // An out-of-order timestamp before the start lands in the first bucket, not outside.
    EXPECT_EQ(t.bucket(kStart - kMs), 0U);
}

TEST(LogHistogram, TenBinsPerDecadeFromOneMicrosecond) {
    EXPECT_EQ(LogHistogram::bin_of(999.0), -1);
    EXPECT_EQ(LogHistogram::bin_of(1'000.0), 0);
    EXPECT_EQ(LogHistogram::bin_of(10'000.0), 10);
    EXPECT_EQ(LogHistogram::bin_of(1'000'000.0), 30);
    EXPECT_EQ(LogHistogram::bin_of(1e11), static_cast<long>(LogHistogram::kBins));
    LogHistogram h;
    h.add(500.0);
    h.add(1'500'000.0); // 1.5 ms: bin 31
    h.add(1e12);
    EXPECT_EQ(h.below(), 1U);
    EXPECT_EQ(h.above(), 1U);
    EXPECT_EQ(h.counts()[31], 1U);
    EXPECT_EQ(h.total(), 3U);
}

TEST(PeriodHistogram, BinsAroundTheMedianOfTheFirstIntervals) {
    PeriodHistogram h;
    for (std::size_t i = 0; i < PeriodHistogram::kLearn - 1; ++i) {
        h.add(1 * kMs);
    }
    h.add(5 * kMs); // an odd one among the first: the median is still 1 ms
    EXPECT_DOUBLE_EQ(h.nominal_ns(), 1e6);
    EXPECT_DOUBLE_EQ(h.bin_ns(), 1e4); // 200 bins over 0..2 ms
    h.add(1500 * kUs);
    const auto c = h.counts();
    EXPECT_EQ(c[100], PeriodHistogram::kLearn - 1); // 1 ms
    EXPECT_EQ(c[150], 1U);                          // 1.5 ms
    EXPECT_EQ(h.above(), 1U);                       // 5 ms
    EXPECT_EQ(h.total(), PeriodHistogram::kLearn + 1);
}

TEST(ReportStats, SyncPeriodAndSyncToTpdoLatency) {
    Stats s(500000);
    s.enable_report();
    for (int i = 0; i < 100; ++i) {
        const std::int64_t t = kStart + i * kMs;
        s.on_sync(t);
        s.on_pdo(3, true, t + 200 * kUs + (i % 2) * 100 * kUs); // 200 or 300 µs after SYNC
        s.on_pdo(3, false, t + 100 * kUs);                      // RPDOs have no latency
    }
    EXPECT_EQ(s.syncs(), 100U);
    EXPECT_EQ(s.sync_period().n, 99U);
    EXPECT_DOUBLE_EQ(s.sync_period().mean_ns, 1e6);
    const auto& lat = s.node(3).sync_latency;
    EXPECT_EQ(lat.n, 100U);
    EXPECT_NEAR(lat.mean_ns, 250e3, 1.0);
    EXPECT_EQ(lat.min_ns, 200 * kUs);
    EXPECT_EQ(lat.max_ns, 300 * kUs);
    // SYNC stops: a TPDO 50 ms later is not "latency" (over twice the SYNC period).
    s.on_pdo(3, true, kStart + 150 * kMs);
    EXPECT_EQ(s.node(3).sync_latency.n, 100U);
    // 200 µs falls in log bin 23 (10^(2.3) µs = 199.5 µs), 300 µs in bin 24.
    EXPECT_EQ(s.detail()->sync_latency[3].counts()[23], 50U);
    EXPECT_EQ(s.detail()->sync_latency[3].counts()[24], 50U);
}

TEST(ReportStats, HeartbeatJitterAndBuckets) {
    Stats s;
    s.enable_report();
    const std::int64_t periods[] = {100, 102, 98, 100, 100};
    std::int64_t t = kStart;
    s.on_heartbeat(5, 0x05, t);
    for (auto p : periods) {
        t += p * kMs;
        s.on_heartbeat(5, 0x05, t);
    }
    const auto& hb = s.node(5).hb;
    EXPECT_EQ(hb.n, 5U);
    EXPECT_DOUBLE_EQ(hb.mean_ns, 100e6);
    EXPECT_NEAR(hb.stddev_ns(), std::sqrt(8.0 / 4.0) * 1e6, 1.0); // sample standard deviation
    EXPECT_EQ(hb.min_ns, 98 * kMs);
    EXPECT_EQ(hb.max_ns, 102 * kMs);
    // The buckets hold every interval and their sum.
    const auto& tl = s.detail()->timeline;
    std::uint32_t n = 0;
    double sum = 0;
    for (std::size_t i = 0; i < tl.used(); ++i) {
        n += tl.node(5, i).hb;
        sum += tl.node(5, i).hb_sum_ns;
    }
    EXPECT_EQ(n, 5U);
    EXPECT_DOUBLE_EQ(sum, 500e6);
}

TEST(ReportStats, MemoryStaysFixedOverFramesAndEventsWithoutEnd) {
    Stats s;
    s.enable_report();
    const auto f = Frame::make(0x181, {1, 2, 3, 4});
    for (std::int64_t i = 0; i < 300'000; ++i) {
        const std::int64_t t = kStart + i * 10 * kMs; // 50 minutes
        s.on_frame(f, t);
        if (i % 30 == 0) {
            s.on_event(t, 1, false, "warning", "sdo", "made-up anomaly");
        }
    }
    const auto* d = s.detail();
    EXPECT_LE(d->timeline.used(), Timeline::kBuckets);
    EXPECT_EQ(d->events.size(), Stats::Detail::kMaxEvents);
    EXPECT_EQ(d->events_total, 10'000U);
    EXPECT_EQ(d->events.capacity(), Stats::Detail::kMaxEvents);
    std::uint64_t frames = 0;
    std::uint64_t anomalies = 0;
    for (std::size_t i = 0; i < d->timeline.used(); ++i) {
        frames += d->timeline.bus(i).frames;
        anomalies += d->timeline.bus(i).anomalies;
    }
    EXPECT_EQ(frames, 300'000U);
    EXPECT_EQ(anomalies, 10'000U);
}

TEST(ReportJson, ConversationBecomesChartData) {
    DumpOptions o;
    o.print = false;
    o.report = true;
    o.bitrate = 250000;
    Dumper d(o, nullptr, nullptr);
    std::int64_t t = kStart;
    // Identity of node 4 read by SDO (1018h:01 vendor, :02 product), a boot-up and heartbeats,
    // SYNC with a TPDO each, an EMCY and an SDO abort.
    const auto step = [&](std::int64_t dt, const Frame& f) {
        t += dt;
        d.on_record(rec(t, f));
    };
    step(0, Frame::make(0x704, {0x00}));
    step(kMs, Frame::make(0x604, {0x40, 0x18, 0x10, 0x01, 0, 0, 0, 0}));
    step(kMs, Frame::make(0x584, {0x43, 0x18, 0x10, 0x01, 0x6A, 0x00, 0x00, 0x00}));
    step(kMs, Frame::make(0x604, {0x40, 0x18, 0x10, 0x02, 0, 0, 0, 0}));
    step(kMs, Frame::make(0x584, {0x43, 0x18, 0x10, 0x02, 0x34, 0x12, 0x00, 0x00}));
    for (int i = 0; i < 50; ++i) {
        step(kMs, Frame::make(0x080, {}));
        step(250 * kUs, Frame::make(0x184, {0x37, 0x06}));
        if (i % 10 == 0) {
            step(0, Frame::make(0x704, {0x05}));
        }
    }
    step(kMs, Frame::make(0x084, {0x10, 0x23, 0x03, 0, 0, 0, 0, 0}));
    step(kMs, Frame::make(0x604, {0x40, 0x00, 0x20, 0x00, 0, 0, 0, 0}));
    step(kMs, Frame::make(0x584, {0x80, 0x00, 0x20, 0x00, 0x00, 0x00, 0x02, 0x06}));
    d.finish();
    const std::string j = report_json(d.stats(), ReportInfo{"made-up.log", "test"});
    EXPECT_EQ(j.front(), '{');
    EXPECT_EQ(j.back(), '}');
    EXPECT_NE(j.find("\"source\":\"made-up.log\""), std::string::npos) << j;
    EXPECT_NE(j.find("\"bitrate\":250000"), std::string::npos);
    EXPECT_NE(j.find("\"identity\":[106,4660,null,null]"), std::string::npos) << j;
    EXPECT_NE(j.find("\"state\":\"operational\""), std::string::npos);
    EXPECT_NE(j.find("\"latency\":{\"n\":50,\"mean\":250,\"jitter\":0,\"min\":250,\"max\":250}"),
              std::string::npos)
        << j;
    EXPECT_NE(j.find("\"sync\":{\"n\":49,"), std::string::npos) << j;
    EXPECT_NE(j.find("\"last_emcy\":\"0x2310 "), std::string::npos) << j;
    // The EMCY and the abort are events with their decoded text.
    EXPECT_NE(j.find("\"emcy\":true,\"severity\":\"error\",\"service\":\"emcy\""),
              std::string::npos)
        << j;
    EXPECT_NE(j.find("abort"), std::string::npos) << j;
    EXPECT_NE(j.find("\"events_total\":2"), std::string::npos) << j;
    EXPECT_EQ(j.find("</"), std::string::npos);
}

TEST(ReportJson, TextCannotCloseTheScriptElement) {
    Stats s;
    s.enable_report();
    s.on_event(kStart, 1, false, "warning", "sdo", "a </script><b>\"quoted\"</b>");
    const std::string j = report_json(s, ReportInfo{"x</script>.log", "test"});
    EXPECT_EQ(j.find("</"), std::string::npos) << j;
    EXPECT_NE(j.find("a <\\/script><b>\\\"quoted\\\"<\\/b>"), std::string::npos) << j;
}

// A candump screen trace has no times: a transfer it leaves open is reported without one, in
// the text, the JSON lines and the report, never as "(0.000000)" or at 1970 on the timeline.
TEST(ReportJson, ATransferOfUntimedFramesEndsWithoutATime) {
    TraceRecord r;
    r.has_ts = false;
    r.iface = "vcan0";
    r.frame = Frame::make(0x605, {0x40, 0x00, 0x10, 0x00, 0, 0, 0, 0});
    for (const bool json : {false, true}) {
        DumpOptions o;
        o.report = true;
        o.line.json = json;
        std::string out;
        Dumper d(
            o, [&](std::string_view s) { out += s; }, nullptr);
        d.on_record(r);
        d.finish();
        EXPECT_NE(out.find("no response before the end of the trace"), std::string::npos) << out;
        if (json) {
            EXPECT_EQ(out.find("\"ts\""), std::string::npos) << out;
            EXPECT_NE(out.find("{\"service\":\"sdo\",\"node\":5,\"event\":\"unfinished\""),
                      std::string::npos)
                << out;
        } else {
            EXPECT_NE(out.find("(no timestamp)  -  "), std::string::npos) << out;
            EXPECT_EQ(out.find("(0.000000)"), std::string::npos) << out;
        }
        const std::string j = report_json(d.stats(), ReportInfo{"screen.log", "test"});
        EXPECT_NE(j.find("{\"t\":null,\"node\":5,"), std::string::npos) << j;
        EXPECT_NE(j.find("\"events_total\":1"), std::string::npos) << j;
    }
}
