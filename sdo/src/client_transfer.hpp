// SPDX-License-Identifier: Apache-2.0
// State of one client transfer (private to the client).
#pragma once

#include "block_receiver.hpp"
#include "block_sender.hpp"

#include <codrive/sdo/client.hpp>
#include <codrive/sdo/client_machine.hpp>
#include <codrive/sdo/protocol.hpp>

namespace codrive::sdo::detail {

enum class ClientState : std::uint8_t {
    Queued,
    InitiateUpload,
    UploadSegment,
    InitiateDownload,
    DownloadSegment,
    BlockDownloadInitiate,
    BlockDownloadAck,
    BlockDownloadEnd,
    BlockUploadInitiate,
    BlockUploadData,
    BlockUploadEnd,
};

/// One queued or running transfer. Its data side (ISdoData) is the caller's sink, the in-memory
/// buffer or the download source; `machine` runs expedited and segmented transfers (a block
/// upload the server switched to segmented continues there too).
struct ClientTransfer final : ISdoData {
    bool begin(std::optional<std::size_t> size) override;
    bool write(std::span<const std::uint8_t> data) override;
    bool read(std::span<std::uint8_t> out) override;

    TransferId id = 0;
    Direction direction = Direction::Upload;
    std::uint16_t index = 0;
    std::uint8_t subindex = 0;
    TransferOptions options;
    Duration timeout{0};
    int retries_left = 0;

    UploadCallback on_upload; ///< in-memory upload
    DoneCallback on_done;     ///< everything else
    UploadSink sink;          ///< empty `write`: collect into `buffer`
    Bytes buffer;
    DownloadSource source;

    ClientState state = ClientState::Queued;
    SdoClientMachine machine;
    Protocol protocol = Protocol::Unknown;
    bool crc = false;
    std::uint8_t block_size = kMaxBlockSize;
    std::size_t done = 0;
    std::optional<std::size_t> total;
    /// Last frame sent or received: the response timeout runs from here.
    TimePoint activity = kNever;
    /// Last block segment of a sub-block not yet acknowledged (kNever: none pending).
    TimePoint gap_activity = kNever;
    /// Block upload: the start or sub-block response sent last, and when, while nothing of the
    /// sub-block it asks for has arrived (kNever: not waiting). Repeated after the gap timeout:
    /// a lost one would otherwise stall both sides until the timeout.
    Payload flow_frame{};
    TimePoint flow_sent = kNever;
    Payload initiate{};
    /// Last response accepted in this transfer: a byte-identical frame is a repeat (a CAN
    /// controller repeats a frame after an ACK error; a fault injector duplicates it).
    Payload last_response{};
    bool have_last_response = false;
    BlockSender sender;
    BlockReceiver receiver;
};

} // namespace codrive::sdo::detail
