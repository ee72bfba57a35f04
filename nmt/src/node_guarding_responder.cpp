// SPDX-License-Identifier: Apache-2.0
// Node guarding, slave side: guard replies and life guarding (CiA 301 §7.2.8.3.1).
#include "format.hpp"

#include <codrive/nmt/node_guarding.hpp>

namespace codrive::nmt {

void NodeGuardingResponder::set_life_guarding(milliseconds guard_time,
                                              std::uint8_t life_time_factor) {
    guard_time_ = guard_time;
    factor_ = life_time_factor;
    // Life guarding starts with the first guard request after configuration.
    deadline_ = kNever;
    lost_ = false;
}

void NodeGuardingResponder::on_frame(const Frame& frame, TimePoint now) {
    if (!frame.rtr() || frame.extended() || frame.id != cob::heartbeat(node_)) {
        return;
    }
    auto byte = static_cast<std::uint8_t>(static_cast<std::uint8_t>(state_) & 0x7FU);
    std::uint8_t toggle = toggle_;
    if (corrupt_next_) {
        corrupt_next_ = false;
        toggle ^= 1U;
    }
    byte = static_cast<std::uint8_t>(byte | (toggle << 7));
    if (bus_.send(Frame::make(cob::heartbeat(node_), {byte}))) {
        ++replies_;
    }
    toggle_ ^= 1U;
    if (guard_time_.count() > 0 && factor_ > 0) {
        last_rtr_ = now;
        deadline_ = now + guard_time_ * factor_;
        if (lost_) {
            lost_ = false;
            if (handler_) {
                handler_(ErrorControlEvent{node_, ErrorControlEventKind::LifeGuardRecovered, state_,
                                           now,
                                           fmt::format("node {}: life guarding recovered: guard "
                                                       "request received",
                                                       node_)});
            }
        }
    }
}

void NodeGuardingResponder::on_tick(TimePoint now) {
    if (deadline_ == kNever || now < deadline_ || lost_) {
        return;
    }
    lost_ = true;
    deadline_ = kNever;
    if (handler_) {
        handler_(ErrorControlEvent{
            node_, ErrorControlEventKind::LifeGuardLost, state_, now,
            fmt::format("node {}: life guarding: no guard request from the NMT master for {} ms "
                        "(guard time {} ms x life time factor {})",
                        node_, detail::ms_text(now - last_rtr_), guard_time_.count(), factor_)});
    }
}

} // namespace codrive::nmt
