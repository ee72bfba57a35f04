// SPDX-License-Identifier: Apache-2.0
// SYNC producer on absolute deadlines (CiA 301 §7.2.5).
#include <codrive/sync/producer.hpp>

namespace codrive::sync {

VoidResult SyncProducer::configure(const SyncConfig& config) {
    // CiA 301 1019h: 0 = no counter, 1 reserved, 2..240 counter overflow value, 241..255 reserved.
    if (config.period.count() <= 0 || config.counter_overflow == 1 ||
        config.counter_overflow > 240 || config.cob_id > Frame::kStdMask) {
        return fail(CoreErrc::InvalidArgument);
    }
    config_ = config;
    stop();
    return {};
}

void SyncProducer::start(TimePoint start) {
    start_ = start;
    k_ = 0;
    next_ = start;
    counter_ = 1;
    last_counter_ = 0;
    running_ = true;
    stats_.reset();
}

void SyncProducer::stop() {
    running_ = false;
    next_ = kNever;
}

TimePoint SyncProducer::ideal_time(std::uint64_t k) const {
    return start_ + config_.period * static_cast<std::int64_t>(k);
}

void SyncProducer::on_tick(TimePoint now) {
    if (!running_ || now < next_) {
        return;
    }
    Frame f;
    f.id = config_.cob_id;
    std::uint8_t counter = 0;
    if (config_.counter_overflow != 0) {
        counter = counter_;
        f.len = 1;
        f.data[0] = counter;
    }
    const TimePoint ideal = next_;
    const std::uint64_t cycle = k_;
    const bool taken = sender_ ? sender_(f, SyncInfo{cycle, counter, ideal, now})
                               : static_cast<bool>(bus_.send(f));
    if (taken) {
        ++sent_;
        last_counter_ = counter;
        if (config_.counter_overflow != 0) {
            // 1..overflow, then back to 1 (CiA 301 §7.2.5.2).
            counter_ = counter_ >= config_.counter_overflow
                           ? std::uint8_t{1}
                           : static_cast<std::uint8_t>(counter_ + 1);
        }
    } else {
        ++send_errors_;
    }
    stats_.add(now - ideal);
    // Next slot on the grid after now: a tick later than one period skips the missed slots.
    ++k_;
    next_ = ideal_time(k_);
    if (next_ <= now) {
        const auto behind = static_cast<std::uint64_t>((now - next_) / config_.period) + 1;
        skipped_ += behind;
        k_ += behind;
        next_ = ideal_time(k_);
    }
    if (hook_) {
        hook_(SyncInfo{cycle, counter, ideal, now});
    }
}

} // namespace codrive::sync
