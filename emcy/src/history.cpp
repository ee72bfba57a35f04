// SPDX-License-Identifier: Apache-2.0
// Bounded EMCY history ring.
#include <codrive/emcy/history.hpp>

namespace codrive::emcy {

void EmcyHistory::push(const EmcyRecord& r) {
    ring_[head_] = r;
    head_ = (head_ + 1) % kCapacity;
    if (size_ < kCapacity) {
        ++size_;
    } else {
        ++dropped_;
    }
}

void EmcyHistory::clear() {
    head_ = 0;
    size_ = 0;
}

const EmcyRecord& EmcyHistory::operator[](std::size_t i) const {
    return ring_[(head_ + kCapacity - 1 - (i % kCapacity)) % kCapacity];
}

} // namespace codrive::emcy
