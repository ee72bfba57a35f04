// SPDX-License-Identifier: Apache-2.0
// The controller error category.
#include <codrive/controller/error.hpp>

namespace codrive::controller {
namespace {

class ControllerCategory final : public std::error_category {
public:
    [[nodiscard]] const char* name() const noexcept override { return "codrive.controller"; }
    [[nodiscard]] std::string message(int ev) const override {
        switch (static_cast<ControllerErrc>(ev)) {
        case ControllerErrc::BusFileInvalid:
            return "the bus file is invalid";
        case ControllerErrc::InvalidConfiguration:
            return "invalid controller configuration";
        case ControllerErrc::EventLoopFailed:
            return "cannot create the event loop";
        case ControllerErrc::AlreadyStarted:
            return "the controller was already started";
        case ControllerErrc::BusOpenFailed:
            return "cannot open a CAN bus";
        case ControllerErrc::SegmentFailed:
            return "an EtherCAT segment did not come up";
        case ControllerErrc::StopRequested:
            return "stopped by request during start";
        case ControllerErrc::BootTimeout:
            return "boot-up timed out";
        case ControllerErrc::NodeBootFailed:
            return "a node failed its boot-up";
        case ControllerErrc::SyncFailed:
            return "cannot configure SYNC";
        case ControllerErrc::NotStarted:
            return "the controller is not started";
        case ControllerErrc::NoSuchDevice:
            return "no such bus, node or slave";
        }
        return "unknown controller error";
    }
};

} // namespace

const std::error_category& controller_category() {
    static const ControllerCategory category;
    return category;
}

std::error_code make_error_code(ControllerErrc e) {
    return {static_cast<int>(e), controller_category()};
}

std::string_view to_string(ControllerErrc e) {
    switch (e) {
    case ControllerErrc::BusFileInvalid:
        return "bus_file_invalid";
    case ControllerErrc::InvalidConfiguration:
        return "invalid_configuration";
    case ControllerErrc::EventLoopFailed:
        return "event_loop_failed";
    case ControllerErrc::AlreadyStarted:
        return "already_started";
    case ControllerErrc::BusOpenFailed:
        return "bus_open_failed";
    case ControllerErrc::SegmentFailed:
        return "segment_failed";
    case ControllerErrc::StopRequested:
        return "stop_requested";
    case ControllerErrc::BootTimeout:
        return "boot_timeout";
    case ControllerErrc::NodeBootFailed:
        return "node_boot_failed";
    case ControllerErrc::SyncFailed:
        return "sync_failed";
    case ControllerErrc::NotStarted:
        return "not_started";
    case ControllerErrc::NoSuchDevice:
        return "no_such_device";
    }
    return "unknown";
}

} // namespace codrive::controller
