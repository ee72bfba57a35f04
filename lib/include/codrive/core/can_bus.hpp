// SPDX-License-Identifier: Apache-2.0
// The CAN bus interface every service sends through, and bus-state events.
#pragma once

#include <codrive/core/error.hpp>
#include <codrive/core/frame.hpp>
#include <codrive/core/time.hpp>

#include <cstdint>
#include <functional>
#include <span>
#include <string>

namespace codrive {

/// Controller / bus state as reported by error frames (SocketCAN) or fault injection.
enum class BusState : std::uint8_t { ErrorActive, ErrorWarning, ErrorPassive, BusOff };
[[nodiscard]] std::string_view to_string(BusState s);

/// A decoded bus event (from a SocketCAN error frame or the virtual bus).
struct BusEvent {
    enum class Kind : std::uint8_t {
        StateChanged,      ///< `state` holds the new state
        Restarted,         ///< controller restarted after bus-off
        ControllerProblem, ///< rx/tx overflow and similar (`detail`)
        ProtocolError,     ///< bit/form/stuff error (`detail`)
        NoAck,             ///< transmission not acknowledged
        LostArbitration,
        TransceiverError,
        RxOverflow, ///< frames dropped by the kernel socket queue (`count`)
    };
    Kind kind = Kind::StateChanged;
    BusState state = BusState::ErrorActive;
    std::uint8_t tx_errors = 0;
    std::uint8_t rx_errors = 0;
    std::uint32_t count = 0;
    std::string detail;
};
/// "bus state error-passive (tx errors 128, rx errors 0)" and similar.
[[nodiscard]] std::string to_string(const BusEvent& e);

/// Counters every bus keeps.
struct BusStats {
    std::uint64_t tx_frames = 0;
    std::uint64_t rx_frames = 0;
    std::uint64_t tx_queued = 0;     ///< frames that had to wait in the retry queue
    std::uint64_t tx_queue_full = 0; ///< sends refused because the retry queue was full
    std::uint64_t rx_dropped = 0;    ///< frames the kernel dropped (SO_RXQ_OVFL)
    std::uint64_t error_frames = 0;
};

/// A CAN bus endpoint. Received frames and events arrive through the handlers, dispatched by
/// the owner's event loop (SocketCanBus) or by the virtual network (VirtualBus).
class ICanBus {
public:
    using FrameHandler = std::function<void(const Frame&, TimePoint rx_time)>;
    using EventHandler = std::function<void(const BusEvent&)>;

    virtual ~ICanBus() = default;

    /// Sends a frame. If the transmit path is momentarily full, the frame is queued and sent
    /// later in order; an error only if it cannot be queued either (TxQueueFull) or the bus is
    /// gone. Never blocks.
    virtual VoidResult send(const Frame& frame) = 0;
    /// Sends `frames` in order, as send() one by one would, but lets the bus hand them to the
    /// kernel together (SocketCanBus: one sendmmsg() per batch, e.g. every RPDO of a SYNC
    /// cycle). Returns how many were accepted (sent or queued); it stops at the first frame
    /// send() would refuse, so the caller learns that frame's error by sending it alone. Never
    /// blocks, never allocates.
    virtual std::size_t send_many(std::span<const Frame> frames) {
        std::size_t n = 0;
        while (n < frames.size() && send(frames[n])) {
            ++n;
        }
        return n;
    }
    virtual void set_frame_handler(FrameHandler handler) = 0;
    virtual void set_event_handler(EventHandler handler) = 0;
    /// Frames waiting in the transmit retry queue.
    [[nodiscard]] virtual std::size_t tx_pending() const = 0;
    [[nodiscard]] virtual const BusStats& stats() const = 0;
    /// Interface name ("vcan0") or virtual endpoint name.
    [[nodiscard]] virtual const std::string& name() const = 0;
};

} // namespace codrive
