// SPDX-License-Identifier: Apache-2.0
// Buffered byte input from a file or stdin: big reads, no per-line system calls.
#pragma once

#include <codrive/core/error.hpp>
#include <codrive/dump/gunzip.hpp>

#include <cstddef>
#include <cstdint>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

namespace codrive::dump {

/// One read(2) of up to `n` bytes, retried on EINTR: bytes read, 0 at the end, -1 on an error
/// (errno set).
long read_retrying(int fd, std::uint8_t* dst, std::size_t n);

/// Reads a file (or stdin for "-") in large chunks into one buffer; readers look at the unread
/// bytes and consume them. Memory is the buffer only (1 MiB by default), whatever the file size.
/// A gzip file (RFC 1952 magic 1F 8B, also several members one after another, as `cat a.gz b.gz`
/// makes) is inflated as it is read, so every trace format may come compressed.
class BufferedInput {
public:
    static constexpr std::size_t kDefaultCapacity = 1U << 20;
    /// Opens `path` ("-" is stdin). Errors: the std::errc of a failed open.
    static Result<std::unique_ptr<BufferedInput>> open(const std::string& path,
                                                       std::size_t capacity = kDefaultCapacity);
    /// Reads from bytes in memory (tests, fuzzing), inflated when they are gzip.
    static std::unique_ptr<BufferedInput> from_memory(std::string_view bytes);
    ~BufferedInput();
    BufferedInput(const BufferedInput&) = delete;
    BufferedInput& operator=(const BufferedInput&) = delete;

    /// Makes at least `n` unread bytes available unless the input ends first (or `n` exceeds the
    /// capacity). Returns the bytes available.
    std::size_t ensure(std::size_t n);
    [[nodiscard]] const std::uint8_t* data() const { return buf_.data() + pos_; }
    [[nodiscard]] std::size_t available() const { return end_ - pos_; }
    void consume(std::size_t n) { pos_ += n; }
    /// True once the underlying file reported end of file (buffered bytes may remain).
    [[nodiscard]] bool at_eof() const { return eof_; }
    [[nodiscard]] std::size_t capacity() const { return buf_.size(); }
    /// True when the file is gzip-compressed (the bytes above are the inflated ones).
    [[nodiscard]] bool gzipped() const { return gz_ != nullptr; }
    /// The most bytes `size` bytes of this input can deliver (more than `size` only for gzip).
    [[nodiscard]] std::size_t max_plain_bytes(std::size_t size) const {
        return gzipped() ? size * kMaxInflateRatio : size;
    }
    /// A read error (not end of file), if one happened; for gzip also a corrupt or cut stream.
    [[nodiscard]] const std::string& read_error() const { return read_error_; }

    /// The next line without its "\n" (and "\r"); false at end of input. A line longer than the
    /// buffer is returned cut, with `too_long` set, and the rest of it is skipped.
    bool next_line(std::string_view& line, bool& too_long);

private:
    BufferedInput();
    /// Up to `n` bytes of the file (inflated when gzipped): > 0 bytes, 0 at the end, < 0 on an
    /// error (read_error_ set).
    long read_some(std::uint8_t* dst, std::size_t n);
    /// Switches to inflating, `first` being the file's first compressed bytes. False if zlib
    /// cannot start.
    bool start_gunzip(std::string_view first, bool file_end);
    std::unique_ptr<Gunzip> gz_; ///< set when the file is gzip
    std::vector<std::uint8_t> buf_;
    std::size_t pos_ = 0;
    std::size_t end_ = 0;
    int fd_ = -1;
    bool own_fd_ = false;
    bool eof_ = false;
    bool skipping_ = false;
    std::string read_error_;
};

} // namespace codrive::dump
