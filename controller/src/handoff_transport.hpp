// SPDX-License-Identifier: Apache-2.0
// A DriveTransport for axes that live on the cyclic thread: process data goes straight to the
// wrapped transport's image (owned by the cyclic thread); object accesses (SDO, CoE) are handed
// to the acyclic thread through lock-free rings and their completions handed back.
#pragma once

#include "spsc_ring.hpp"

#include <codrive/drives/transport.hpp>

#include <deque>

namespace codrive::controller {

class HandoffTransport final : public drives::DriveTransport {
public:
    explicit HandoffTransport(drives::DriveTransport& inner);

    // Cyclic thread.
    [[nodiscard]] std::string name() const override { return name_; }
    /// Queues the access for the acyclic thread; fails at once (DriveErrc::Transport) when 64
    /// accesses are already waiting.
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
    /// Runs the callbacks of completed accesses (cyclic thread, at the start of a cycle).
    std::size_t deliver_completions();

    /// Acyclic thread: starts the queued accesses on the wrapped transport and hands results
    /// back. Returns how many were started.
    std::size_t pump_requests();

private:
    using Request = ObjectRequest;
    struct Completion {
        ReadDone read_done;
        WriteDone write_done;
        drives::DriveResult<drives::Bytes> read_result;
        drives::DriveVoid write_result;
    };
    void complete(Completion c);

    drives::DriveTransport& inner_;
    std::string name_;
    SpscRing<Request, 64> requests_;       ///< cyclic → acyclic
    SpscRing<Completion, 64> completions_; ///< acyclic → cyclic
    std::deque<Completion> backlog_;       ///< acyclic side only: completions waiting for room
};

} // namespace codrive::controller
