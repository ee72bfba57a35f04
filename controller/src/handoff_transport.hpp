// SPDX-License-Identifier: Apache-2.0
// A DriveTransport whose object accesses are carried out on another thread: process data goes
// straight to the wrapped transport's image; object accesses (SDO, CoE) travel through lock-free
// rings of preallocated slots to the thread that owns the wrapped transport, and back.
#pragma once

#include "spsc_ring.hpp"

#include <codrive/drives/transport.hpp>

#include <array>
#include <cstdint>
#include <string>
#include <string_view>

namespace codrive::controller {

/// Two threads share one HandoffTransport: the *requesting* thread calls read(), write() and
/// deliver_completions(); the *executing* thread owns the wrapped transport and calls
/// pump_requests(). CAN axes in Threading::DedicatedCyclic request from the cyclic thread and the
/// loop thread executes; Controller::read_object() on an EtherCAT slave requests from the loop
/// thread and the cyclic thread executes (the slave's mailbox rides in its cyclic frame).
///
/// Neither side allocates: the kSlots request slots are allocated at construction, a request
/// moves its callback and data into a free slot, the executing side hands the wrapped transport
/// a callback that holds only the slot's number (stored inside std::function, no heap), and the
/// result comes back in the same slot. Every access in flight owns one slot, so the completion
/// ring can never be full and needs no backlog. What a caller builds itself (a callback too big
/// for std::function's inline storage, a non-empty byte vector) and what the wrapped transport
/// allocates are theirs; a refusal's sentence is a string built on the refusal path only.
class HandoffTransport final : public drives::DriveTransport {
public:
    /// Accesses that can be queued, under way or waiting for delivery at once.
    static constexpr std::size_t kSlots = 64;

    /// `executor` names the executing thread in the refusal sentence ("acyclic thread").
    HandoffTransport(drives::DriveTransport& inner, std::string executor);

    // ---- requesting thread ---------------------------------------------------------------
    [[nodiscard]] std::string name() const override { return name_; }
    /// Queues the access for the executing thread; fails at once (DriveErrc::Transport, "slave
    /// 2: too many object accesses waiting for the acyclic thread (64)") when kSlots accesses
    /// are already queued, under way or undelivered.
    void read(std::uint16_t index, std::uint8_t subindex, ReadDone done) override;
    void write(std::uint16_t index, std::uint8_t subindex, drives::Bytes data,
               WriteDone done) override;
    [[nodiscard]] drives::CyclicHandle output(std::uint16_t index,
                                              std::uint8_t subindex) const override {
        return inner_.output(index, subindex);
    }
    [[nodiscard]] drives::CyclicHandle input(std::uint16_t index,
                                             std::uint8_t subindex) const override {
        return inner_.input(index, subindex);
    }
    void set_raw(drives::CyclicHandle h, std::uint64_t raw) override { inner_.set_raw(h, raw); }
    [[nodiscard]] std::optional<std::uint64_t> get_raw(drives::CyclicHandle h) const override {
        return inner_.get_raw(h);
    }
    [[nodiscard]] std::optional<std::uint64_t> input_count(drives::CyclicHandle h) const override {
        return inner_.input_count(h);
    }
    /// Runs the callbacks of completed accesses. Returns how many ran.
    std::size_t deliver_completions();

    // ---- executing thread ----------------------------------------------------------------
    /// Starts the queued accesses on the wrapped transport; their results go back when it
    /// completes them. Returns how many were started.
    std::size_t pump_requests();
    /// Ends the queued accesses that were never started, each with DriveErrc::Transport and a
    /// sentence naming the device, the object and `why`; deliver_completions() runs their
    /// callbacks. For an executing thread that stops for good (shutdown): call it on the
    /// thread that owns the executing side from then on. Returns how many were ended.
    std::size_t abandon_requests(std::string_view why);

private:
    struct Slot {
        ObjectRequest request;
        drives::DriveResult<drives::Bytes> read_result;
        drives::DriveVoid write_result;
    };
    /// Requesting thread: a free slot's number, or false when all are in use.
    /// Queues one access in a free slot, or refuses it with its sentence.
    void submit(ObjectRequest r);
    bool take_slot(std::uint8_t& slot);
    void refuse(ObjectRequest& r) const;

    drives::DriveTransport& inner_;
    std::string name_;
    std::string executor_;
    std::array<Slot, kSlots> slots_{};
    std::array<std::uint8_t, kSlots> free_{}; ///< requesting thread only
    std::size_t free_count_ = 0;
    SpscRing<std::uint8_t, kSlots> requests_;    ///< slot numbers, requesting → executing
    SpscRing<std::uint8_t, kSlots> completions_; ///< slot numbers, executing → requesting
};

} // namespace codrive::controller
