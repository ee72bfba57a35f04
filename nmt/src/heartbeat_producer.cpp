// SPDX-License-Identifier: Apache-2.0
// Heartbeat producer on absolute deadlines (CiA 301 §7.2.8.3.2, 1017h).
#include <codrive/nmt/heartbeat_producer.hpp>

namespace codrive::nmt {

void HeartbeatProducer::set_period(milliseconds period, TimePoint now) {
    period_ = period;
    start_ = now;
    k_ = 1;
    next_ = period.count() > 0 ? start_ + period_ : kNever;
}

VoidResult HeartbeatProducer::send_boot_up() {
    if (!valid_node_id(node_)) {
        return fail(CoreErrc::InvalidArgument);
    }
    auto r = bus_.send(Frame::make(cob::heartbeat(node_), {0x00}));
    if (!r) {
        ++send_errors_;
        return r;
    }
    ++sent_;
    state_ = NmtState::PreOperational;
    return {};
}

void HeartbeatProducer::on_tick(TimePoint now) {
    if (next_ == kNever || now < next_ || !valid_node_id(node_)) {
        return;
    }
    if (bus_.send(Frame::make(cob::heartbeat(node_), {static_cast<std::uint8_t>(state_)}))) {
        ++sent_;
    } else {
        ++send_errors_;
    }
    // Stay on the grid start + k·period; skip periods that were missed entirely so a late tick
    // produces one heartbeat, not a burst.
    while (next_ <= now) {
        ++k_;
        next_ = start_ + period_ * static_cast<std::int64_t>(k_);
    }
}

} // namespace codrive::nmt
