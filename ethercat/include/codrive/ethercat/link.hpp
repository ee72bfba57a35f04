// SPDX-License-Identifier: Apache-2.0
// The link under the EtherCAT master: sends and receives whole Ethernet frames.
#pragma once

#include <codrive/core/error.hpp>
#include <codrive/core/time.hpp>

#include <cstdint>
#include <span>
#include <string>

namespace codrive::ethercat {

/// A frame link. The master owns the protocol; a link only moves frames: the raw-socket link on
/// a real interface, or an in-process link to simulated slaves in unit tests.
class IEcatLink {
public:
    virtual ~IEcatLink() = default;
    /// Sends one Ethernet frame. Errors: the socket's errno, or Closed.
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

} // namespace codrive::ethercat
