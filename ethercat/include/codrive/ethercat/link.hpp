// SPDX-License-Identifier: Apache-2.0
// The link under the EtherCAT master: sends and receives whole Ethernet frames.
#pragma once

#include <codrive/core/error.hpp>
#include <codrive/core/time.hpp>

#include <cstdint>
#include <span>
#include <string>
#include <system_error>

namespace codrive::ethercat {

/// A frame link. The master owns the protocol; a link only moves frames: the raw-socket link on
/// a real interface, or an in-process link to simulated slaves in unit tests.
class IEcatLink {
public:
    virtual ~IEcatLink() = default;
    /// Sends one Ethernet frame without waiting for room to send it. Errors: the socket's errno
    /// (ENOBUFS or EAGAIN when the transmit queue is full: see transmit_queue_full()), or Closed.
    virtual VoidResult send(std::span<const std::uint8_t> frame) = 0;
    /// Waits for the next EtherCAT frame until `deadline`; returns its length. Frames longer than
    /// `buffer` are truncated. Errors: CoreErrc::Timeout at the deadline, the socket's errno.
    virtual Result<std::size_t> receive(std::span<std::uint8_t> buffer, TimePoint deadline) = 0;
    /// Lets time pass between polls (a mailbox answer is not there yet). The real link sleeps;
    /// a simulated link advances its fake clock.
    virtual void idle(Duration d) = 0;
    /// "eth0", "in-process chain".
    [[nodiscard]] virtual std::string name() const = 0;
};

/// True for a send error that says the frame found no room (ENOBUFS: the interface's queue
/// dropped it; EAGAIN: the socket's send buffer is full). A later send may succeed; the frame
/// did not leave.
[[nodiscard]] inline bool transmit_queue_full(const std::error_code& ec) {
    return ec == std::errc::no_buffer_space || ec == std::errc::resource_unavailable_try_again ||
           ec == std::errc::operation_would_block;
}

} // namespace codrive::ethercat
