// SPDX-License-Identifier: Apache-2.0
// pcap/pcapng: SocketCAN record layout, round trip, pcapng, truncation.
#include "dump_test_util.hpp"

#include <codrive/core/endian.hpp>
#include <codrive/dump/log_parser.hpp>
#include <codrive/dump/pcap.hpp>

#include <gtest/gtest.h>

#include <fstream>
#include <sstream>

using namespace codrive;
using namespace codrive::dump;
using codrive::dump::testing::rec;
using codrive::dump::testing::slurp;

namespace {
std::string write_pcap(const std::vector<TraceRecord>& recs) {
    const auto path = ::testing::TempDir() + "/dump_test.pcap";
    {
        auto w = PcapWriter::open(path);
        EXPECT_TRUE(w);
        for (const auto& r : recs) {
            (*w)->write(r);
        }
    }
    return slurp(path);
}

} // namespace

TEST(DumpPcap, SocketCanIdIsBigEndianWithFlagsInTopBits) {
    Frame ext = Frame::make(0, {0xAA});
    ext.id = 0x12345678;
    ext.flags = Frame::kExtended;
    const auto bytes = write_pcap({rec(1'700'000'000'123'456'000, ext)});
    ASSERT_EQ(bytes.size(), 24U + 16U + 16U);
    const auto* p = reinterpret_cast<const std::uint8_t*>(bytes.data());
    EXPECT_EQ(get_le<std::uint32_t>(p), 0xA1B2C3D4U);
    EXPECT_EQ(get_le<std::uint32_t>(p + 20), 227U);
    EXPECT_EQ(get_le<std::uint32_t>(p + 24), 1'700'000'000U);
    EXPECT_EQ(get_le<std::uint32_t>(p + 28), 123'456U);
    const auto* c = p + 40;
    EXPECT_EQ(c[0], 0x92); // 0x80000000 (EFF) | 0x12345678, big-endian
    EXPECT_EQ(c[1], 0x34);
    EXPECT_EQ(c[2], 0x56);
    EXPECT_EQ(c[3], 0x78);
    EXPECT_EQ(c[4], 1);
    EXPECT_EQ(c[8], 0xAA);
}

TEST(DumpPcap, RoundTripKeepsFramesAndTimestamps) {
    Frame rtr = Frame::make_rtr(0x705, 1);
    Frame fd = Frame::make(0x123, {});
    fd.flags = Frame::kFd;
    fd.len = 12;
    fd.data[11] = 0x5A;
    const auto bytes = write_pcap({rec(1'000'000'001'000, Frame::make(0x181, {1, 2, 3})),
                                   rec(2'000'000'000'000, rtr), rec(3'000'000'000'000, fd)});
    auto in = BufferedInput::from_memory(bytes);
    PcapReader reader(*in);
    TraceRecord r;
    ASSERT_EQ(reader.next(r), ReadStatus::Frame) << reader.error();
    EXPECT_EQ(r.ts_ns, 1'000'000'001'000);
    EXPECT_EQ(r.frame, Frame::make(0x181, {1, 2, 3}));
    ASSERT_EQ(reader.next(r), ReadStatus::Frame);
    EXPECT_TRUE(r.frame.rtr());
    EXPECT_EQ(r.frame.id, 0x705U);
    ASSERT_EQ(reader.next(r), ReadStatus::Frame);
    EXPECT_TRUE(r.frame.fd());
    EXPECT_EQ(r.frame.len, 12);
    EXPECT_EQ(r.frame.data[11], 0x5A);
    EXPECT_EQ(reader.next(r), ReadStatus::End);
}

TEST(DumpPcap, TruncatedFileEndsWithAMessage) {
    auto bytes = write_pcap(
        {rec(1'000'000'000, Frame::make(0x181, {1})), rec(2'000'000'000, Frame::make(0x182, {2}))});
    bytes.resize(bytes.size() - 5);
    DumpOptions o;
    const auto out = codrive::dump::testing::run_dump_bytes(bytes, o);
    EXPECT_NE(out.find("pcap truncated after 1 records"), std::string::npos) << out;
    EXPECT_NE(out.find("node 1 TPDO1"), std::string::npos) << out;
}

TEST(DumpPcap, DecodesTheSameAsTheLogItWasWrittenFrom) {
    // Every frame of the block-transfer trace, through pcap and back, decodes to the same text.
    DumpOptions o;
    o.line.time = TimeMode::None;
    const auto from_log = codrive::dump::testing::run_dump("sdo_block.log", o);
    std::vector<TraceRecord> recs;
    auto in = BufferedInput::open(codrive::dump::testing::trace_path("sdo_block.log"));
    ASSERT_TRUE(in);
    LogReader reader(**in);
    TraceRecord r;
    while (reader.next(r) == ReadStatus::Frame) {
        recs.push_back(r);
    }
    ASSERT_EQ(recs.size(), 31U);
    auto from_pcap = codrive::dump::testing::run_dump_bytes(write_pcap(recs), o);
    // pcap has no interface names: the reader calls every frame's interface "pcap".
    for (auto pos = from_pcap.find("pcap "); pos != std::string::npos;
         pos = from_pcap.find("pcap ", pos)) {
        from_pcap.replace(pos, 5, "can0 ");
    }
    EXPECT_EQ(from_pcap, from_log);
}

TEST(DumpPcap, PcapngWithNanosecondResolutionAndInterfaceName) {
    std::string b;
    auto u32 = [&](std::uint32_t v) {
        for (int i = 0; i < 4; ++i) {
            b.push_back(static_cast<char>(v >> (8 * i)));
        }
    };
    auto u16 = [&](std::uint16_t v) {
        b.push_back(static_cast<char>(v));
        b.push_back(static_cast<char>(v >> 8));
    };
    // SHB
    u32(0x0A0D0D0A);
    u32(28);
    u32(0x1A2B3C4D);
    u16(1);
    u16(0);
    u32(0xFFFFFFFF);
    u32(0xFFFFFFFF);
    u32(28);
    // IDB with if_name "vcan7" and if_tsresol 9
    u32(1);
    u32(44);
    u16(227);
    u16(0);
    u32(72);
    u16(2);
    u16(5);
    b += "vcan7";
    b.append(3, '\0');
    u16(9);
    u16(1);
    b.push_back(9);
    b.append(3, '\0');
    u16(0);
    u16(0);
    u32(44);
    // EPB with a 16-byte SocketCAN frame 0x701 [1] 05 at 1.5 s
    const std::uint64_t ts = 1'500'000'000;
    u32(6);
    u32(32 + 16);
    u32(0);
    u32(static_cast<std::uint32_t>(ts >> 32));
    u32(static_cast<std::uint32_t>(ts));
    u32(16);
    u32(16);
    b += std::string("\x00\x00\x07\x01\x01\x00\x00\x00\x05\x00\x00\x00\x00\x00\x00\x00", 16);
    u32(32 + 16);
    // The same frame at 2^64 - 1 ns: past the year 2255, the latest time a trace may carry.
    u32(6);
    u32(32 + 16);
    u32(0);
    u32(0xFFFFFFFF);
    u32(0xFFFFFFFF);
    u32(16);
    u32(16);
    b += std::string("\x00\x00\x07\x01\x01\x00\x00\x00\x05\x00\x00\x00\x00\x00\x00\x00", 16);
    u32(32 + 16);
    auto in = BufferedInput::from_memory(b);
    PcapReader reader(*in);
    TraceRecord r;
    ASSERT_EQ(reader.next(r), ReadStatus::Frame) << reader.error();
    EXPECT_EQ(r.iface, "vcan7");
    EXPECT_EQ(r.ts_ns, 1'500'000'000);
    EXPECT_EQ(r.frame, Frame::make(0x701, {5}));
    ASSERT_EQ(reader.next(r), ReadStatus::Malformed);
    EXPECT_EQ(reader.error(), "pcapng packet 2: timestamp 18446744073709551615 (1000000000 per "
                              "second) is past the year 2255, skipped");
    EXPECT_EQ(reader.next(r), ReadStatus::End);
}

namespace {
// A 16-byte struct can_frame record: big-endian id, len, pad/flags, res0, res1 (len8_dlc), data.
std::vector<std::uint8_t> classic_record(std::uint32_t id, std::uint8_t len, std::uint8_t pad,
                                         std::uint8_t res0, std::uint8_t res1,
                                         std::vector<std::uint8_t> data) {
    std::vector<std::uint8_t> r{static_cast<std::uint8_t>(id >> 24),
                                static_cast<std::uint8_t>(id >> 16),
                                static_cast<std::uint8_t>(id >> 8),
                                static_cast<std::uint8_t>(id),
                                len,
                                pad,
                                res0,
                                res1};
    data.resize(8);
    r.insert(r.end(), data.begin(), data.end());
    return r;
}
} // namespace

TEST(DumpPcap, JunkInThePadByteOfAClassicRecordIsNotCanFd) {
    // An SDO upload initiate as an old kernel captured it: `7f 00 00` after the length byte.
    const auto r = classic_record(0x605, 8, 0x7F, 0x00, 0x00, {0x40, 0x10, 0x20, 0x0D});
    Frame f;
    ASSERT_EQ(decode_socketcan_record(r.data(), r.size(), r.size(), f), SocketCanDecode::Ok);
    EXPECT_FALSE(f.fd());
    EXPECT_EQ(f.id, 0x605U);
    EXPECT_EQ(f.len, 8);
    EXPECT_EQ(f.data[0], 0x40);
    EXPECT_EQ(f.data[3], 0x0D);
    // FDF set but reserved bytes dirty: still junk, not FD.
    const auto r2 = classic_record(0x000, 2, 0x04, 0x11, 0x00, {0x81, 0x0F});
    ASSERT_EQ(decode_socketcan_record(r2.data(), r2.size(), r2.size(), f), SocketCanDecode::Ok);
    EXPECT_FALSE(f.fd());
    EXPECT_EQ(f.len, 2);
    EXPECT_EQ(f.data[1], 0x0F);
}

TEST(DumpPcap, CleanFdFlagsOrA72ByteRecordIsCanFd) {
    // Clean flags byte with FDF|BRS and zero reserved bytes: believed.
    const auto r = classic_record(0x181, 8, 0x05, 0x00, 0x00, {1, 2, 3, 4, 5, 6, 7, 8});
    Frame f;
    ASSERT_EQ(decode_socketcan_record(r.data(), r.size(), r.size(), f), SocketCanDecode::Ok);
    EXPECT_TRUE(f.fd());
    EXPECT_NE(f.flags & Frame::kBrs, 0);
    // A 72-byte record (CANFD_MTU) is FD whatever the flags byte says (kernels before FDF).
    std::vector<std::uint8_t> fd(72, 0);
    fd[2] = 0x01;
    fd[3] = 0x81;
    fd[4] = 12;
    for (std::size_t i = 0; i < 12; ++i) {
        fd[8 + i] = static_cast<std::uint8_t>(0xA0 + i);
    }
    ASSERT_EQ(decode_socketcan_record(fd.data(), fd.size(), fd.size(), f), SocketCanDecode::Ok);
    EXPECT_TRUE(f.fd());
    EXPECT_EQ(f.flags & Frame::kBrs, 0);
    EXPECT_EQ(f.len, 12);
    EXPECT_EQ(f.data[11], 0xAB);
    // Captured with a snaplen of 20: the original length still says FD.
    ASSERT_EQ(decode_socketcan_record(fd.data(), 20, 72, f), SocketCanDecode::Ok);
    EXPECT_TRUE(f.fd());
    EXPECT_EQ(f.len, 12);
}

TEST(DumpPcap, ClassicRecordClaimingMoreThan8BytesIsReportedNotTakenForFd) {
    const auto r = classic_record(0x705, 12, 0x7F, 0x00, 0x00, {0x05});
    Frame f;
    ASSERT_EQ(decode_socketcan_record(r.data(), r.size(), r.size(), f),
              SocketCanDecode::ClassicLenOver8);
    EXPECT_FALSE(f.fd());
    const auto msg =
        socketcan_decode_error(SocketCanDecode::ClassicLenOver8, "pcap record 3", r.size(), f);
    EXPECT_NE(msg.find("pcap record 3"), std::string::npos) << msg;
    EXPECT_NE(msg.find("0x705"), std::string::npos) << msg;
    EXPECT_NE(msg.find("12 data bytes"), std::string::npos) << msg;
}

TEST(DumpPcap, JunkPadRecordsInAFileDecodeAsCanopen) {
    // A whole classic pcap: header + NMT reset node 15 and an SDO request with junk pad bytes.
    std::vector<std::uint8_t> file{0xD4, 0xC3, 0xB2, 0xA1, 2, 0, 4, 0, 0,   0, 0, 0,
                                   0,    0,    0,    0,    0, 0, 4, 0, 227, 0, 0, 0};
    auto add = [&](std::uint32_t sec, const std::vector<std::uint8_t>& body) {
        const std::uint32_t hdr[4] = {sec, 0, static_cast<std::uint32_t>(body.size()),
                                      static_cast<std::uint32_t>(body.size())};
        for (auto v : hdr) {
            for (int i = 0; i < 4; ++i) {
                file.push_back(static_cast<std::uint8_t>(v >> (8 * i)));
            }
        }
        file.insert(file.end(), body.begin(), body.end());
    };
    add(1, classic_record(0x000, 2, 0x7F, 0x00, 0x00, {0x81, 0x0F}));
    add(2, classic_record(0x60F, 8, 0xFF, 0x00, 0x00, {0x40, 0x10, 0x20, 0x0D}));
    const std::string bytes(file.begin(), file.end());
    const auto out = codrive::dump::testing::run_dump_bytes(bytes, DumpOptions{});
    EXPECT_NE(out.find("NMT"), std::string::npos) << out;
    EXPECT_NE(out.find("NMT reset node"), std::string::npos) << out;
    EXPECT_EQ(out.find("FD"), std::string::npos) << out;
}

namespace {
// A pcapng file in either byte order: a section header, one SocketCAN interface with `options`
// (code, value), and one EPB of the frame 701h [1] 05 per timestamp (in interface units).
std::string pcapng_file(bool big_endian,
                        const std::vector<std::pair<std::uint16_t, std::string>>& options,
                        const std::vector<std::uint64_t>& stamps) {
    const auto put = [big_endian](std::string& b, std::uint64_t v, int bytes) {
        for (int i = 0; i < bytes; ++i) {
            const int shift = 8 * (big_endian ? bytes - 1 - i : i);
            b.push_back(static_cast<char>(v >> shift));
        }
    };
    const auto block = [&](std::uint32_t type, const std::string& body) {
        std::string b;
        put(b, type, 4);
        put(b, 12 + body.size(), 4);
        b += body;
        put(b, 12 + body.size(), 4);
        return b;
    };
    std::string shb;
    put(shb, 0x1A2B3C4D, 4);
    put(shb, 1, 2);
    put(shb, 0, 2);
    put(shb, ~std::uint64_t{0}, 8);
    std::string idb;
    put(idb, 227, 2); // LINKTYPE_CAN_SOCKETCAN
    put(idb, 0, 2);
    put(idb, 0, 4);
    for (const auto& [code, value] : options) {
        put(idb, code, 2);
        put(idb, value.size(), 2);
        idb += value;
        idb.append((4 - value.size() % 4) % 4, '\0');
    }
    put(idb, 0, 4); // opt_endofopt
    std::string file = block(0x0A0D0D0A, shb) + block(1, idb);
    for (const auto ts : stamps) {
        std::string epb;
        put(epb, 0, 4);
        put(epb, ts >> 32, 4);
        put(epb, ts & 0xFFFFFFFFU, 4);
        put(epb, 16, 4);
        put(epb, 16, 4);
        epb += std::string("\x00\x00\x07\x01\x01\x00\x00\x00\x05\x00\x00\x00\x00\x00\x00\x00", 16);
        file += block(6, epb);
    }
    return file;
}

std::string int64_value(bool big_endian, std::int64_t v) {
    std::string s;
    for (int i = 0; i < 8; ++i) {
        s.push_back(
            static_cast<char>(static_cast<std::uint64_t>(v) >> (8 * (big_endian ? 7 - i : i))));
    }
    return s;
}
} // namespace

// if_tsresol in powers of two and down to 10^-19 s, and if_tsoffset (seconds added to every
// timestamp), in both byte orders. The expected times are tshark 4.0's for the same files, but
// for 10^-19 s, where tshark reads 1.0 s (1.5 * 10^19 units of 10^-19 s are 1.5 s).
TEST(DumpPcap, PcapngResolutionAndOffsetOptionsInBothByteOrders) {
    for (const bool big : {false, true}) {
        SCOPED_TRACE(big ? "big-endian section" : "little-endian section");
        const auto times = [](const std::string& file) {
            auto in = BufferedInput::from_memory(file);
            PcapReader reader(*in);
            std::vector<std::string> out;
            TraceRecord r;
            for (ReadStatus s; (s = reader.next(r)) != ReadStatus::End && s != ReadStatus::Fatal;) {
                out.push_back(s == ReadStatus::Frame ? std::to_string(r.ts_ns)
                                                     : std::string(reader.error()));
            }
            return out;
        };
        using V = std::vector<std::string>;
        EXPECT_EQ(times(pcapng_file(big, {{9, "\x94"}}, {3 * (1U << 20) + (1U << 19)})),
                  V{"3500000000"}); // 2^-20 s units
        EXPECT_EQ(times(pcapng_file(big, {{9, "\x13"}}, {15'000'000'000'000'000'000ULL})),
                  V{"1500000000"}); // 10^-19 s units
        EXPECT_EQ(times(pcapng_file(big, {{14, int64_value(big, 1'700'000'000)}}, {1'500'000})),
                  V{"1700000001500000000"});
        EXPECT_EQ(times(pcapng_file(big, {{14, int64_value(big, -10)}}, {1'500'000, 12'500'000})),
                  (V{"pcapng packet 1: timestamp 1500000 (1000000 per second) with the interface's "
                     "offset of -10 s is before 1970 or past the year 2255, skipped",
                     "2500000000"}));
        EXPECT_EQ(times(pcapng_file(big, {{9, "\x14"}}, {1})),
                  V{"pcapng packet 1: its interface's if_tsresol of 10^-20 s is too fine: a "
                    "second holds more than 2^64 such units, skipped"});
    }
}
