// SPDX-License-Identifier: Apache-2.0
// Receiving side of an SDO block transfer (client upload, server download), CiA 301 §7.2.4.3.9.
#pragma once

#include <codrive/sdo/protocol.hpp>

#include <array>
#include <cstdint>
#include <functional>
#include <span>

namespace codrive::sdo::detail {

/// Consumes data in order; returns false if the consumer failed.
using WriteFn = std::function<bool(std::span<const std::uint8_t>)>;

/// Accepts block segments in sequence, ignores a sub-block's segments after a gap (the sender
/// repeats them after our acknowledgement), and holds the last segment back until the end frame
/// says how many of its bytes are data.
class BlockReceiver {
public:
    enum class SegmentResult : std::uint8_t {
        Stored,          ///< accepted, more expected in this sub-block
        Skipped,         ///< out of sequence or repeated: not acknowledged
        Stale,           ///< a repeat, or left over from an early acknowledgement: ignore
        SubBlockDone,    ///< send the sub-block response now (ackseq())
        InvalidSequence, ///< seqno 0 or beyond the block size: abort 0x05040003
        WriteFailed,     ///< the consumer refused the data
    };

    void reset(std::uint8_t block_size);
    SegmentResult on_segment(const FrameInfo& segment, const WriteFn& write);
    /// Sequence number to acknowledge.
    [[nodiscard]] std::uint8_t ackseq() const { return static_cast<std::uint8_t>(expected_ - 1); }
    /// Sequence number of the segment accepted next.
    [[nodiscard]] unsigned next_seqno() const { return expected_; }
    /// After sending the acknowledgement: the next sub-block has `next_block_size` segments.
    /// `early`: the acknowledgement came from the gap timer, not from the sub-block's end.
    void start_sub_block(std::uint8_t next_block_size, bool early = false);
    /// The blksize for the next acknowledgement: `configured` and `configured - 1` in turn, so
    /// that two successive sub-block responses always differ and the sender can tell a repeated
    /// response (CAN repeats a frame after an ACK error) from a new one (BlockSender::on_ack).
    [[nodiscard]] std::uint8_t next_block_size(std::uint8_t configured);
    /// True once the segment with the c bit arrived in sequence: the end frame comes next.
    [[nodiscard]] bool complete() const { return complete_; }
    /// Applies the end frame: writes the data bytes of the last segment. False if n is invalid
    /// or the consumer failed.
    bool finish(std::uint8_t unused, const WriteFn& write);
    [[nodiscard]] std::uint16_t crc() const { return crc_; }
    [[nodiscard]] std::size_t received() const { return received_; }
    [[nodiscard]] std::uint8_t block_size() const { return block_size_; }

private:
    std::uint8_t block_size_ = kMaxBlockSize;
    std::uint8_t previous_block_size_ = kMaxBlockSize;
    unsigned expected_ = 1;
    bool gap_ = false;
    bool complete_ = false;
    bool stale_possible_ = false;
    bool shrink_next_ = false;
    /// The segment accepted last: an out-of-sequence copy of it is a repeat, not a gap.
    std::array<std::uint8_t, kSegmentData> accepted_data_{};
    std::uint8_t accepted_seqno_ = 0; ///< 0: none yet
    bool accepted_last_ = false;
    std::array<std::uint8_t, kSegmentData> last_{};
    std::uint16_t crc_ = 0;
    std::size_t received_ = 0;
};

} // namespace codrive::sdo::detail
