// SPDX-License-Identifier: Apache-2.0
// The core error category and the real clock instance.
#include <codrive/core/error.hpp>
#include <codrive/core/time.hpp>

namespace codrive {
namespace {

class CoreCategory final : public std::error_category {
public:
    const char* name() const noexcept override { return "codrive-core"; }
    std::string message(int ev) const override {
        switch (static_cast<CoreErrc>(ev)) {
        case CoreErrc::InvalidArgument:
            return "invalid argument";
        case CoreErrc::InvalidFrame:
            return "invalid CAN frame";
        case CoreErrc::ParseError:
            return "cannot parse the text";
        case CoreErrc::OutOfRange:
            return "value out of range for its type";
        case CoreErrc::TypeMismatch:
            return "data type does not match";
        case CoreErrc::NotSupported:
            return "not supported by this device";
        case CoreErrc::NotPermitted:
            return "not permitted (needs root or CAP_NET_ADMIN / CAP_NET_RAW)";
        case CoreErrc::NoSuchInterface:
            return "no such network interface";
        case CoreErrc::InterfaceDown:
            return "network interface is down";
        case CoreErrc::TxQueueFull:
            return "transmit queue full";
        case CoreErrc::BusOff:
            return "CAN controller is bus-off";
        case CoreErrc::Timeout:
            return "timed out";
        case CoreErrc::Closed:
            return "closed";
        case CoreErrc::NoSocketCan:
            return "this kernel has no SocketCAN support (AF_CAN unavailable)";
        }
        return "unknown core error";
    }
};

} // namespace

const std::error_category& core_category() {
    static const CoreCategory category;
    return category;
}

std::error_code make_error_code(CoreErrc e) {
    return {static_cast<int>(e), core_category()};
}

RealClock& RealClock::instance() {
    static RealClock clock;
    return clock;
}

} // namespace codrive
