// SPDX-License-Identifier: Apache-2.0
// SDO frame encoders and the frame parser (CiA 301 §7.2.4.3.3..16).
#include <codrive/core/endian.hpp>
#include <codrive/core/sdo_abort.hpp>
#include <codrive/sdo/protocol.hpp>

#include <algorithm>
#include <fmt/format.h>

namespace codrive::sdo {
namespace {

constexpr std::uint8_t cs_byte(std::uint8_t command, unsigned low_bits) {
    return static_cast<std::uint8_t>((command << 5) | (low_bits & 0x1FU));
}
constexpr std::uint8_t ccs(ClientCommand c) {
    return static_cast<std::uint8_t>(c);
}
constexpr std::uint8_t scs(ServerCommand c) {
    return static_cast<std::uint8_t>(c);
}

void read_multiplexer(const Payload& p, FrameInfo& info) {
    info.index = get_le<std::uint16_t>(p.data() + 1);
    info.subindex = p[3];
}

void read_segment_bits(const Payload& p, FrameInfo& info) {
    info.toggle = (p[0] & 0x10) != 0;
    info.unused = static_cast<std::uint8_t>((p[0] >> 1) & 0x07);
    info.last = (p[0] & 0x01) != 0;
    info.data_len = static_cast<std::uint8_t>(kSegmentData - info.unused);
    std::copy(p.begin() + 1, p.end(), info.data.begin());
}

// Initiate frames with e/s/n bits (§7.2.4.3.3 and §7.2.4.3.6 share this layout).
void read_initiate(const Payload& p, FrameInfo& info) {
    read_multiplexer(p, info);
    info.unused = static_cast<std::uint8_t>((p[0] >> 2) & 0x03);
    info.expedited = (p[0] & 0x02) != 0;
    info.size_indicated = (p[0] & 0x01) != 0;
    if (info.expedited) {
        info.data_len = static_cast<std::uint8_t>(info.size_indicated ? kExpeditedMax - info.unused
                                                                      : kExpeditedMax);
        std::copy(p.begin() + 4, p.end(), info.data.begin());
    } else if (info.size_indicated) {
        info.size = get_le<std::uint32_t>(p.data() + 4);
    }
}

void read_block_segment(const Payload& p, FrameInfo& info) {
    info.kind = FrameKind::BlockSegment;
    info.seqno = static_cast<std::uint8_t>(p[0] & kSeqnoMask);
    info.last = (p[0] & kLastSegmentBit) != 0;
    info.data_len = kSegmentData;
    std::copy(p.begin() + 1, p.end(), info.data.begin());
}

void parse_request(const Payload& p, FrameInfo& info) {
    switch (static_cast<ClientCommand>(command_bits(p[0]))) {
    case ClientCommand::DownloadSegment:
        info.kind = FrameKind::DownloadSegmentRequest;
        read_segment_bits(p, info);
        break;
    case ClientCommand::InitiateDownload:
        info.kind = FrameKind::InitiateDownloadRequest;
        read_initiate(p, info);
        break;
    case ClientCommand::InitiateUpload:
        info.kind = FrameKind::InitiateUploadRequest;
        read_multiplexer(p, info);
        break;
    case ClientCommand::UploadSegment:
        info.kind = FrameKind::UploadSegmentRequest;
        info.toggle = (p[0] & 0x10) != 0;
        break;
    case ClientCommand::Abort:
        break; // handled by the caller
    case ClientCommand::BlockUpload:
        switch (static_cast<BlockUploadClientSub>(p[0] & 0x03)) {
        case BlockUploadClientSub::Initiate:
            info.kind = FrameKind::BlockUploadInitiateRequest;
            read_multiplexer(p, info);
            info.crc = (p[0] & 0x04) != 0;
            info.block_size = p[4];
            info.pst = p[5];
            break;
        case BlockUploadClientSub::End:
            info.kind = FrameKind::BlockUploadEndResponse;
            break;
        case BlockUploadClientSub::Ack:
            info.kind = FrameKind::BlockUploadAck;
            info.seqno = p[1];
            info.block_size = p[2];
            break;
        case BlockUploadClientSub::Start:
            info.kind = FrameKind::BlockUploadStart;
            break;
        }
        break;
    case ClientCommand::BlockDownload:
        if ((p[0] & 0x01) == 0) {
            info.kind = FrameKind::BlockDownloadInitiateRequest;
            read_multiplexer(p, info);
            info.crc = (p[0] & 0x04) != 0;
            info.size_indicated = (p[0] & 0x02) != 0;
            info.size = get_le<std::uint32_t>(p.data() + 4);
        } else {
            info.kind = FrameKind::BlockDownloadEndRequest;
            info.unused = static_cast<std::uint8_t>((p[0] >> 2) & 0x07);
            info.crc_value = get_le<std::uint16_t>(p.data() + 1);
        }
        break;
    default:
        break;
    }
}

void parse_response(const Payload& p, FrameInfo& info) {
    switch (static_cast<ServerCommand>(command_bits(p[0]))) {
    case ServerCommand::UploadSegment:
        info.kind = FrameKind::UploadSegmentResponse;
        read_segment_bits(p, info);
        break;
    case ServerCommand::DownloadSegment:
        info.kind = FrameKind::DownloadSegmentResponse;
        info.toggle = (p[0] & 0x10) != 0;
        break;
    case ServerCommand::InitiateUpload:
        info.kind = FrameKind::InitiateUploadResponse;
        read_initiate(p, info);
        break;
    case ServerCommand::InitiateDownload:
        info.kind = FrameKind::InitiateDownloadResponse;
        read_multiplexer(p, info);
        break;
    case ServerCommand::Abort:
        break;
    case ServerCommand::BlockDownload:
        switch (p[0] & 0x03) {
        case static_cast<unsigned>(BlockDownloadServerSub::Initiate):
            info.kind = FrameKind::BlockDownloadInitiateResponse;
            read_multiplexer(p, info);
            info.crc = (p[0] & 0x04) != 0;
            info.block_size = p[4];
            break;
        case static_cast<unsigned>(BlockDownloadServerSub::End):
            info.kind = FrameKind::BlockDownloadEndResponse;
            break;
        case static_cast<unsigned>(BlockDownloadServerSub::Ack):
            info.kind = FrameKind::BlockDownloadAck;
            info.seqno = p[1];
            info.block_size = p[2];
            break;
        default:
            break;
        }
        break;
    case ServerCommand::BlockUpload:
        if ((p[0] & 0x01) == 0) {
            info.kind = FrameKind::BlockUploadInitiateResponse;
            read_multiplexer(p, info);
            info.crc = (p[0] & 0x04) != 0;
            info.size_indicated = (p[0] & 0x02) != 0;
            info.size = get_le<std::uint32_t>(p.data() + 4);
        } else {
            info.kind = FrameKind::BlockUploadEndRequest;
            info.unused = static_cast<std::uint8_t>((p[0] >> 2) & 0x07);
            info.crc_value = get_le<std::uint16_t>(p.data() + 1);
        }
        break;
    default:
        break;
    }
}

} // namespace

FrameInfo parse_frame(std::span<const std::uint8_t> payload, Sender sender, bool in_block) {
    FrameInfo info;
    if (payload.empty()) {
        return info;
    }
    // Short frames are padded with zeros: some devices send fewer than 8 bytes for frames whose
    // tail is reserved, and the parser must never read past the payload.
    Payload p{};
    std::copy_n(payload.begin(), std::min(payload.size(), p.size()), p.begin());
    // Inside a sub-block byte 0 is c+seqno. Seqno 0 is invalid, so 0x80 (c=1, seqno 0) can only
    // be an abort (ccs/scs 4 with no further bits).
    if (in_block && p[0] != 0x80) {
        read_block_segment(p, info);
        return info;
    }
    if (command_bits(p[0]) == ccs(ClientCommand::Abort)) {
        info.kind = FrameKind::Abort;
        read_multiplexer(p, info);
        info.abort_code = get_le<std::uint32_t>(p.data() + 4);
        return info;
    }
    if (sender == Sender::Client) {
        parse_request(p, info);
    } else {
        parse_response(p, info);
    }
    return info;
}

bool is_initiate_response(FrameKind kind) {
    return kind == FrameKind::InitiateUploadResponse ||
           kind == FrameKind::InitiateDownloadResponse ||
           kind == FrameKind::BlockDownloadInitiateResponse ||
           kind == FrameKind::BlockUploadInitiateResponse;
}

std::string_view to_string(FrameKind kind) {
    switch (kind) {
    case FrameKind::Invalid:
        return "invalid SDO frame";
    case FrameKind::Abort:
        return "abort";
    case FrameKind::InitiateDownloadRequest:
        return "initiate download request";
    case FrameKind::InitiateDownloadResponse:
        return "initiate download response";
    case FrameKind::DownloadSegmentRequest:
        return "download segment request";
    case FrameKind::DownloadSegmentResponse:
        return "download segment response";
    case FrameKind::InitiateUploadRequest:
        return "initiate upload request";
    case FrameKind::InitiateUploadResponse:
        return "initiate upload response";
    case FrameKind::UploadSegmentRequest:
        return "upload segment request";
    case FrameKind::UploadSegmentResponse:
        return "upload segment response";
    case FrameKind::BlockDownloadInitiateRequest:
        return "block download initiate request";
    case FrameKind::BlockDownloadInitiateResponse:
        return "block download initiate response";
    case FrameKind::BlockDownloadAck:
        return "block download sub-block response";
    case FrameKind::BlockDownloadEndRequest:
        return "block download end request";
    case FrameKind::BlockDownloadEndResponse:
        return "block download end response";
    case FrameKind::BlockUploadInitiateRequest:
        return "block upload initiate request";
    case FrameKind::BlockUploadInitiateResponse:
        return "block upload initiate response";
    case FrameKind::BlockUploadStart:
        return "block upload start";
    case FrameKind::BlockUploadAck:
        return "block upload sub-block response";
    case FrameKind::BlockUploadEndRequest:
        return "block upload end request";
    case FrameKind::BlockUploadEndResponse:
        return "block upload end response";
    case FrameKind::BlockSegment:
        return "block segment";
    }
    return "invalid SDO frame";
}

std::string describe(const FrameInfo& info) {
    const auto mux = fmt::format("0x{:04X}:{:02X}", info.index, info.subindex);
    const auto name = to_string(info.kind);
    const std::span<const std::uint8_t> data(info.data.data(), info.data_len);
    switch (info.kind) {
    case FrameKind::Abort:
        return fmt::format("{} {} 0x{:08X} {}", name, mux, info.abort_code,
                           sdo_abort_describe(info.abort_code));
    case FrameKind::InitiateDownloadRequest:
    case FrameKind::InitiateUploadResponse:
        if (info.expedited) {
            return fmt::format("{} {} expedited {} bytes [{:02X}]", name, mux, info.data_len,
                               fmt::join(data, " "));
        }
        if (info.size_indicated) {
            return fmt::format("{} {} segmented size {}", name, mux, info.size);
        }
        return fmt::format("{} {} segmented size not indicated", name, mux);
    case FrameKind::InitiateDownloadResponse:
    case FrameKind::InitiateUploadRequest:
        return fmt::format("{} {}", name, mux);
    case FrameKind::DownloadSegmentRequest:
    case FrameKind::UploadSegmentResponse:
        return fmt::format("{} t={} c={} {} bytes [{:02X}]", name, info.toggle ? 1 : 0,
                           info.last ? 1 : 0, info.data_len, fmt::join(data, " "));
    case FrameKind::DownloadSegmentResponse:
    case FrameKind::UploadSegmentRequest:
        return fmt::format("{} t={}", name, info.toggle ? 1 : 0);
    case FrameKind::BlockDownloadInitiateRequest:
    case FrameKind::BlockUploadInitiateResponse:
        return fmt::format("{} {} crc={} size {}", name, mux, info.crc ? 1 : 0,
                           info.size_indicated ? fmt::format("{}", info.size)
                                               : std::string("not indicated"));
    case FrameKind::BlockDownloadInitiateResponse:
        return fmt::format("{} {} crc={} blksize {}", name, mux, info.crc ? 1 : 0, info.block_size);
    case FrameKind::BlockUploadInitiateRequest:
        return fmt::format("{} {} crc={} blksize {} pst {}", name, mux, info.crc ? 1 : 0,
                           info.block_size, info.pst);
    case FrameKind::BlockDownloadAck:
    case FrameKind::BlockUploadAck:
        return fmt::format("{} ackseq {} blksize {}", name, info.seqno, info.block_size);
    case FrameKind::BlockDownloadEndRequest:
    case FrameKind::BlockUploadEndRequest:
        return fmt::format("{} n={} crc 0x{:04X}", name, info.unused, info.crc_value);
    case FrameKind::BlockSegment:
        return fmt::format("{} seqno {}{} [{:02X}]", name, info.seqno, info.last ? " last" : "",
                           fmt::join(data, " "));
    default:
        return std::string(name);
    }
}

void put_multiplexer(Payload& p, std::uint16_t index, std::uint8_t subindex) {
    put_le<std::uint16_t>(p.data() + 1, index);
    p[3] = subindex;
}

Payload make_abort(std::uint16_t index, std::uint8_t subindex, std::uint32_t code) {
    Payload p{};
    p[0] = cs_byte(ccs(ClientCommand::Abort), 0);
    put_multiplexer(p, index, subindex);
    put_le<std::uint32_t>(p.data() + 4, code);
    return p;
}

namespace {
Payload make_expedited(std::uint8_t command, std::uint16_t index, std::uint8_t subindex,
                       std::span<const std::uint8_t> data) {
    Payload p{};
    const auto len = std::min(data.size(), kExpeditedMax);
    const auto n = static_cast<unsigned>(kExpeditedMax - len);
    p[0] = cs_byte(command, (n << 2) | 0x03U);
    put_multiplexer(p, index, subindex);
    std::copy_n(data.begin(), len, p.begin() + 4);
    return p;
}
Payload make_sized(std::uint8_t command, std::uint16_t index, std::uint8_t subindex,
                   std::uint32_t size) {
    Payload p{};
    p[0] = cs_byte(command, 0x01);
    put_multiplexer(p, index, subindex);
    put_le<std::uint32_t>(p.data() + 4, size);
    return p;
}
Payload make_segment(std::uint8_t command, bool toggle, bool last,
                     std::span<const std::uint8_t> data) {
    Payload p{};
    const auto len = std::min(data.size(), kSegmentData);
    const auto n = static_cast<unsigned>(kSegmentData - len);
    p[0] = cs_byte(command, (toggle ? 0x10U : 0U) | (n << 1) | (last ? 1U : 0U));
    std::copy_n(data.begin(), len, p.begin() + 1);
    return p;
}
Payload make_toggle_only(std::uint8_t command, bool toggle) {
    Payload p{};
    p[0] = cs_byte(command, toggle ? 0x10U : 0U);
    return p;
}
} // namespace

Payload make_initiate_download_expedited(std::uint16_t index, std::uint8_t subindex,
                                         std::span<const std::uint8_t> data) {
    return make_expedited(ccs(ClientCommand::InitiateDownload), index, subindex, data);
}
Payload make_initiate_download_segmented(std::uint16_t index, std::uint8_t subindex,
                                         std::uint32_t size) {
    return make_sized(ccs(ClientCommand::InitiateDownload), index, subindex, size);
}
Payload make_initiate_download_response(std::uint16_t index, std::uint8_t subindex) {
    Payload p{};
    p[0] = cs_byte(scs(ServerCommand::InitiateDownload), 0);
    put_multiplexer(p, index, subindex);
    return p;
}
Payload make_download_segment(bool toggle, bool last, std::span<const std::uint8_t> data) {
    return make_segment(ccs(ClientCommand::DownloadSegment), toggle, last, data);
}
Payload make_download_segment_response(bool toggle) {
    return make_toggle_only(scs(ServerCommand::DownloadSegment), toggle);
}
Payload make_initiate_upload(std::uint16_t index, std::uint8_t subindex) {
    Payload p{};
    p[0] = cs_byte(ccs(ClientCommand::InitiateUpload), 0);
    put_multiplexer(p, index, subindex);
    return p;
}
Payload make_initiate_upload_expedited(std::uint16_t index, std::uint8_t subindex,
                                       std::span<const std::uint8_t> data) {
    return make_expedited(scs(ServerCommand::InitiateUpload), index, subindex, data);
}
Payload make_initiate_upload_segmented(std::uint16_t index, std::uint8_t subindex,
                                       std::uint32_t size) {
    return make_sized(scs(ServerCommand::InitiateUpload), index, subindex, size);
}
Payload make_upload_segment_request(bool toggle) {
    return make_toggle_only(ccs(ClientCommand::UploadSegment), toggle);
}
Payload make_upload_segment(bool toggle, bool last, std::span<const std::uint8_t> data) {
    return make_segment(scs(ServerCommand::UploadSegment), toggle, last, data);
}

Payload make_block_download_initiate(std::uint16_t index, std::uint8_t subindex, bool crc,
                                     std::uint32_t size) {
    Payload p{};
    p[0] = cs_byte(ccs(ClientCommand::BlockDownload), (crc ? 0x04U : 0U) | 0x02U);
    put_multiplexer(p, index, subindex);
    put_le<std::uint32_t>(p.data() + 4, size);
    return p;
}
Payload make_block_download_initiate_response(std::uint16_t index, std::uint8_t subindex, bool crc,
                                              std::uint8_t block_size) {
    Payload p{};
    p[0] = cs_byte(scs(ServerCommand::BlockDownload), crc ? 0x04U : 0U);
    put_multiplexer(p, index, subindex);
    p[4] = block_size;
    return p;
}
Payload make_block_segment(std::uint8_t seqno, bool last, std::span<const std::uint8_t> data) {
    Payload p{};
    p[0] = static_cast<std::uint8_t>((seqno & kSeqnoMask) | (last ? kLastSegmentBit : 0U));
    std::copy_n(data.begin(), std::min(data.size(), kSegmentData), p.begin() + 1);
    return p;
}
Payload make_block_download_ack(std::uint8_t ackseq, std::uint8_t block_size) {
    Payload p{};
    p[0] = cs_byte(scs(ServerCommand::BlockDownload),
                   static_cast<unsigned>(BlockDownloadServerSub::Ack));
    p[1] = ackseq;
    p[2] = block_size;
    return p;
}
Payload make_block_download_end(std::uint8_t unused, std::uint16_t crc) {
    Payload p{};
    p[0] = cs_byte(ccs(ClientCommand::BlockDownload), ((unused & 0x07U) << 2) | 0x01U);
    put_le<std::uint16_t>(p.data() + 1, crc);
    return p;
}
Payload make_block_download_end_response() {
    Payload p{};
    p[0] = cs_byte(scs(ServerCommand::BlockDownload),
                   static_cast<unsigned>(BlockDownloadServerSub::End));
    return p;
}
Payload make_block_upload_initiate(std::uint16_t index, std::uint8_t subindex, bool crc,
                                   std::uint8_t block_size, std::uint8_t pst) {
    Payload p{};
    p[0] = cs_byte(ccs(ClientCommand::BlockUpload), crc ? 0x04U : 0U);
    put_multiplexer(p, index, subindex);
    p[4] = block_size;
    p[5] = pst;
    return p;
}
Payload make_block_upload_initiate_response(std::uint16_t index, std::uint8_t subindex, bool crc,
                                            std::uint32_t size) {
    Payload p{};
    p[0] = cs_byte(scs(ServerCommand::BlockUpload), (crc ? 0x04U : 0U) | 0x02U);
    put_multiplexer(p, index, subindex);
    put_le<std::uint32_t>(p.data() + 4, size);
    return p;
}
Payload make_block_upload_start() {
    Payload p{};
    p[0] = cs_byte(ccs(ClientCommand::BlockUpload),
                   static_cast<unsigned>(BlockUploadClientSub::Start));
    return p;
}
Payload make_block_upload_ack(std::uint8_t ackseq, std::uint8_t block_size) {
    Payload p{};
    p[0] =
        cs_byte(ccs(ClientCommand::BlockUpload), static_cast<unsigned>(BlockUploadClientSub::Ack));
    p[1] = ackseq;
    p[2] = block_size;
    return p;
}
Payload make_block_upload_end(std::uint8_t unused, std::uint16_t crc) {
    Payload p{};
    p[0] = cs_byte(scs(ServerCommand::BlockUpload), ((unused & 0x07U) << 2) | 0x01U);
    put_le<std::uint16_t>(p.data() + 1, crc);
    return p;
}
Payload make_block_upload_end_response() {
    Payload p{};
    p[0] =
        cs_byte(ccs(ClientCommand::BlockUpload), static_cast<unsigned>(BlockUploadClientSub::End));
    return p;
}

} // namespace codrive::sdo
