// SPDX-License-Identifier: Apache-2.0
// Gzip inflation with zlib (inflateInit2 with a gzip wrapper), member after member.
#include <codrive/dump/gunzip.hpp>

#include <codrive/dump/input.hpp>

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <cerrno>
#include <cstring>
#include <vector>
#include <zlib.h>

namespace codrive::dump {
namespace {

constexpr std::size_t kCompressedChunk = 64U * 1024U;
constexpr std::uint8_t kGzipMagic0 = 0x1F; // RFC 1952 §2.3.1: ID1, ID2
constexpr std::uint8_t kGzipMagic1 = 0x8B;

} // namespace

struct Gunzip::State {
    z_stream s{};
    bool ready = false;
    bool in_member = true; ///< inside a member: the file must not end here
    bool file_end = false;
    std::uint64_t inflated = 0;
    std::string pending_error; ///< found after the bytes last returned; reported next time
    std::vector<std::uint8_t> in;
    State() { ready = inflateInit2(&s, 16 + MAX_WBITS) == Z_OK; } // 16: gzip, not zlib
    ~State() {
        if (ready) {
            inflateEnd(&s);
        }
    }
    State(const State&) = delete;
    State& operator=(const State&) = delete;
};

std::string_view other_compression(const std::uint8_t* p, std::size_t n) {
    struct Magic {
        std::string_view bytes;
        std::string_view tool;
    };
    // The formats' own magic numbers: xz (FD "7zXZ" 00), bzip2 ("BZh" and a block size digit),
    // zstd frames (28 B5 2F FD), lz4 frames (04 22 4D 18), zip local file headers ("PK" 03 04).
    static constexpr std::array<Magic, 5> kMagics = {{
        {std::string_view("\xFD"
                          "7zXZ\x00",
                          6),
         "xz"},
        {"BZh", "bzip2"},
        {"\x28\xB5\x2F\xFD", "zstd"},
        {"\x04\x22\x4D\x18", "lz4"},
        {"PK\x03\x04", "zip"},
    }};
    const std::string_view head(reinterpret_cast<const char*>(p), n);
    for (const auto& m : kMagics) {
        if (head.substr(0, m.bytes.size()) == m.bytes &&
            (m.tool != "bzip2" || (n > 3 && p[3] >= '1' && p[3] <= '9'))) {
            return m.tool;
        }
    }
    return {};
}

bool Gunzip::is_gzip(const std::uint8_t* p, std::size_t n) {
    return n >= 2 && p[0] == kGzipMagic0 && p[1] == kGzipMagic1;
}

Gunzip::Gunzip(std::unique_ptr<State> state) : st_(std::move(state)) {}

Gunzip::~Gunzip() = default;

std::unique_ptr<Gunzip> Gunzip::start(std::string_view first, bool file_end) {
    auto st = std::make_unique<State>();
    if (!st->ready) {
        return nullptr;
    }
    st->in.assign(first.begin(), first.end());
    if (!file_end) {
        st->in.resize(std::max(st->in.size(), kCompressedChunk));
    }
    st->s.next_in = st->in.data();
    st->s.avail_in = static_cast<uInt>(first.size());
    st->file_end = file_end;
    return std::unique_ptr<Gunzip>(new Gunzip(std::move(st)));
}

long Gunzip::read(int fd, std::uint8_t* dst, std::size_t n, std::string& error) {
    State& g = *st_;
    if (!g.pending_error.empty()) {
        error = g.pending_error;
        return -1;
    }
    const auto message = [&](std::string_view why) {
        return fmt::format("gzip: {} after {} uncompressed bytes", why, g.inflated);
    };
    const auto fail_with = [&](std::string_view why) {
        error = message(why);
        return -1L;
    };
    for (;;) {
        if (g.s.avail_in == 0 && !g.file_end) {
            const long got = read_retrying(fd, g.in.data(), g.in.size());
            if (got < 0) {
                error = std::strerror(errno);
                return -1;
            }
            g.file_end = got == 0;
            g.s.next_in = g.in.data();
            g.s.avail_in = static_cast<uInt>(got);
        }
        if (g.s.avail_in == 0) { // the file has ended
            return g.in_member ? fail_with("the compressed stream is cut short") : 0;
        }
        if (!g.in_member) {
            // RFC 1952 §2.2: a file is a series of members. Zero padding after the last one is
            // ignored; other bytes are named (gzip -d warns "trailing garbage ignored").
            if (g.s.next_in[0] != kGzipMagic0) {
                return trailing(fd, error);
            }
            if (inflateReset(&g.s) != Z_OK) {
                return fail_with("zlib could not start the next member");
            }
            g.in_member = true;
        }
        g.s.next_out = dst;
        g.s.avail_out = static_cast<uInt>(std::min<std::size_t>(n, 1U << 30));
        const int r = inflate(&g.s, Z_NO_FLUSH);
        const auto produced = static_cast<std::size_t>(g.s.next_out - dst);
        g.inflated += produced;
        if (r == Z_STREAM_END) {
            g.in_member = false;
        } else if (r != Z_OK && r != Z_BUF_ERROR) {
            const auto why =
                fmt::format("bad compressed data ({})", g.s.msg != nullptr ? g.s.msg : zError(r));
            if (produced == 0) {
                return fail_with(why);
            }
            g.pending_error = message(why); // the bytes before the damage first (a bad checksum)
        }
        if (produced > 0) {
            return static_cast<long>(produced);
        }
    }
}

long Gunzip::trailing(int fd, std::string& error) {
    State& g = *st_;
    const auto nonzero = [](const std::uint8_t* p, std::size_t n) {
        return std::any_of(p, p + n, [](std::uint8_t b) { return b != 0; });
    };
    bool garbage = nonzero(g.s.next_in, g.s.avail_in);
    g.s.avail_in = 0;
    while (!garbage && !g.file_end) {
        const long got = read_retrying(fd, g.in.data(), g.in.size());
        if (got <= 0) {
            break;
        }
        garbage = nonzero(g.in.data(), static_cast<std::size_t>(got));
    }
    g.file_end = true;
    if (garbage) {
        error = fmt::format("gzip: the bytes after the last member ({} uncompressed bytes) are no "
                            "gzip member and were not read",
                            g.inflated);
        return -1;
    }
    return 0;
}

} // namespace codrive::dump
