// SPDX-License-Identifier: Apache-2.0
// The PDO error category.
#include <codrive/pdo/error.hpp>

namespace codrive::pdo {
namespace {

class PdoCategory final : public std::error_category {
public:
    const char* name() const noexcept override { return "pdo"; }
    std::string message(int ev) const override {
        switch (static_cast<PdoErrc>(ev)) {
        case PdoErrc::InvalidMapping:
            return "invalid PDO mapping";
        case PdoErrc::LengthExceeded:
            return "PDO length exceeded";
        case PdoErrc::InvalidCommunication:
            return "invalid PDO communication parameter";
        case PdoErrc::UnsupportedByDevice:
            return "not supported by the device";
        case PdoErrc::SdoFailed:
            return "SDO transfer failed";
        case PdoErrc::UnknownObject:
            return "object is not mapped";
        case PdoErrc::UnknownNode:
            return "unknown node";
        case PdoErrc::AlreadyConfigured:
            return "node already configured";
        case PdoErrc::TooManyPdos:
            return "too many PDOs";
        }
        return "unknown PDO error";
    }
};

} // namespace

const std::error_category& pdo_category() {
    static const PdoCategory category;
    return category;
}

std::error_code make_error_code(PdoErrc e) {
    return {static_cast<int>(e), pdo_category()};
}

} // namespace codrive::pdo
