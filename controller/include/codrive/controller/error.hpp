// SPDX-License-Identifier: Apache-2.0
// Errors of the controller: a code per failure site (ControllerErrc), the lower-level cause, and
// the sentence for the user.
#pragma once

#include <string>
#include <string_view>
#include <system_error>
#include <utility>

namespace codrive::controller {

/// Why Controller::from_file(), create() or start() failed. `ControllerError::code` is always
/// one of these; the lower-level error behind it, if any, is `ControllerError::cause`.
enum class ControllerErrc {
    BusFileInvalid = 1,   ///< from_file(): the bus file cannot be read or has findings
    InvalidConfiguration, ///< no bus at all, or options that do not fit together
    EventLoopFailed,      ///< the event loop (epoll, timerfd) could not be created
    AlreadyStarted,       ///< start() was called before on this controller
    BusOpenFailed,        ///< a CAN interface could not be opened, watched or filtered
    SegmentFailed,        ///< an EtherCAT segment did not come up to OP
    StopRequested,        ///< request_stop() or a signal arrived while start() ran
    BootTimeout,          ///< the boot-up did not finish within boot_timeout
    NodeBootFailed,       ///< at least one node failed its boot-up (see boot_reports())
    SyncFailed,           ///< the SYNC producer could not be configured
    NotStarted,           ///< read_object()/write_object() before start() or after shutdown()
    NoSuchDevice,         ///< read_object()/write_object(): no such bus, node or slave
};

const std::error_category& controller_category();
std::error_code make_error_code(ControllerErrc e);
/// The code's name in snake case ("node_boot_failed"): Python's `codrive.Error.reason`.
[[nodiscard]] std::string_view to_string(ControllerErrc e);

} // namespace codrive::controller

template <>
struct std::is_error_code_enum<codrive::controller::ControllerErrc> : std::true_type {};

namespace codrive::controller {

/// A failed from_file(), create() or start(): a code to branch on, the lower-level cause, and
/// the sentence for people (e.g. "boot-up failed:\n  node 3: ...").
///
///     if (!r && r.error().code == ControllerErrc::NodeBootFailed) { ... }
struct ControllerError {
    std::error_code code;  ///< always a ControllerErrc: where start-up failed
    std::error_code cause; ///< the error below it (errno, CoreErrc, EcatErrc, ...); may be empty
    std::string detail;    ///< the sentence naming the interface, node or slave and the cause

    ControllerError() = default;
    ControllerError(ControllerErrc c, std::string d, std::error_code why = {})
        : code(make_error_code(c)), cause(why), detail(std::move(d)) {}
    /// The sentence (`detail`).
    [[nodiscard]] const std::string& message() const { return detail; }
    /// The sentence (`detail`), as the other error types of the stack spell it.
    [[nodiscard]] const std::string& to_string() const { return detail; }
};

} // namespace codrive::controller
