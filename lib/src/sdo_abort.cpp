// SPDX-License-Identifier: Apache-2.0
// Texts of the CiA 301 SDO abort codes and their error category.
#include <codrive/core/sdo_abort.hpp>

#include <array>
#include <fmt/format.h>
#include <string>

namespace codrive {
namespace {

struct AbortRow {
    SdoAbort code;
    std::string_view text;
};

// CiA 301 v4.2 table 22.
constexpr std::array kAbortRows{
    AbortRow{SdoAbort::ToggleBit, "toggle bit not alternated"},
    AbortRow{SdoAbort::Timeout, "SDO protocol timed out"},
    AbortRow{SdoAbort::UnknownCommand, "client/server command specifier not valid or unknown"},
    AbortRow{SdoAbort::InvalidBlockSize, "invalid block size (block mode only)"},
    AbortRow{SdoAbort::InvalidSequence, "invalid sequence number (block mode only)"},
    AbortRow{SdoAbort::CrcError, "CRC error (block mode only)"},
    AbortRow{SdoAbort::OutOfMemory, "out of memory"},
    AbortRow{SdoAbort::UnsupportedAccess, "unsupported access to an object"},
    AbortRow{SdoAbort::WriteOnly, "attempt to read a write only object"},
    AbortRow{SdoAbort::ReadOnly, "attempt to write a read only object"},
    AbortRow{SdoAbort::NoObject, "object does not exist in the object dictionary"},
    AbortRow{SdoAbort::NotMappable, "object cannot be mapped to the PDO"},
    AbortRow{SdoAbort::PdoLengthExceeded,
             "the number and length of the objects to be mapped would exceed PDO length"},
    AbortRow{SdoAbort::ParameterIncompatible, "general parameter incompatibility reason"},
    AbortRow{SdoAbort::DeviceIncompatible, "general internal incompatibility in the device"},
    AbortRow{SdoAbort::HardwareError, "access failed due to a hardware error"},
    AbortRow{SdoAbort::LengthMismatch,
             "data type does not match, length of service parameter does not match"},
    AbortRow{SdoAbort::LengthTooHigh, "data type does not match, length of service parameter too "
                                      "high"},
    AbortRow{SdoAbort::LengthTooLow, "data type does not match, length of service parameter too "
                                     "low"},
    AbortRow{SdoAbort::NoSubindex, "sub-index does not exist"},
    AbortRow{SdoAbort::InvalidValue, "invalid value for parameter (download only)"},
    AbortRow{SdoAbort::ValueTooHigh, "value of parameter written too high (download only)"},
    AbortRow{SdoAbort::ValueTooLow, "value of parameter written too low (download only)"},
    AbortRow{SdoAbort::MaxBelowMin, "maximum value is less than minimum value"},
    AbortRow{SdoAbort::NoResource, "resource not available: SDO connection"},
    AbortRow{SdoAbort::General, "general error"},
    AbortRow{SdoAbort::DataTransfer, "data cannot be transferred or stored to the application"},
    AbortRow{SdoAbort::DataTransferLocal, "data cannot be transferred or stored to the "
                                          "application because of local control"},
    AbortRow{SdoAbort::DataTransferState, "data cannot be transferred or stored to the "
                                          "application because of the present device state"},
    AbortRow{SdoAbort::NoDictionary, "object dictionary dynamic generation fails or no object "
                                     "dictionary is present"},
    AbortRow{SdoAbort::NoData, "no data available"},
};

constexpr auto kAllAborts = [] {
    std::array<SdoAbort, kAbortRows.size()> out{};
    for (std::size_t i = 0; i < kAbortRows.size(); ++i) {
        out[i] = kAbortRows[i].code;
    }
    return out;
}();

class SdoAbortCategory final : public std::error_category {
public:
    const char* name() const noexcept override { return "sdo-abort"; }
    std::string message(int ev) const override {
        const auto code = static_cast<std::uint32_t>(ev);
        return fmt::format("0x{:08X} {}", code, sdo_abort_describe(code));
    }
};

} // namespace

std::optional<std::string_view> sdo_abort_text(std::uint32_t code) {
    for (const auto& row : kAbortRows) {
        if (static_cast<std::uint32_t>(row.code) == code) {
            return row.text;
        }
    }
    return std::nullopt;
}

std::string_view sdo_abort_describe(std::uint32_t code) {
    return sdo_abort_text(code).value_or("unknown abort code");
}

std::span<const SdoAbort> all_sdo_aborts() {
    return kAllAborts;
}

const std::error_category& sdo_abort_category() {
    static const SdoAbortCategory category;
    return category;
}

std::error_code make_error_code(SdoAbort a) {
    return {static_cast<int>(static_cast<std::uint32_t>(a)), sdo_abort_category()};
}

} // namespace codrive
