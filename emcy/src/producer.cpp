// SPDX-License-Identifier: Apache-2.0
// EMCY producer with inhibit time (CiA 301 §7.2.7.1, 1015h).
#include <codrive/emcy/producer.hpp>

namespace codrive::emcy {

VoidResult EmcyProducer::send(std::uint16_t error_code, std::uint8_t error_register,
                              const std::array<std::uint8_t, 5>& manufacturer, TimePoint now) {
    EmcyMessage m;
    m.node = node_;
    m.error_code = error_code;
    m.error_register = error_register;
    m.manufacturer = manufacturer;
    const bool inhibited = sent_any_ && now < last_sent_ + inhibit_;
    if (count_ == 0 && !inhibited) {
        return transmit(m, now);
    }
    if (count_ == kQueueCapacity) {
        ++dropped_;
        return fail(CoreErrc::TxQueueFull);
    }
    queue_[(head_ + count_) % kQueueCapacity] = m;
    ++count_;
    return {};
}

VoidResult EmcyProducer::transmit(const EmcyMessage& m, TimePoint now) {
    auto r = bus_.send(make_emcy_frame(m, cob_id_));
    if (!r) {
        return r;
    }
    ++sent_;
    sent_any_ = true;
    last_sent_ = now;
    return {};
}

TimePoint EmcyProducer::next_deadline() const {
    if (count_ == 0) {
        return kNever;
    }
    return sent_any_ ? last_sent_ + inhibit_ : TimePoint{};
}

void EmcyProducer::on_tick(TimePoint now) {
    while (count_ != 0 && (!sent_any_ || now >= last_sent_ + inhibit_)) {
        if (!transmit(queue_[head_], now)) {
            // The bus has its own retry queue; a refusal means it is full or off. Drop the
            // message rather than spin on a deadline that stays due.
            ++dropped_;
        }
        head_ = (head_ + 1) % kQueueCapacity;
        --count_;
    }
}

} // namespace codrive::emcy
