// SPDX-License-Identifier: Apache-2.0
// Buffered byte input from a file or stdin.
#include <codrive/dump/input.hpp>

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <fcntl.h>
#include <unistd.h>

namespace codrive::dump {

long read_retrying(int fd, std::uint8_t* dst, std::size_t n) {
    for (;;) {
        const ssize_t got = ::read(fd, dst, n);
        if (got >= 0 || errno != EINTR) {
            return static_cast<long>(got);
        }
    }
}

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
    in->ensure(std::min<std::size_t>(2, in->buf_.size()));
    if (Gunzip::is_gzip(in->buf_.data(), in->end_)) {
        // All that has been read becomes the first compressed input.
        const std::string_view first(reinterpret_cast<const char*>(in->buf_.data()), in->end_);
        if (!in->start_gunzip(first, in->eof_)) {
            return fail(std::errc::not_enough_memory);
        }
    }
    return in;
}

std::unique_ptr<BufferedInput> BufferedInput::from_memory(std::string_view bytes) {
    std::unique_ptr<BufferedInput> in(new BufferedInput());
    if (Gunzip::is_gzip(reinterpret_cast<const std::uint8_t*>(bytes.data()), bytes.size())) {
        in->buf_.resize(kDefaultCapacity);
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
    gz_ = Gunzip::start(first, file_end);
    if (gz_ == nullptr) {
        return false;
    }
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
        return gz_->read(fd_, dst, n, read_error_);
    }
    const long got = read_retrying(fd_, dst, n);
    if (got < 0) {
        read_error_ = std::strerror(errno);
    }
    return got;
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
