// SPDX-License-Identifier: Apache-2.0
// SDO frame layout (CiA 301 §7.2.4.3): command specifiers, field encoders and a frame parser.
#pragma once

#include <array>
#include <cstdint>
#include <span>
#include <string>
#include <string_view>

namespace codrive::sdo {

/// Client command specifier (ccs, bits 7..5 of byte 0 of a request), CiA 301 §7.2.4.3.
enum class ClientCommand : std::uint8_t {
    DownloadSegment = 0,
    InitiateDownload = 1,
    InitiateUpload = 2,
    UploadSegment = 3,
    Abort = 4,
    BlockUpload = 5,
    BlockDownload = 6,
};

/// Server command specifier (scs, bits 7..5 of byte 0 of a response).
enum class ServerCommand : std::uint8_t {
    UploadSegment = 0,
    DownloadSegment = 1,
    InitiateUpload = 2,
    InitiateDownload = 3,
    Abort = 4,
    BlockDownload = 5,
    BlockUpload = 6,
};

/// Sub-commands of block download requests (client cs, bit 0) and block upload requests
/// (client cs, bits 1..0), CiA 301 §7.2.4.3.9..16.
enum class BlockDownloadClientSub : std::uint8_t { Initiate = 0, End = 1 };
enum class BlockDownloadServerSub : std::uint8_t { Initiate = 0, End = 1, Ack = 2 };
enum class BlockUploadClientSub : std::uint8_t { Initiate = 0, End = 1, Ack = 2, Start = 3 };
enum class BlockUploadServerSub : std::uint8_t { Initiate = 0, End = 1 };

/// Layout constants.
inline constexpr std::size_t kFrameLen = 8;           ///< every SDO frame carries 8 bytes
inline constexpr std::size_t kExpeditedMax = 4;       ///< data bytes in an expedited frame
inline constexpr std::size_t kSegmentData = 7;        ///< data bytes in a segment / block segment
inline constexpr std::uint8_t kMaxBlockSize = 127;    ///< segments per sub-block (§7.2.4.3.9)
inline constexpr std::uint8_t kLastSegmentBit = 0x80; ///< `c` bit of a block segment
inline constexpr std::uint8_t kSeqnoMask = 0x7F;
/// Command byte bit 4 of a CoE initiate request: complete access (ETG.1000.6 §5.6.2.1.1; on
/// CAN the bit is reserved).
inline constexpr std::uint8_t kCompleteAccessBit = 0x10;

[[nodiscard]] constexpr std::uint8_t command_bits(std::uint8_t byte0) {
    return static_cast<std::uint8_t>(byte0 >> 5);
}

/// Who sent a frame: the client (request COB-ID, 600h+n by default) or the server (580h+n).
enum class Sender : std::uint8_t { Client, Server };

/// What one SDO frame is.
enum class FrameKind : std::uint8_t {
    Invalid, ///< too short or reserved command specifier
    Abort,   ///< either direction
    InitiateDownloadRequest,
    InitiateDownloadResponse,
    DownloadSegmentRequest,
    DownloadSegmentResponse,
    InitiateUploadRequest,
    InitiateUploadResponse,
    UploadSegmentRequest,
    UploadSegmentResponse,
    BlockDownloadInitiateRequest,
    BlockDownloadInitiateResponse,
    BlockDownloadAck, ///< server confirms a sub-block
    BlockDownloadEndRequest,
    BlockDownloadEndResponse,
    BlockUploadInitiateRequest,
    BlockUploadInitiateResponse,
    BlockUploadStart,
    BlockUploadAck,         ///< client confirms a sub-block
    BlockUploadEndRequest,  ///< server's end frame carrying n and the CRC
    BlockUploadEndResponse, ///< client's confirmation of the end frame
    BlockSegment,           ///< c + seqno + 7 data bytes (only when `in_block` was given)
};

/// The fields of one SDO frame. Only the fields the kind defines are set.
struct FrameInfo {
    FrameKind kind = FrameKind::Invalid;
    std::uint16_t index = 0;
    std::uint8_t subindex = 0;
    bool expedited = false;       ///< initiate: e bit
    bool size_indicated = false;  ///< initiate: s bit
    std::uint32_t size = 0;       ///< initiate with s and !e: size in bytes
    bool toggle = false;          ///< segments: t bit
    bool last = false;            ///< segments: c bit (no more segments)
    std::uint8_t unused = 0;      ///< n: bytes at the end not carrying data
    std::uint8_t seqno = 0;       ///< block segment sequence number, or ackseq in acks
    std::uint8_t block_size = 0;  ///< blksize in block initiate / ack frames
    std::uint8_t pst = 0;         ///< protocol switch threshold in a block upload request
    bool crc = false;             ///< block initiate: cc / sc (CRC supported)
    std::uint16_t crc_value = 0;  ///< block end request: CRC
    std::uint32_t abort_code = 0; ///< abort frames
    std::array<std::uint8_t, kSegmentData> data{}; ///< expedited / segment / block data bytes
    std::uint8_t data_len = 0; ///< data bytes that carry data (expedited with s, segments)
};

/// Parses the 8 bytes of an SDO frame. `in_block` tells the parser that the sender is inside a
/// block sub-block, where byte 0 is c+seqno rather than a command specifier (a frame decoder
/// tracks that state; the client and server know it). Never fails: unknown frames are Invalid.
[[nodiscard]] FrameInfo parse_frame(std::span<const std::uint8_t> payload, Sender sender,
                                    bool in_block = false);

/// One-line description of a parsed frame: "initiate upload request 0x1018:01",
/// "upload segment response t=1 c=0 7 bytes", "abort 0x1000:00 0x06020000 object does not exist
/// in the object dictionary".
[[nodiscard]] std::string describe(const FrameInfo& info);
[[nodiscard]] std::string_view to_string(FrameKind kind);
/// An initiate response of any protocol: it names its object and only ever answers an initiate
/// request (CiA 301 §7.2.4.3).
[[nodiscard]] bool is_initiate_response(FrameKind kind);

/// Frame builders: each fills an 8-byte SDO payload.
using Payload = std::array<std::uint8_t, kFrameLen>;

void put_multiplexer(Payload& p, std::uint16_t index, std::uint8_t subindex);
[[nodiscard]] Payload make_abort(std::uint16_t index, std::uint8_t subindex, std::uint32_t code);

[[nodiscard]] Payload make_initiate_download_expedited(std::uint16_t index, std::uint8_t subindex,
                                                       std::span<const std::uint8_t> data);
[[nodiscard]] Payload make_initiate_download_segmented(std::uint16_t index, std::uint8_t subindex,
                                                       std::uint32_t size);
[[nodiscard]] Payload make_initiate_download_response(std::uint16_t index, std::uint8_t subindex);
[[nodiscard]] Payload make_download_segment(bool toggle, bool last,
                                            std::span<const std::uint8_t> data);
[[nodiscard]] Payload make_download_segment_response(bool toggle);

[[nodiscard]] Payload make_initiate_upload(std::uint16_t index, std::uint8_t subindex);
[[nodiscard]] Payload make_initiate_upload_expedited(std::uint16_t index, std::uint8_t subindex,
                                                     std::span<const std::uint8_t> data);
[[nodiscard]] Payload make_initiate_upload_segmented(std::uint16_t index, std::uint8_t subindex,
                                                     std::uint32_t size);
[[nodiscard]] Payload make_upload_segment_request(bool toggle);
[[nodiscard]] Payload make_upload_segment(bool toggle, bool last,
                                          std::span<const std::uint8_t> data);

[[nodiscard]] Payload make_block_download_initiate(std::uint16_t index, std::uint8_t subindex,
                                                   bool crc, std::uint32_t size);
[[nodiscard]] Payload make_block_download_initiate_response(std::uint16_t index,
                                                            std::uint8_t subindex, bool crc,
                                                            std::uint8_t block_size);
[[nodiscard]] Payload make_block_segment(std::uint8_t seqno, bool last,
                                         std::span<const std::uint8_t> data);
[[nodiscard]] Payload make_block_download_ack(std::uint8_t ackseq, std::uint8_t block_size);
[[nodiscard]] Payload make_block_download_end(std::uint8_t unused, std::uint16_t crc);
[[nodiscard]] Payload make_block_download_end_response();

[[nodiscard]] Payload make_block_upload_initiate(std::uint16_t index, std::uint8_t subindex,
                                                 bool crc, std::uint8_t block_size,
                                                 std::uint8_t pst);
[[nodiscard]] Payload make_block_upload_initiate_response(std::uint16_t index,
                                                          std::uint8_t subindex, bool crc,
                                                          std::uint32_t size);
[[nodiscard]] Payload make_block_upload_start();
[[nodiscard]] Payload make_block_upload_ack(std::uint8_t ackseq, std::uint8_t block_size);
[[nodiscard]] Payload make_block_upload_end(std::uint8_t unused, std::uint16_t crc);
[[nodiscard]] Payload make_block_upload_end_response();

} // namespace codrive::sdo
