// SPDX-License-Identifier: Apache-2.0
// CiA 301 SDO abort codes (§7.2.4.3.17): one table shared by CANopen SDO and EtherCAT CoE.
#pragma once

#include <cstdint>
#include <optional>
#include <span>
#include <string_view>
#include <system_error>

namespace codrive {

/// SDO abort codes; the enumerator values are the 32-bit codes sent on the wire.
enum class SdoAbort : std::uint32_t {
    ToggleBit = 0x05030000,
    Timeout = 0x05040000,
    UnknownCommand = 0x05040001,
    InvalidBlockSize = 0x05040002,
    InvalidSequence = 0x05040003,
    CrcError = 0x05040004,
    OutOfMemory = 0x05040005,
    UnsupportedAccess = 0x06010000,
    WriteOnly = 0x06010001,
    ReadOnly = 0x06010002,
    NoObject = 0x06020000,
    NotMappable = 0x06040041,
    PdoLengthExceeded = 0x06040042,
    ParameterIncompatible = 0x06040043,
    DeviceIncompatible = 0x06040047,
    HardwareError = 0x06060000,
    LengthMismatch = 0x06070010,
    LengthTooHigh = 0x06070012,
    LengthTooLow = 0x06070013,
    NoSubindex = 0x06090011,
    InvalidValue = 0x06090030,
    ValueTooHigh = 0x06090031,
    ValueTooLow = 0x06090032,
    MaxBelowMin = 0x06090036,
    NoResource = 0x060A0023,
    General = 0x08000000,
    DataTransfer = 0x08000020,
    DataTransferLocal = 0x08000021,
    DataTransferState = 0x08000022,
    NoDictionary = 0x08000023,
    NoData = 0x08000024,
};

/// The CiA 301 text for an abort code ("object does not exist in the object dictionary"), or
/// nullopt for a code the standard does not define (vendor codes).
[[nodiscard]] std::optional<std::string_view> sdo_abort_text(std::uint32_t code);

/// Text for any code: the standard text, or "unknown abort code".
[[nodiscard]] std::string_view sdo_abort_describe(std::uint32_t code);

/// Every abort code the standard defines, in ascending order.
[[nodiscard]] std::span<const SdoAbort> all_sdo_aborts();

const std::error_category& sdo_abort_category();
std::error_code make_error_code(SdoAbort a);

} // namespace codrive

template <>
struct std::is_error_code_enum<codrive::SdoAbort> : std::true_type {};
