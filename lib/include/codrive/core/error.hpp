// SPDX-License-Identifier: Apache-2.0
// Core error codes, the std::error_category that names them, and the Result alias.
#pragma once

#include <string>
#include <system_error>
#include <tl/expected.hpp>

namespace codrive {

/// Every fallible codrive call returns Result<T>: a value, or an error code.
template <typename T>
using Result = tl::expected<T, std::error_code>;
using VoidResult = tl::expected<void, std::error_code>;

/// Shorthand for returning an error: `return fail(CoreErrc::Timeout);`
template <typename E>
[[nodiscard]] tl::unexpected<std::error_code> fail(E e) {
    return tl::unexpected<std::error_code>(make_error_code(e));
}
[[nodiscard]] inline tl::unexpected<std::error_code> fail(std::error_code ec) {
    return tl::unexpected<std::error_code>(ec);
}
/// The current errno as an error code.
[[nodiscard]] inline tl::unexpected<std::error_code> fail_errno(int err) {
    return tl::unexpected<std::error_code>(std::error_code(err, std::system_category()));
}

/// Errors of the core layer (frames, values, buses, event loop).
enum class CoreErrc {
    InvalidArgument = 1,
    InvalidFrame,
    ParseError,
    OutOfRange,
    TypeMismatch,
    NotSupported,
    NotPermitted,
    NoSuchInterface,
    InterfaceDown,
    TxQueueFull,
    BusOff,
    Timeout,
    Closed,
    NoSocketCan,
};

const std::error_category& core_category();
std::error_code make_error_code(CoreErrc e);

} // namespace codrive

template <>
struct std::is_error_code_enum<codrive::CoreErrc> : std::true_type {};
