// SPDX-License-Identifier: Apache-2.0
// The drive error category.
#include <codrive/drives/error.hpp>

namespace codrive::drives {
namespace {

class DriveCategory final : public std::error_category {
public:
    [[nodiscard]] const char* name() const noexcept override { return "codrive.drives"; }
    [[nodiscard]] std::string message(int ev) const override {
        switch (static_cast<DriveErrc>(ev)) {
        case DriveErrc::Timeout:
            return "drive operation timed out";
        case DriveErrc::Fault:
            return "drive fault";
        case DriveErrc::FollowingError:
            return "following error";
        case DriveErrc::HomingError:
            return "homing error";
        case DriveErrc::NotSupported:
            return "not supported by the drive";
        case DriveErrc::WrongState:
            return "wrong CiA 402 state for the operation";
        case DriveErrc::WrongMode:
            return "wrong mode of operation for the operation";
        case DriveErrc::Cancelled:
            return "operation cancelled";
        case DriveErrc::Transport:
            return "object access failed";
        case DriveErrc::NotMapped:
            return "object not mapped into the process image";
        case DriveErrc::InvalidArgument:
            return "invalid argument";
        }
        return "unknown drive error";
    }
};

} // namespace

const std::error_category& drive_category() {
    static const DriveCategory category;
    return category;
}

std::error_code make_error_code(DriveErrc e) {
    return {static_cast<int>(e), drive_category()};
}

} // namespace codrive::drives
