// SPDX-License-Identifier: Apache-2.0
// Every trace format: detected by content, the same conversation decodes to the same lines from
// each, and a round trip through pcapng (`-w out.pcapng`) keeps every frame byte-exact.
#include "dump_test_util.hpp"

#include <codrive/dump/pcap.hpp>

#include <gtest/gtest.h>

#include <sstream>

using namespace codrive;
using namespace codrive::dump;
using codrive::dump::testing::frames_of;
using codrive::dump::testing::read_trace;
using codrive::dump::testing::ReadItem;
using codrive::dump::testing::run_dump;
using codrive::dump::testing::slurp;
using codrive::dump::testing::trace_path;

namespace {

// The same conversation in every format (tests/data/traces/formats/).
const std::vector<std::pair<std::string, TraceFormat>> kSameConversation = {
    {"conversation.log", TraceFormat::Candump},
    {"conversation-screen.txt", TraceFormat::Candump},
    {"conversation-screen-delta.txt", TraceFormat::Candump},
    {"conversation-v11.trc", TraceFormat::PeakTrc},
    {"conversation-v13.trc", TraceFormat::PeakTrc},
    {"conversation-v20.trc", TraceFormat::PeakTrc},
    {"conversation-v21.trc", TraceFormat::PeakTrc},
    {"conversation.asc", TraceFormat::VectorAsc},
    {"conversation-python-can.csv", TraceFormat::Csv},
    {"conversation.blf", TraceFormat::VectorBlf},
};

// The output with the interface column taken out (each format names interfaces its own way).
std::string without_interface(const std::string& out) {
    std::istringstream in(out);
    std::string line;
    std::string result;
    while (std::getline(in, line)) {
        const auto ts_end = line.find(' ');
        auto iface = line.find_first_not_of(' ', ts_end);
        const auto iface_end = line.find(' ', iface);
        const auto rest = line.find_first_not_of(' ', iface_end);
        result += line.substr(0, ts_end) + " " +
                  (rest == std::string::npos ? std::string() : line.substr(rest)) + "\n";
    }
    return result;
}

std::string conversation(const std::string& file) {
    return slurp(trace_path("formats/" + file));
}

} // namespace

TEST(DumpTraceFormat, EachFormatIsRecognisedByItsContent) {
    for (const auto& [file, format] : kSameConversation) {
        const auto bytes = conversation(file);
        EXPECT_EQ(
            detect_trace_format(reinterpret_cast<const std::uint8_t*>(bytes.data()), bytes.size()),
            format)
            << file;
    }
    const auto detect = [](std::string_view s) {
        return detect_trace_format(reinterpret_cast<const std::uint8_t*>(s.data()), s.size());
    };
    EXPECT_EQ(detect("\xEF\xBB\xBF;$FILEVERSION=2.1\n"), TraceFormat::PeakTrc);
    EXPECT_EQ(detect("# comment\n(1.0) can0 181#00\n"), TraceFormat::Candump);
    EXPECT_EQ(detect("  can0  181   [1]  00\n"), TraceFormat::Candump);
    EXPECT_EQ(detect("\r\nbase hex  timestamps absolute\r\n"), TraceFormat::VectorAsc);
    EXPECT_EQ(detect("Time Stamp,ID,Extended,Dir,Bus,LEN,D1,D2\n"), TraceFormat::Csv);
    EXPECT_EQ(detect("a,b,c\n1,2,3\n"), TraceFormat::Candump) << "CSV needs id and data columns";
    EXPECT_EQ(detect("\xD4\xC3\xB2\xA1"), TraceFormat::Pcap);
    EXPECT_EQ(detect(std::string_view("LOGG\x90\0\0\0", 8)), TraceFormat::VectorBlf);
    EXPECT_EQ(detect("LOGGING STARTED\n(1.0) can0 181#00\n"), TraceFormat::Candump)
        << "BLF is recognised by its binary header, not by a word";
    EXPECT_EQ(detect(""), TraceFormat::Candump);
}

TEST(DumpTraceFormat, TheSameConversationDecodesTheSameFromEveryFormat) {
    DumpOptions zero;
    zero.line.time = TimeMode::Zero;
    const auto reference = run_dump("formats/conversation.log", zero);
    ASSERT_NE(reference.find("node 4 upload 1000:00 Device type = 0x00020192"), std::string::npos)
        << reference;
    ASSERT_NE(reference.find("node 5 guarding request"), std::string::npos) << reference;
    ASSERT_EQ(reference.find("codrive-dump:"), std::string::npos) << reference;
    for (const auto& [file, format] : kSameConversation) {
        EXPECT_EQ(without_interface(run_dump("formats/" + file, zero)),
                  without_interface(reference))
            << file;
    }
}

TEST(DumpTraceFormat, AbsoluteTimestampsAreKept) {
    const auto reference = frames_of(read_trace(conversation("conversation.log")));
    ASSERT_EQ(reference.size(), 12U);
    for (const auto& [file, format] : kSameConversation) {
        if (file == "conversation-screen-delta.txt") {
            continue; // candump -t d has no absolute time
        }
        const auto frames = frames_of(read_trace(conversation(file)));
        ASSERT_EQ(frames.size(), reference.size()) << file;
        for (std::size_t i = 0; i < frames.size(); ++i) {
            EXPECT_EQ(frames[i].ts_ns, reference[i].ts_ns) << file << " frame " << i;
            EXPECT_EQ(frames[i].frame, reference[i].frame) << file << " frame " << i;
        }
    }
}

TEST(DumpTraceFormat, SavvyCanExportHasTheFramesRelativeToItsStart) {
    auto reference = frames_of(read_trace(conversation("conversation.log")));
    std::erase_if(reference, [](const ReadItem& i) { return i.frame.rtr(); }); // no RTR column
    const auto frames = frames_of(read_trace(conversation("conversation-savvycan.csv")));
    ASSERT_EQ(frames.size(), reference.size());
    for (std::size_t i = 0; i < frames.size(); ++i) {
        EXPECT_EQ(frames[i].frame, reference[i].frame) << i;
        EXPECT_EQ(frames[i].ts_ns, reference[i].ts_ns - reference[0].ts_ns) << i;
    }
}

TEST(DumpTraceFormat, IxxatExportHasTheFramesRelativeToTheInterfaceStart) {
    auto reference = frames_of(read_trace(conversation("conversation.log")));
    std::erase_if(reference, [](const ReadItem& i) { return i.frame.rtr(); }); // no RTR column
    TraceFormat format{};
    const auto frames = frames_of(read_trace(conversation("conversation-ixxat.csv"), &format));
    EXPECT_EQ(format, TraceFormat::Csv);
    ASSERT_EQ(frames.size(), reference.size());
    for (std::size_t i = 0; i < frames.size(); ++i) {
        ASSERT_EQ(frames[i].status, ReadStatus::Frame) << i << ": " << frames[i].error;
        EXPECT_EQ(frames[i].frame, reference[i].frame) << i;
        // "Time (abs)" counts from when the interface started (3605.25 s before the first frame).
        EXPECT_EQ(frames[i].ts_ns - 3'605'250'000'000LL, reference[i].ts_ns - reference[0].ts_ns)
            << i;
        EXPECT_EQ(frames[i].iface, "can1") << "the Bus column";
    }
}

TEST(DumpTraceFormat, EveryFormatRoundTripsThroughPcapngByteExact) {
    const auto path = ::testing::TempDir() + "/dump_roundtrip.pcapng";
    auto files = kSameConversation;
    files.emplace_back("conversation-savvycan.csv", TraceFormat::Csv);
    files.emplace_back("conversation-ixxat.csv", TraceFormat::Csv);
    for (const auto& [file, format] : files) {
        const auto original = frames_of(read_trace(conversation(file)));
        {
            auto w = PcapWriter::open(path);
            ASSERT_TRUE(w);
            for (const auto& item : original) {
                TraceRecord r;
                r.frame = item.frame;
                r.ts_ns = item.ts_ns;
                r.iface = item.iface;
                (*w)->write(r);
            }
        }
        TraceFormat detected{};
        const auto back = read_trace(slurp(path), &detected);
        EXPECT_EQ(detected, TraceFormat::Pcap);
        ASSERT_EQ(back.size(), original.size()) << file;
        for (std::size_t i = 0; i < back.size(); ++i) {
            ASSERT_EQ(back[i].status, ReadStatus::Frame) << file << ": " << back[i].error;
            EXPECT_EQ(back[i].frame, original[i].frame) << file << " frame " << i;
            EXPECT_EQ(back[i].ts_ns, original[i].ts_ns) << "pcapng keeps nanoseconds";
            EXPECT_EQ(back[i].iface, original[i].iface) << "one interface description per name";
        }
    }
}

TEST(DumpTraceFormat, PcapngKeepsCanFdBrsErrorAndRemoteFrames) {
    Frame fd = Frame::make(0x123, {});
    fd.flags = Frame::kFd | Frame::kBrs;
    fd.len = 64;
    fd.data[63] = 0xEE;
    Frame err = Frame::make(0x40, {}); // CAN_ERR_BUSOFF
    err.flags = Frame::kError;
    err.len = 8;
    Frame ext = Frame::make(0x1ABCDEF, {1});
    ext.flags = Frame::kExtended;
    const std::vector<Frame> frames = {fd, err, ext, Frame::make_rtr(0x705, 1)};
    const auto path = ::testing::TempDir() + "/dump_kinds.pcapng";
    {
        auto w = PcapWriter::open(path);
        ASSERT_TRUE(w);
        std::int64_t ts = 1'795'478'400'123'456'789LL;
        for (const auto& f : frames) {
            TraceRecord r;
            r.frame = f;
            r.ts_ns = ts++;
            r.iface = "can0";
            (*w)->write(r);
        }
    }
    const auto back = read_trace(slurp(path));
    ASSERT_EQ(back.size(), frames.size());
    for (std::size_t i = 0; i < frames.size(); ++i) {
        EXPECT_EQ(back[i].frame, frames[i]) << i;
        EXPECT_EQ(back[i].ts_ns, 1'795'478'400'123'456'789LL + static_cast<std::int64_t>(i));
    }
}

// Another tool's log (BUSMASTER's here, as SavvyCAN's examples have it) is no format codrive-dump
// reads: after 20 unreadable lines and no frame, one sentence and the end, not one error for each
// of its thousands of lines. Unreadable lines after a frame, or fewer than 20, are each skipped.
TEST(DumpTraceFormat, AFileOfAnotherFormatStopsAfterTwentyUnreadableLines) {
    std::string busmaster = "***BUSMASTER Ver 2.4.0***\n***PROTOCOL CAN***\n";
    for (int i = 0; i < 500; ++i) {
        busmaster += "22:20:14:992 Rx 0 0000029A s 8 01 36 FE 00 00 00 00 00\n";
    }
    const auto items = read_trace(busmaster);
    ASSERT_EQ(items.size(), 20U);
    for (std::size_t i = 0; i < 19; ++i) {
        EXPECT_EQ(items[i].status, ReadStatus::Malformed) << i;
    }
    EXPECT_EQ(items[19].status, ReadStatus::Fatal);
    EXPECT_EQ(items[19].error.rfind("20: no trace format codrive-dump reads: none of the first 20 "
                                    "lines that are not comments could be read, so reading stops "
                                    "(this one: bad CAN identifier: '22:20:14:992",
                                    0),
              0U)
        << items[19].error;

    std::string mixed;
    for (int i = 0; i < 19; ++i) {
        mixed += "garbage line\n";
    }
    mixed += "(1700000000.000000) can0 704#05\n";
    for (int i = 0; i < 30; ++i) {
        mixed += "garbage line\n";
    }
    mixed += "(1700000000.100000) can0 704#05\n";
    const auto kept = read_trace(mixed);
    EXPECT_EQ(frames_of(kept).size(), 2U) << "a file with frames is read to its end";
    EXPECT_EQ(kept.size(), 51U);
}
