// SPDX-License-Identifier: Apache-2.0
// Sending side of an SDO block transfer (client download, server upload), CiA 301 §7.2.4.3.9.
#pragma once

#include <codrive/sdo/protocol.hpp>

#include <cstdint>
#include <functional>
#include <span>
#include <vector>

namespace codrive::sdo::detail {

/// Fills `out` completely with the next bytes of the object; false if the source failed.
using ReadFn = std::function<bool(std::span<std::uint8_t> out)>;

/// Holds the current sub-block so segments after the acknowledged sequence number can be sent
/// again, computes the CRC over the data as it is read, and knows when the last segment went.
/// The sub-block buffer (at most 127 * 7 bytes) is allocated once.
class BlockSender {
public:
    enum class AckResult : std::uint8_t {
        NextBlock,
        Done,
        Repeat, ///< a copy of the previous response (see on_ack): ignore it
        InvalidSequence,
        InvalidBlockSize
    };

    BlockSender();
    void reset(std::size_t total);
    /// Tops the sub-block buffer up to `block_size` segments of data; false if `read` failed.
    bool fill(std::uint8_t block_size, const ReadFn& read);
    /// Segments in the current sub-block (at least 1: a zero-byte object sends one empty segment).
    [[nodiscard]] std::uint8_t segments() const { return segments_; }
    /// Frame payload of segment `seqno` (1-based) of the current sub-block.
    [[nodiscard]] Payload segment(std::uint8_t seqno) const;
    /// Applies a sub-block response: drops the acknowledged segments (the rest go again).
    /// A response byte-identical to the previous one is a Repeat when the previous one changed
    /// the block size: a receiver that alternates blksize (BlockReceiver::next_block_size, as
    /// codrive's does) never sends two equal responses in a row. With a receiver that keeps
    /// blksize, equal responses are legitimate and are applied.
    AckResult on_ack(std::uint8_t ackseq, std::uint8_t block_size);
    /// n of the end frame: bytes of the last segment that carry no data.
    [[nodiscard]] std::uint8_t last_unused() const { return last_unused_; }
    [[nodiscard]] std::uint16_t crc() const { return crc_; }
    [[nodiscard]] std::size_t acknowledged() const { return acked_; }
    [[nodiscard]] std::uint64_t retransmitted() const { return retransmitted_; }

private:
    std::vector<std::uint8_t> buffer_; ///< unacknowledged bytes, from absolute offset acked_
    std::size_t buffered_ = 0;
    std::size_t total_ = 0;
    std::size_t acked_ = 0;
    std::size_t read_ = 0;
    std::uint8_t segments_ = 0;
    std::uint8_t block_size_ = 0; ///< blksize of the current sub-block (from fill())
    std::uint8_t last_ackseq_ = 0;
    std::uint8_t last_ack_block_size_ = 0; ///< 0: no response yet
    bool last_ack_resized_ = false;
    std::uint8_t last_unused_ = 0;
    std::uint16_t crc_ = 0;
    std::uint64_t retransmitted_ = 0;
};

} // namespace codrive::sdo::detail
