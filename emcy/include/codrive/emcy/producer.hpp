// SPDX-License-Identifier: Apache-2.0
// EMCY producer with inhibit time (CiA 301 §7.2.7, 1014h/1015h) for simulated devices.
#pragma once

#include <codrive/core/can_bus.hpp>
#include <codrive/core/event_loop.hpp>
#include <codrive/emcy/message.hpp>

#include <array>
#include <cstdint>

namespace codrive::emcy {

/// Sends EMCY no closer together than the inhibit time (1015h, 100 µs units): a message that
/// comes too early waits in a small fixed queue and leaves on on_tick() at the earliest
/// allowed time (CiA 301 §7.2.7.1). No allocation.
class EmcyProducer final : public ITimed {
public:
    static constexpr std::size_t kQueueCapacity = 8;

    /// `cob_id` 0 = the predefined 080h + node.
    EmcyProducer(ICanBus& bus, NodeId node, std::uint32_t cob_id = 0)
        : bus_(bus), node_(node), cob_id_(cob_id != 0 ? cob_id : cob::emcy(node)) {}

    /// 1015h in multiples of 100 µs; 0 = no inhibit.
    void set_inhibit_time(std::uint16_t units_100us) { inhibit_ = microseconds(100) * units_100us; }
    [[nodiscard]] Duration inhibit_time() const { return inhibit_; }
    void set_cob_id(std::uint32_t cob_id) { cob_id_ = cob_id; }

    /// Sends now, or queues if the inhibit time has not passed since the last EMCY.
    /// Errors: TxQueueFull if the queue is full (the message is dropped and counted); the
    /// bus's send errors.
    VoidResult send(std::uint16_t error_code, std::uint8_t error_register,
                    const std::array<std::uint8_t, 5>& manufacturer, TimePoint now);
    /// The error-reset EMCY (code 0000h).
    VoidResult send_reset(std::uint8_t error_register, TimePoint now) {
        return send(0x0000, error_register, {}, now);
    }

    [[nodiscard]] TimePoint next_deadline() const override;
    void on_tick(TimePoint now) override;

    [[nodiscard]] std::size_t queued() const { return count_; }
    [[nodiscard]] std::uint64_t sent() const { return sent_; }
    [[nodiscard]] std::uint64_t dropped() const { return dropped_; }

private:
    VoidResult transmit(const EmcyMessage& m, TimePoint now);

    ICanBus& bus_;
    NodeId node_;
    std::uint32_t cob_id_;
    Duration inhibit_{0};
    bool sent_any_ = false;
    TimePoint last_sent_{};
    std::array<EmcyMessage, kQueueCapacity> queue_{};
    std::size_t head_ = 0;
    std::size_t count_ = 0;
    std::uint64_t sent_ = 0;
    std::uint64_t dropped_ = 0;
};

} // namespace codrive::emcy
