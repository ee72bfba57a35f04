// SPDX-License-Identifier: Apache-2.0
// Sub-block bookkeeping for the receiving side of SDO block transfers.
#include "block_receiver.hpp"

#include <codrive/sdo/crc16.hpp>

namespace codrive::sdo::detail {

void BlockReceiver::reset(std::uint8_t block_size) {
    block_size_ = block_size;
    previous_block_size_ = block_size;
    expected_ = 1;
    gap_ = false;
    complete_ = false;
    stale_possible_ = false;
    shrink_next_ = false;
    accepted_seqno_ = 0;
    crc_ = 0;
    received_ = 0;
}

std::uint8_t BlockReceiver::next_block_size(std::uint8_t configured) {
    shrink_next_ = !shrink_next_;
    return shrink_next_ && configured > 1 ? static_cast<std::uint8_t>(configured - 1) : configured;
}

void BlockReceiver::start_sub_block(std::uint8_t next_block_size, bool early) {
    previous_block_size_ = block_size_;
    block_size_ = next_block_size;
    expected_ = 1;
    gap_ = false;
    stale_possible_ = early;
}

BlockReceiver::SegmentResult BlockReceiver::on_segment(const FrameInfo& segment,
                                                       const WriteFn& write) {
    if (segment.seqno > block_size_ && segment.seqno <= previous_block_size_) {
        // Beyond the new (smaller, see next_block_size()) sub-block but within the previous one:
        // a late or repeated segment of the sub-block just acknowledged.
        return SegmentResult::Stale;
    }
    if (segment.seqno == 0 || segment.seqno > block_size_) {
        return SegmentResult::InvalidSequence;
    }
    if (complete_) {
        return SegmentResult::Skipped; // a repeat after the last segment: ignore
    }
    if (accepted_seqno_ != 0 && segment.seqno == accepted_seqno_ && segment.seqno != expected_ &&
        segment.last == accepted_last_ && segment.data == accepted_data_) {
        // A copy of the segment accepted last (typically the last one of the sub-block just
        // acknowledged): taking it for a gap would ask the sender to repeat a whole sub-block.
        return SegmentResult::Stale;
    }
    // CiA 301 §7.2.4.3.9: the receiver acknowledges the last segment received in sequence; the
    // sender restarts from there. The sub-block ends with seqno == blksize or the c bit, even if
    // that segment itself is out of sequence.
    const bool ends_block = segment.last || segment.seqno == block_size_;
    if (segment.seqno != expected_ || gap_) {
        if (expected_ == 1 && stale_possible_) {
            // After an early (timer) acknowledgement, segments the sender had already sent may
            // still arrive. Acknowledging on them would make the sender repeat data we would
            // then accept twice, so they are dropped unanswered. Without an early
            // acknowledgement FIFO delivery rules them out: a gap here is a lost first segment.
            return SegmentResult::Stale;
        }
        if (segment.seqno >= expected_) {
            gap_ = true;
        }
        return ends_block && gap_ ? SegmentResult::SubBlockDone : SegmentResult::Skipped;
    }
    ++expected_;
    stale_possible_ = false;
    accepted_seqno_ = segment.seqno;
    accepted_last_ = segment.last;
    accepted_data_ = segment.data;
    if (segment.last) {
        last_ = segment.data;
        complete_ = true;
        return SegmentResult::SubBlockDone;
    }
    const std::span<const std::uint8_t> data(segment.data.data(), kSegmentData);
    if (!write(data)) {
        return SegmentResult::WriteFailed;
    }
    crc_ = crc16_ccitt(data, crc_);
    received_ += kSegmentData;
    return ends_block ? SegmentResult::SubBlockDone : SegmentResult::Stored;
}

bool BlockReceiver::finish(std::uint8_t unused, const WriteFn& write) {
    if (unused > kSegmentData) {
        return false;
    }
    const std::span<const std::uint8_t> data(last_.data(), kSegmentData - unused);
    if (!data.empty() && !write(data)) {
        return false;
    }
    crc_ = crc16_ccitt(data, crc_);
    received_ += data.size();
    return true;
}

} // namespace codrive::sdo::detail
