// SPDX-License-Identifier: Apache-2.0
// Errors of the drive layer: codes with a std::error_category plus a sentence for the user.
#pragma once

#include <codrive/core/error.hpp>

#include <string>
#include <system_error>
#include <tl/expected.hpp>
#include <utility>

namespace codrive::drives {

/// Why a drive operation failed.
enum class DriveErrc {
    Timeout = 1,    ///< the drive did not reach the expected state/bit in time
    Fault,          ///< the drive entered FAULT (or reported an error bit) during the operation
    FollowingError, ///< statusword bit 13 in PP/CSP
    HomingError,    ///< statusword bit 13 in HM
    NotSupported,   ///< mode or object the drive/profile does not support
    WrongState, ///< the operation needs another CiA 402 state (e.g. motion needs OPERATION ENABLED)
    WrongMode,  ///< the operation needs another mode of operation
    Cancelled,  ///< superseded by another operation or by a stop
    Transport,  ///< object access failed (SDO abort, timeout, CoE error)
    NotMapped,  ///< no cyclic (PDO) entry for an object that must be cyclic
    InvalidArgument,
};

const std::error_category& drive_category();
std::error_code make_error_code(DriveErrc e);

} // namespace codrive::drives

template <>
struct std::is_error_code_enum<codrive::drives::DriveErrc> : std::true_type {};

namespace codrive::drives {

/// A failed drive operation: a code for programs and a sentence for people, e.g.
/// "axis 1: enable timed out in SWITCH ON DISABLED: STO active (statusword bit 8)".
struct DriveError {
    std::error_code code;
    std::string message;

    DriveError() = default;
    DriveError(std::error_code c, std::string m) : code(c), message(std::move(m)) {}
    DriveError(DriveErrc c, std::string m) : code(make_error_code(c)), message(std::move(m)) {}
    [[nodiscard]] const std::string& to_string() const { return message; }
};

template <typename T>
using DriveResult = tl::expected<T, DriveError>;
using DriveVoid = tl::expected<void, DriveError>;

[[nodiscard]] inline tl::unexpected<DriveError> drive_fail(DriveErrc c, std::string message) {
    return tl::unexpected<DriveError>(DriveError(c, std::move(message)));
}

} // namespace codrive::drives
