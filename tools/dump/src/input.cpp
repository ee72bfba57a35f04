// SPDX-License-Identifier: Apache-2.0
// Buffered byte input from a file or stdin.
#include <codrive/dump/input.hpp>

#include <fmt/format.h>

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <fcntl.h>
#include <unistd.h>
#include <zlib.h>

namespace codrive::dump {
namespace {

constexpr std::size_t kCompressedChunk = 64U * 1024U;
constexpr std::uint8_t kGzipMagic0 = 0x1F; // RFC 1952 §2.3.1: ID1, ID2
constexpr std::uint8_t kGzipMagic1 = 0x8B;

// One read(2) of up to `n` bytes, retried on EINTR: bytes read, 0 at the end, -1 on an error.
long read_fd(int fd, std::uint8_t* dst, std::size_t n) {
    for (;;) {
        const ssize_t got = ::read(fd, dst, n);
        if (got >= 0 || errno != EINTR) {
            return static_cast<long>(got);
        }
    }
}

bool is_gzip(const std::uint8_t* p, std::size_t n) {
    return n >= 2 && p[0] == kGzipMagic0 && p[1] == kGzipMagic1;
}

} // namespace

struct BufferedInput::Gunzip {
    z_stream s{};
    bool ready = false;
    bool in_member = true; ///< inside a member: the file must not end here
    bool file_end = false;
    std::uint64_t inflated = 0;
    std::vector<std::uint8_t> in;
    Gunzip() {
        ready = inflateInit2(&s, 16 + MAX_WBITS) == Z_OK; // 16: a gzip wrapper, not zlib
    }
    ~Gunzip() {
        if (ready) {
            inflateEnd(&s);
        }
    }
    Gunzip(const Gunzip&) = delete;
    Gunzip& operator=(const Gunzip&) = delete;
};

BufferedInput::BufferedInput() = default;

Result<std::unique_ptr<BufferedInput>> BufferedInput::open(const std::string& path,
                                                           std::size_t capacity) {
    std::unique_ptr<BufferedInput> in(new BufferedInput());
    if (path == "-") {
        in->fd_ = 0;
    } else {
        in->fd_ = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
        if (in->fd_ < 0) {
            return fail_errno(errno);
        }
        in->own_fd_ = true;
#ifdef POSIX_FADV_SEQUENTIAL
        (void)::posix_fadvise(in->fd_, 0, 0, POSIX_FADV_SEQUENTIAL);
#endif
    }
    in->buf_.resize(capacity);
    // The first two bytes say whether the file is gzip; a pipe may deliver them one by one.
    while (in->end_ < 2 && !in->eof_) {
        const std::size_t room = std::min(in->buf_.size(), kCompressedChunk) - in->end_;
        const long got = read_fd(in->fd_, in->buf_.data() + in->end_, room);
        if (got < 0) {
            in->read_error_ = std::strerror(errno);
            in->eof_ = true;
        } else if (got == 0) {
            in->eof_ = true;
        } else {
            in->end_ += static_cast<std::size_t>(got);
        }
    }
    if (is_gzip(in->buf_.data(), in->end_)) {
        // All of the first read (at most 64 KiB) becomes the first compressed input.
        const std::string_view first(reinterpret_cast<const char*>(in->buf_.data()), in->end_);
        if (!in->start_gunzip(first, in->eof_)) {
            return fail(std::errc::not_enough_memory);
        }
    }
    return in;
}

std::unique_ptr<BufferedInput> BufferedInput::from_memory(std::string_view bytes) {
    std::unique_ptr<BufferedInput> in(new BufferedInput());
    if (is_gzip(reinterpret_cast<const std::uint8_t*>(bytes.data()), bytes.size())) {
        in->buf_.resize(1U << 20);
        if (in->start_gunzip(bytes, true)) {
            return in;
        }
        in->read_error_ = "gzip: zlib could not be initialised";
        in->eof_ = true;
        return in;
    }
    in->buf_.assign(bytes.begin(), bytes.end());
    in->end_ = bytes.size();
    in->eof_ = true;
    return in;
}

bool BufferedInput::start_gunzip(std::string_view first, bool file_end) {
    gz_ = std::make_unique<Gunzip>();
    if (!gz_->ready) {
        gz_.reset();
        return false;
    }
    gz_->in.assign(first.begin(), first.end());
    if (!file_end) {
        gz_->in.resize(std::max(gz_->in.size(), kCompressedChunk));
    }
    gz_->s.next_in = gz_->in.data();
    gz_->s.avail_in = static_cast<uInt>(first.size());
    gz_->file_end = file_end;
    end_ = 0;
    eof_ = false;
    return true;
}

BufferedInput::~BufferedInput() {
    if (own_fd_) {
        ::close(fd_);
    }
}

std::size_t BufferedInput::ensure(std::size_t n) {
    while (available() < n && !eof_) {
        if (pos_ > 0) {
            std::memmove(buf_.data(), buf_.data() + pos_, available());
            end_ -= pos_;
            pos_ = 0;
        }
        if (end_ == buf_.size()) {
            break; // full: n exceeds the capacity
        }
        const long got = read_some(buf_.data() + end_, buf_.size() - end_);
        if (got < 0) {
            eof_ = true;
        } else if (got == 0) {
            eof_ = true;
        } else {
            end_ += static_cast<std::size_t>(got);
        }
    }
    return available();
}

long BufferedInput::read_some(std::uint8_t* dst, std::size_t n) {
    if (gz_ != nullptr) {
        return inflate_some(dst, n);
    }
    const long got = read_fd(fd_, dst, n);
    if (got < 0) {
        read_error_ = std::strerror(errno);
    }
    return got;
}

long BufferedInput::inflate_some(std::uint8_t* dst, std::size_t n) {
    Gunzip& g = *gz_;
    const auto fail_with = [&](std::string why) {
        read_error_ = fmt::format("gzip: {} after {} uncompressed bytes", why, g.inflated);
        return -1L;
    };
    for (;;) {
        if (g.s.avail_in == 0 && !g.file_end) {
            const long got = read_fd(fd_, g.in.data(), g.in.size());
            if (got < 0) {
                read_error_ = std::strerror(errno);
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
            // RFC 1952 §2.2: a file is a series of members. Anything else after a member (zero
            // padding, say) is ignored, as gzip -d does.
            if (g.s.next_in[0] != kGzipMagic0) {
                return 0;
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
            return fail_with(
                fmt::format("bad compressed data ({})", g.s.msg != nullptr ? g.s.msg : zError(r)));
        }
        if (produced > 0) {
            return static_cast<long>(produced);
        }
    }
}

bool BufferedInput::next_line(std::string_view& line, bool& too_long) {
    too_long = false;
    std::size_t scanned = 0;
    for (;;) {
        const auto* start = buf_.data() + pos_;
        const auto* nl = available() > scanned ? static_cast<const std::uint8_t*>(std::memchr(
                                                     start + scanned, '\n', available() - scanned))
                                               : nullptr;
        if (nl != nullptr) {
            std::size_t len = static_cast<std::size_t>(nl - start);
            const bool was_skipping = skipping_;
            skipping_ = false;
            pos_ += len + 1;
            if (was_skipping) {
                scanned = 0;
                continue; // the tail of an over-long line already reported
            }
            if (len > 0 && start[len - 1] == '\r') {
                --len;
            }
            line = std::string_view(reinterpret_cast<const char*>(start), len);
            return true;
        }
        scanned = available();
        if (eof_) {
            if (available() == 0) {
                return false;
            }
            const bool was_skipping = skipping_;
            skipping_ = false;
            std::size_t len = available();
            pos_ = end_;
            if (was_skipping) {
                return false;
            }
            if (len > 0 && start[len - 1] == '\r') {
                --len;
            }
            line = std::string_view(reinterpret_cast<const char*>(start), len);
            return true;
        }
        if (pos_ == 0 && end_ == buf_.size()) {
            // No newline in a full buffer: report the cut line once, skip to the next newline.
            const bool was_skipping = skipping_;
            line = std::string_view(reinterpret_cast<const char*>(start), available());
            pos_ = end_;
            skipping_ = true;
            if (!was_skipping) {
                too_long = true;
                return true;
            }
            scanned = 0;
        }
        ensure(available() + 1);
        if (pos_ != 0) {
            scanned = 0;
        }
    }
}

} // namespace codrive::dump
