// SPDX-License-Identifier: Apache-2.0
// Sub-block bookkeeping for the sending side of SDO block transfers.
#include "block_sender.hpp"

#include <codrive/sdo/crc16.hpp>

#include <algorithm>
#include <cstring>

namespace codrive::sdo::detail {

BlockSender::BlockSender() = default;

void BlockSender::reset(std::size_t total) {
    // Allocated on the first block transfer only, then reused.
    buffer_.resize(std::size_t{kMaxBlockSize} * kSegmentData);
    buffered_ = 0;
    total_ = total;
    acked_ = 0;
    read_ = 0;
    segments_ = 0;
    block_size_ = 0;
    last_ack_block_size_ = 0;
    last_ack_resized_ = false;
    last_unused_ = 0;
    crc_ = 0;
    retransmitted_ = 0;
}

bool BlockSender::fill(std::uint8_t block_size, const ReadFn& read) {
    const std::size_t want =
        std::min<std::size_t>(std::size_t{block_size} * kSegmentData, buffer_.size());
    const std::size_t remaining = total_ - read_;
    const std::size_t add = std::min(remaining, want > buffered_ ? want - buffered_ : 0);
    if (add > 0) {
        const std::span<std::uint8_t> out(buffer_.data() + buffered_, add);
        if (!read(out)) {
            return false;
        }
        // The CRC covers each byte once, when it is first read; retransmissions reuse it.
        crc_ = crc16_ccitt(out, crc_);
        buffered_ += add;
        read_ += add;
    }
    block_size_ = block_size;
    const std::size_t segs =
        std::max<std::size_t>(1, (buffered_ + kSegmentData - 1) / kSegmentData);
    segments_ = static_cast<std::uint8_t>(std::min<std::size_t>(segs, block_size));
    if (read_ == total_) {
        const std::size_t tail = buffered_ - (segs - 1) * kSegmentData;
        last_unused_ = static_cast<std::uint8_t>(kSegmentData - std::min(tail, kSegmentData));
    }
    return true;
}

Payload BlockSender::segment(std::uint8_t seqno) const {
    const std::size_t offset = (std::size_t{seqno} - 1) * kSegmentData;
    const std::size_t len = offset < buffered_ ? std::min(kSegmentData, buffered_ - offset) : 0;
    const bool last = read_ == total_ && offset + kSegmentData >= buffered_;
    return make_block_segment(seqno, last,
                              std::span<const std::uint8_t>(buffer_.data() + offset, len));
}

BlockSender::AckResult BlockSender::on_ack(std::uint8_t ackseq, std::uint8_t block_size) {
    if (last_ack_resized_ && ackseq == last_ackseq_ && block_size == last_ack_block_size_) {
        return AckResult::Repeat;
    }
    if (ackseq > segments_) {
        return AckResult::InvalidSequence;
    }
    if (block_size == 0 || block_size > kMaxBlockSize) {
        return AckResult::InvalidBlockSize;
    }
    last_ack_resized_ = block_size != block_size_;
    last_ackseq_ = ackseq;
    last_ack_block_size_ = block_size;
    retransmitted_ += segments_ - ackseq;
    const bool all_acked = ackseq == segments_;
    const std::size_t done = std::min(buffered_, std::size_t{ackseq} * kSegmentData);
    if (all_acked && read_ == total_ && done == buffered_) {
        acked_ += done;
        buffered_ = 0;
        return AckResult::Done;
    }
    std::memmove(buffer_.data(), buffer_.data() + done, buffered_ - done);
    buffered_ -= done;
    acked_ += done;
    return AckResult::NextBlock;
}

} // namespace codrive::sdo::detail
