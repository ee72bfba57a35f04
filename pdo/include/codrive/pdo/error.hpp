// SPDX-License-Identifier: Apache-2.0
// PDO errors: codes for the category, and PdoError, which reads as one sentence.
#pragma once

#include <codrive/core/error.hpp>

#include <string>
#include <system_error>
#include <tl/expected.hpp>

namespace codrive::pdo {

enum class PdoErrc {
    InvalidMapping = 1,   ///< an entry cannot be mapped (object, direction, length)
    LengthExceeded,       ///< more than 64 bits, or more entries than the device allows
    InvalidCommunication, ///< COB-ID or transmission type not valid for the device
    UnsupportedByDevice,  ///< the device quirks forbid it (e.g. changing a read-only COB-ID)
    SdoFailed,            ///< an SDO transfer of the configuration or read-back failed
    UnknownObject,        ///< process image: (index, sub) is not mapped in any PDO of the node
    UnknownNode,          ///< the engine has no such node
    AlreadyConfigured,    ///< the node was added twice
    TooManyPdos,          ///< engine capacity
};

const std::error_category& pdo_category();
std::error_code make_error_code(PdoErrc e);

/// A PDO failure: a code plus the sentence that explains it ("node 3: TPDO1 maps 0x607A:00
/// (INTEGER32) but it is only RPDO-mappable").
struct PdoError {
    std::error_code code;
    std::string message;
    [[nodiscard]] const std::string& to_string() const { return message; }
};

template <typename T>
using PdoResult = tl::expected<T, PdoError>;

[[nodiscard]] inline tl::unexpected<PdoError> pdo_fail(PdoErrc code, std::string message) {
    return tl::unexpected<PdoError>(PdoError{make_error_code(code), std::move(message)});
}

} // namespace codrive::pdo

template <>
struct std::is_error_code_enum<codrive::pdo::PdoErrc> : std::true_type {};
