// SPDX-License-Identifier: Apache-2.0
// Gzip inflation (RFC 1952) of a file read in pieces: what makes compressed traces readable.
#pragma once

#include <cstddef>
#include <cstdint>
#include <memory>
#include <string>
#include <string_view>

namespace codrive::dump {

/// Deflate's largest compression ratio (zlib's technical details: 1032:1): a gzip input of n
/// bytes inflates to at most n times this.
inline constexpr std::size_t kMaxInflateRatio = 1032;

/// The most bytes other_compression() looks at (xz's magic number).
inline constexpr std::size_t kCompressionMagicBytes = 6;

/// The compressor of a file that starts with the magic bytes of one codrive-dump does not
/// inflate ("xz", "bzip2", "zstd", "lz4", "zip"), or empty.
[[nodiscard]] std::string_view other_compression(const std::uint8_t* p, std::size_t n);

/// Inflates a gzip file: one member or several one after another (RFC 1952 §2.2, as
/// `cat a.gz b.gz` makes); zero padding after the last member is ignored, other bytes there are
/// an error after everything before them. Compressed bytes come from a file descriptor in reads of
/// 64 KiB, or of the size of the first bytes given to start() when they are more (at most the
/// BufferedInput's capacity).
class Gunzip {
public:
    /// True if `p` starts with the gzip magic bytes 1F 8B (RFC 1952 §2.3.1).
    [[nodiscard]] static bool is_gzip(const std::uint8_t* p, std::size_t n);
    /// Starts inflating a file whose first bytes, already read, are `first`; `file_end`: the file
    /// has no more (then no descriptor is read). Null if zlib cannot start.
    static std::unique_ptr<Gunzip> start(std::string_view first, bool file_end);
    ~Gunzip();
    Gunzip(const Gunzip&) = delete;
    Gunzip& operator=(const Gunzip&) = delete;

    /// Up to `n` inflated bytes, reading `fd` for more compressed ones: > 0 bytes, 0 at the end,
    /// -1 on a read error, a corrupt stream or a file that ends inside a member (`error` says
    /// which and after how many uncompressed bytes). The bytes inflated before damage are
    /// returned first; the error comes with the next call.
    long read(int fd, std::uint8_t* dst, std::size_t n, std::string& error);

private:
    struct State;
    /// After the last member: 0 if only zero bytes follow, else -1 with `error` set.
    long trailing(int fd, std::string& error);
    explicit Gunzip(std::unique_ptr<State> state);
    std::unique_ptr<State> st_;
};

} // namespace codrive::dump
