// SPDX-License-Identifier: Apache-2.0
// Lock-free hand-off of a device's object accesses between two threads through preallocated
// slots.
#include "handoff_transport.hpp"

#include <fmt/format.h>

#include <utility>

namespace codrive::controller {

HandoffTransport::HandoffTransport(drives::DriveTransport& inner, std::string executor)
    : inner_(inner), name_(inner.name()), executor_(std::move(executor)) {
    for (std::size_t i = 0; i < kSlots; ++i) {
        free_[i] = static_cast<std::uint8_t>(kSlots - 1 - i);
    }
    free_count_ = kSlots;
}

bool HandoffTransport::take_slot(std::uint8_t& slot) {
    if (free_count_ == 0) {
        return false;
    }
    slot = free_[--free_count_];
    return true;
}

void HandoffTransport::refuse(ObjectRequest& r) const {
    auto why = drives::drive_fail(drives::DriveErrc::Transport,
                                  name_ + ": too many object accesses waiting for the " +
                                      executor_ + " (" + std::to_string(kSlots) + ")");
    if (r.is_write) {
        r.write_done(std::move(why));
    } else {
        r.read_done(std::move(why));
    }
}

void HandoffTransport::read(std::uint16_t index, std::uint8_t subindex, ReadDone done) {
    submit(ObjectRequest::read(index, subindex, std::move(done)));
}

void HandoffTransport::write(std::uint16_t index, std::uint8_t subindex, drives::Bytes data,
                             WriteDone done) {
    submit(ObjectRequest::write(index, subindex, std::move(data), std::move(done)));
}

void HandoffTransport::submit(ObjectRequest r) {
    std::uint8_t slot = 0;
    if (!take_slot(slot)) {
        refuse(r);
        return;
    }
    slots_[slot].request = std::move(r);
    // Cannot fail: a slot number is in at most one ring at a time and there are kSlots of them.
    (void)requests_.push(slot);
}

std::size_t HandoffTransport::deliver_completions() {
    std::size_t n = 0;
    std::uint8_t slot = 0;
    while (completions_.pop(slot)) {
        Slot& s = slots_[slot];
        // Free the slot before the callback runs: a callback may start the next access.
        ObjectRequest r = std::move(s.request);
        s.request = ObjectRequest{};
        if (r.is_write) {
            drives::DriveVoid res = std::move(s.write_result);
            s.write_result = drives::DriveVoid{};
            free_[free_count_++] = slot;
            r.write_done(std::move(res));
        } else {
            drives::DriveResult<drives::Bytes> res = std::move(s.read_result);
            s.read_result = drives::Bytes{};
            free_[free_count_++] = slot;
            r.read_done(std::move(res));
        }
        ++n;
    }
    return n;
}

std::size_t HandoffTransport::abandon_requests(std::string_view why) {
    std::size_t n = 0;
    std::uint8_t slot = 0;
    while (requests_.pop(slot)) {
        Slot& s = slots_[slot];
        auto failed =
            drives::drive_fail(drives::DriveErrc::Transport,
                               fmt::format("{}: {} of object {:04X}h:{:02X}h cancelled: {}", name_,
                                           s.request.is_write ? "write" : "read", s.request.index,
                                           s.request.subindex, why));
        if (s.request.is_write) {
            s.write_result = std::move(failed);
        } else {
            s.read_result = std::move(failed);
        }
        (void)completions_.push(slot);
        ++n;
    }
    return n;
}

std::size_t HandoffTransport::pump_requests() {
    std::size_t n = 0;
    std::uint8_t slot = 0;
    while (requests_.pop(slot)) {
        ObjectRequest& r = slots_[slot].request;
        // The callbacks hold `this` and the slot's number: small enough for std::function's
        // inline storage. The slot is not touched after the completion is pushed: from then on
        // it belongs to the requesting thread again.
        if (r.is_write) {
            inner_.write(r.index, r.subindex, std::move(r.data),
                         [this, slot](drives::DriveVoid res) {
                             slots_[slot].write_result = std::move(res);
                             std::uint8_t s = slot;
                             (void)completions_.push(s);
                         });
        } else {
            inner_.read(r.index, r.subindex, [this, slot](drives::DriveResult<drives::Bytes> res) {
                slots_[slot].read_result = std::move(res);
                std::uint8_t s = slot;
                (void)completions_.push(s);
            });
        }
        ++n;
    }
    return n;
}

} // namespace codrive::controller
