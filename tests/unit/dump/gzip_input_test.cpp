// SPDX-License-Identifier: Apache-2.0
// Gzip-compressed traces (RFC 1952): every format reads the same compressed as plain, from a file
// in small pieces and from memory; members one after another read as one file; a cut or corrupt
// stream keeps the frames before the damage and says why.
#include "blf_test_writer.hpp"
#include "dump_test_util.hpp"

#include <codrive/dump/input.hpp>

#include <gtest/gtest.h>
#include <zlib.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>
#include <tuple>
#include <unistd.h>

using namespace codrive;
using namespace codrive::dump;
using codrive::dump::testing::blf_file;
using codrive::dump::testing::BlfEvent;
using codrive::dump::testing::frames_of;
using codrive::dump::testing::read_input;
using codrive::dump::testing::read_trace;
using codrive::dump::testing::ReadItem;
using codrive::dump::testing::slurp;
using codrive::dump::testing::trace_path;

namespace {

// One gzip member holding `plain`, as gzip(1) writes it.
std::string gzip_bytes(const std::string& plain) {
    z_stream s{};
    EXPECT_EQ(deflateInit2(&s, 6, Z_DEFLATED, 16 + MAX_WBITS, 8, Z_DEFAULT_STRATEGY), Z_OK);
    std::string out(deflateBound(&s, plain.size()) + 32, '\0');
    s.next_in = reinterpret_cast<Bytef*>(const_cast<char*>(plain.data()));
    s.avail_in = static_cast<uInt>(plain.size());
    s.next_out = reinterpret_cast<Bytef*>(out.data());
    s.avail_out = static_cast<uInt>(out.size());
    EXPECT_EQ(deflate(&s, Z_FINISH), Z_STREAM_END);
    out.resize(s.total_out);
    deflateEnd(&s);
    return out;
}

// A file under the test's temporary directory, removed at the end of the test.
struct GzTempFile {
    std::string path;
    explicit GzTempFile(const std::string& bytes) {
        path = (std::filesystem::temp_directory_path() /
                ("codrive-gzip-" + std::to_string(::getpid()) + "-" +
                 ::testing::UnitTest::GetInstance()->current_test_info()->name()))
                   .string();
        std::ofstream(path, std::ios::binary) << bytes;
    }
    ~GzTempFile() { std::remove(path.c_str()); }
    GzTempFile(const GzTempFile&) = delete;
    GzTempFile& operator=(const GzTempFile&) = delete;
};

struct GzFileRead {
    std::vector<ReadItem> items;
    std::string read_error;
    bool gzipped = false;
};

// Reads a file through BufferedInput::open with a small buffer, so the inflater refills often.
GzFileRead read_gz_file(const std::string& path, std::size_t capacity = 4096) {
    GzFileRead r;
    auto in = BufferedInput::open(path, capacity);
    EXPECT_TRUE(in) << path;
    if (!in) {
        return r;
    }
    r.items = read_input(**in);
    r.read_error = (*in)->read_error();
    r.gzipped = (*in)->gzipped();
    return r;
}

void expect_same_gz(const std::vector<ReadItem>& got, const std::vector<ReadItem>& want,
                    const std::string& what) {
    ASSERT_EQ(got.size(), want.size()) << what;
    for (std::size_t i = 0; i < got.size(); ++i) {
        ASSERT_EQ(got[i].status, ReadStatus::Frame) << what << ": " << got[i].error;
        EXPECT_EQ(got[i].frame, want[i].frame) << what << " frame " << i;
        EXPECT_EQ(got[i].ts_ns, want[i].ts_ns) << what << " frame " << i;
    }
}

// A candump log of `n` frames (a TPDO with a counter), big enough to cut in the middle.
std::string long_candump_log(int n) {
    std::string log;
    for (int i = 0; i < n; ++i) {
        log += "(1700000000." + std::to_string(100000 + i) + ") can0 181#" +
               std::to_string(1000 + i % 9000) + "\n";
    }
    return log;
}

} // namespace

TEST(DumpGzip, EveryFormatReadsTheSameCompressed) {
    const auto plain_log = slurp(trace_path("formats/conversation.log"));
    const auto want = frames_of(read_trace(plain_log));
    ASSERT_GE(want.size(), 10U);
    std::vector<BlfEvent> events;
    for (const auto& w : want) {
        events.push_back({w.frame, w.ts_ns, 1, BlfObjectType::CanMessage2});
    }
    const std::pair<std::string, std::string> samples[] = {
        {"candump log", plain_log},
        {"long candump log", long_candump_log(5000)},
        {"PEAK trc 2.1", slurp(trace_path("formats/conversation-v21.trc"))},
        {"Vector asc", slurp(trace_path("formats/conversation.asc"))},
        {"Vector blf", blf_file(events)},
    };
    for (const auto& [what, plain] : samples) {
        const auto plain_frames = frames_of(read_trace(plain));
        ASSERT_GE(plain_frames.size(), want.size()) << what;
        const auto gz = gzip_bytes(plain);
        ASSERT_LT(gz.size(), plain.size()) << what;
        expect_same_gz(read_trace(gz), plain_frames, what + " from memory");
        GzTempFile file(gz);
        const auto r = read_gz_file(file.path);
        EXPECT_TRUE(r.gzipped) << what;
        EXPECT_EQ(r.read_error, "") << what;
        expect_same_gz(r.items, plain_frames, what + " from a file");
    }
}

TEST(DumpGzip, MembersOneAfterAnotherReadAsOneFileAndTrailingZerosAreIgnored) {
    // `cat a.gz b.gz > c.gz` (and logrotate's appended pieces) make one file of two members.
    const auto plain = slurp(trace_path("formats/conversation.log"));
    const auto cut = plain.find('\n', plain.size() / 2) + 1;
    const auto want = frames_of(read_trace(plain));
    GzTempFile file(gzip_bytes(plain.substr(0, cut)) + gzip_bytes(plain.substr(cut)) +
                    std::string(512, '\0'));
    const auto r = read_gz_file(file.path, 1024);
    EXPECT_EQ(r.read_error, "");
    expect_same_gz(r.items, want, "two members");
}

TEST(DumpGzip, ACutOrCorruptStreamKeepsTheFramesBeforeAndSaysWhy) {
    const auto plain = long_candump_log(5000);
    const auto want = frames_of(read_trace(plain));
    const auto gz = gzip_bytes(plain);

    GzTempFile cut(gz.substr(0, gz.size() / 2));
    const auto r = read_gz_file(cut.path);
    ASSERT_FALSE(r.items.empty());
    EXPECT_EQ(r.items.back().status, ReadStatus::Fatal);
    EXPECT_NE(r.items.back().error.find("read error: gzip: the compressed stream is cut short "
                                        "after "),
              std::string::npos)
        << r.items.back().error;
    std::size_t frames = 0;
    for (const auto& item : r.items) {
        if (item.status == ReadStatus::Frame) {
            EXPECT_EQ(item.frame, want[frames].frame) << "frame " << frames;
            ++frames;
        }
    }
    EXPECT_GT(frames, want.size() / 4) << "the frames before the cut are read";
    EXPECT_LT(frames, want.size());

    auto bad = gz;
    for (std::size_t i = gz.size() / 3; i < gz.size() / 3 + 16; ++i) {
        bad[i] = static_cast<char>(bad[i] ^ 0x5A);
    }
    GzTempFile corrupt(bad);
    const auto c = read_gz_file(corrupt.path);
    ASSERT_FALSE(c.items.empty());
    EXPECT_EQ(c.items.back().status, ReadStatus::Fatal);
    EXPECT_NE(c.read_error.find("gzip: "), std::string::npos) << c.read_error;
    EXPECT_NE(c.items.back().error.find(c.read_error), std::string::npos) << c.items.back().error;
    // Damaged deflate data may inflate to wrong bytes before zlib notices (the checksum at the
    // end catches the rest): the frames from before the damage are read as they were.
    const auto read_back = frames_of(c.items);
    std::size_t intact = 0;
    while (intact < read_back.size() && intact < want.size() &&
           read_back[intact].frame == want[intact].frame) {
        ++intact;
    }
    EXPECT_GT(intact, want.size() / 10) << "the frames before the damage are read";
}

// A damaged checksum (the member's last 8 bytes: CRC-32 and size, RFC 1952 §2.3.1) is found only
// after all the data has been inflated: every frame is read, then the error is named, as gzip -d
// writes the data and then complains. Bytes after the last member that are neither a member nor
// zero padding are named too, after everything before them.
TEST(DumpGzip, ADamagedChecksumOrTrailingGarbageComesAfterEveryFrame) {
    const auto plain = long_candump_log(2000);
    const auto want = frames_of(read_trace(plain));
    auto crc = gzip_bytes(plain);
    crc[crc.size() - 8] = static_cast<char>(crc[crc.size() - 8] ^ 0x01);
    for (const auto& [what, bytes, cause] :
         {std::tuple{std::string("checksum"), crc, std::string("incorrect data check")},
          std::tuple{std::string("trailing garbage"), gzip_bytes(plain) + "not gzip\n",
                     std::string("are no gzip member")}}) {
        for (const std::size_t capacity : {std::size_t{512}, std::size_t{1} << 20}) {
            GzTempFile file(bytes);
            const auto r = read_gz_file(file.path, capacity);
            expect_same_gz(frames_of(r.items), want, what);
            ASSERT_FALSE(r.items.empty()) << what;
            EXPECT_EQ(r.items.back().status, ReadStatus::Fatal) << what;
            EXPECT_NE(r.read_error.find(cause), std::string::npos) << what << ": " << r.read_error;
        }
    }
}

// A trace compressed with another tool is named as such, not read as text line by line.
TEST(DumpGzip, AFileOfAnotherCompressorIsNamedWithTheCommandThatOpensIt) {
    DumpOptions o;
    const std::pair<std::string, std::string> files[] = {
        {std::string("\xFD"
                     "7zXZ\x00\x00\x04",
                     8),
         "xz-compressed; codrive-dump inflates gzip "
         "only: decompress it first (xz -d)"},
        {"BZh91AY&SY", "bzip2-compressed; codrive-dump inflates gzip only: decompress it first "
                       "(bzip2 -d)"},
        {std::string("\x28\xB5\x2F\xFD\x00\x58", 6), "zstd-compressed"},
        {std::string("PK\x03\x04\x14\x00", 6), "zip-compressed; codrive-dump inflates gzip only: "
                                               "decompress it first (unzip)"},
    };
    for (const auto& [bytes, says] : files) {
        const auto out = codrive::dump::testing::run_dump_bytes(bytes, o);
        EXPECT_NE(out.find(says), std::string::npos) << out;
    }
    EXPECT_EQ(codrive::dump::testing::run_dump_bytes("BZh is a word\n", o).find("compressed"),
              std::string::npos)
        << "BZh without a block size digit is text";
}
