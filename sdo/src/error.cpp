// SPDX-License-Identifier: Apache-2.0
// SdoErrc category and the one-sentence rendering of SdoError.
#include <codrive/sdo/error.hpp>

#include <fmt/format.h>

namespace codrive::sdo {
namespace {

class SdoCategory final : public std::error_category {
public:
    const char* name() const noexcept override { return "sdo"; }
    std::string message(int ev) const override {
        switch (static_cast<SdoErrc>(ev)) {
        case SdoErrc::Timeout:
            return "timed out";
        case SdoErrc::NodeRebooted:
            return "the node rebooted during the transfer";
        case SdoErrc::WrongObject:
            return "response for a different object";
        case SdoErrc::ProtocolError:
            return "SDO protocol error";
        case SdoErrc::SendFailed:
            return "the request could not be sent";
        case SdoErrc::Cancelled:
            return "cancelled";
        case SdoErrc::LocalTransferError:
            return "local data source or sink failed";
        case SdoErrc::SizeMismatch:
            return "the object size does not match the requested type";
        case SdoErrc::TooLarge:
            return "too large for an SDO transfer";
        }
        return "unknown SDO error";
    }
};

} // namespace

const std::error_category& sdo_category() {
    static const SdoCategory category;
    return category;
}

std::error_code make_error_code(SdoErrc e) {
    return {static_cast<int>(e), sdo_category()};
}

std::string_view to_string(Direction d) {
    return d == Direction::Upload ? "upload" : "download";
}

std::string_view to_string(Protocol p) {
    switch (p) {
    case Protocol::Expedited:
        return "expedited";
    case Protocol::Segmented:
        return "segmented";
    case Protocol::Block:
        return "block";
    case Protocol::Unknown:
        break;
    }
    return "";
}

std::optional<std::uint32_t> SdoError::abort_code() const {
    if (cause.category() == sdo_abort_category()) {
        return static_cast<std::uint32_t>(cause.value());
    }
    return std::nullopt;
}

std::string SdoError::to_string() const {
    const auto proto = sdo::to_string(protocol);
    std::string head =
        fmt::format("node {}: SDO {}{}{} 0x{:04X}:{:02X}", node, proto, proto.empty() ? "" : " ",
                    sdo::to_string(direction), index, subindex);
    std::string what;
    if (const auto code = abort_code()) {
        const char* by = origin == AbortOrigin::Client ? "client" : "server";
        what = fmt::format("aborted by {}: {}", by, cause.message());
    } else if (cause == SdoErrc::Timeout) {
        what = fmt::format("timed out after {:.0f} ms", to_ms(timeout));
    } else if (cause.category() == sdo_category()) {
        what = fmt::format("failed: {}", cause.message());
    } else {
        what = fmt::format("failed: {}", cause ? cause.message() : std::string("unknown error"));
    }
    if (!detail.empty()) {
        what += fmt::format(" ({})", detail);
    }
    return head + " " + what;
}

} // namespace codrive::sdo
