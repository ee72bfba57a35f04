// SPDX-License-Identifier: Apache-2.0
// What an SDO client transfer needs: options, streaming sinks and sources, results.
#pragma once

#include <codrive/core/time.hpp>
#include <codrive/sdo/error.hpp>

#include <cstdint>
#include <cstdio>
#include <functional>
#include <optional>
#include <span>
#include <string>
#include <tl/expected.hpp>
#include <vector>

namespace codrive::sdo {

using Bytes = std::vector<std::uint8_t>;

/// A transfer's outcome: the value, or an SdoError that explains the failure.
template <typename T>
using SdoResult = tl::expected<T, SdoError>;

/// Which protocol the client uses. Auto: expedited for downloads of 1..4 bytes, segmented
/// otherwise; for uploads the server chooses between expedited and segmented.
enum class Mode : std::uint8_t {
    Auto,
    Segmented, ///< never expedited on download (uploads: the server still chooses)
    Block,     ///< block transfer (CiA 301 §7.2.4.3.9..16)
};

/// Called with the bytes transferred so far and the total when known.
using ProgressFn = std::function<void(std::size_t done, std::optional<std::size_t> total)>;

struct TransferOptions {
    Mode mode = Mode::Auto;
    /// Time to wait for each response; the client's configured default if unset.
    std::optional<Duration> timeout;
    /// Repeats of an unanswered initiate request of an expedited-capable transfer (uploads
    /// outside block mode, expedited downloads); the client's default if unset.
    std::optional<int> retries;
    /// Block upload: sub-block size we ask for (1..127) and protocol switch threshold (bytes;
    /// the server may answer objects up to this size with an expedited/segmented upload, 0 =
    /// never switch).
    std::uint8_t block_size = 127;
    std::uint8_t pst = 0;
    /// Block transfers: offer CRC-16 (used if the server supports it too).
    bool crc = true;
    ProgressFn progress;
};

/// Streams uploaded data to the caller instead of collecting it in memory.
struct UploadSink {
    /// Called once before data with the size the server indicated (if any); false aborts the
    /// transfer (e.g. too large for the destination).
    std::function<bool(std::optional<std::size_t> size)> begin;
    /// Called with each piece of data in order; false aborts the transfer.
    std::function<bool(std::span<const std::uint8_t> data)> write;
};

/// Supplies download data piece by piece.
struct DownloadSource {
    std::size_t size = 0;
    /// Fills `out` completely with the next bytes; false aborts the transfer.
    std::function<bool(std::span<std::uint8_t> out)> read;
};

/// A sink that writes to an open stdio file (not closed by the sink).
[[nodiscard]] UploadSink file_sink(std::FILE* file);
/// A source reading a whole file, which is opened now. Errors: the system error of open/stat.
[[nodiscard]] Result<DownloadSource> file_source(const std::string& path);
/// A source over bytes the source keeps alive.
[[nodiscard]] DownloadSource bytes_source(Bytes data);

using UploadCallback = std::function<void(SdoResult<Bytes>)>;
using DoneCallback = std::function<void(SdoResult<void>)>;

/// Identifies a queued or running transfer for cancel().
using TransferId = std::uint64_t;

} // namespace codrive::sdo
