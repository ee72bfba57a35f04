// SPDX-License-Identifier: Apache-2.0
// Active faults and warnings of a simulated drive: 1001h, histories, emergencies.
#include <codrive/sim/active_errors.hpp>

#include "error_history.hpp"

#include <algorithm>

namespace codrive::sim {

emcy::EmcyMessage ActiveErrors::raise(const FaultCode& code, int axis, bool warning) {
    const bool known = std::any_of(errors_.begin(), errors_.end(), [&](const Entry& e) {
        return e.code == code.emcy && e.axis == axis;
    });
    if (!known) {
        errors_.push_back({code.emcy, code.error_register, axis, warning});
    }
    const std::uint8_t reg = update_register();
    // History: AKD2G 1003h keeps the first four EMCY bytes (AMB-7), FIO its error number,
    // class and code (§7.13.3), DS-BVS 4080h the code.
    record_error_history(od_, profile_, code, reg);
    emcy::EmcyMessage m;
    m.error_code = code.emcy;
    m.error_register = reg; // manufacturer bytes zero: none documented
    return m;
}

std::optional<emcy::EmcyMessage> ActiveErrors::clear(int axis, bool warnings_only,
                                                     std::uint16_t code) {
    const auto before = errors_.size();
    std::erase_if(errors_, [&](const Entry& e) {
        if (e.axis != axis) {
            return false;
        }
        if (code != 0) {
            return e.code == code;
        }
        return warnings_only ? e.warning : !e.warning;
    });
    const std::uint8_t reg = update_register();
    if (before != 0 && errors_.empty()) {
        emcy::EmcyMessage m; // 0000h: error reset or no error
        m.error_register = reg;
        return m;
    }
    return std::nullopt;
}

std::optional<emcy::EmcyMessage> ActiveErrors::on_axis_event(const AxisEvent& e) {
    const int axis = static_cast<int>(e.axis);
    switch (e.kind) {
    case AxisEvent::Kind::FaultRaised:
        return raise(e.code, axis, false);
    case AxisEvent::Kind::WarningRaised:
        return raise(e.code, axis, true);
    case AxisEvent::Kind::WarningCleared:
        return clear(axis, true, e.code.emcy);
    case AxisEvent::Kind::FaultsCleared:
        return clear(axis, false);
    }
    return std::nullopt;
}

void ActiveErrors::reset() {
    errors_.clear();
    update_register();
}

std::uint8_t ActiveErrors::update_register() {
    std::uint8_t reg = 0;
    for (const Entry& e : errors_) {
        reg = static_cast<std::uint8_t>(reg | e.reg | 0x01);
    }
    if (profile_.error_register_generic_only) {
        reg = reg != 0 ? 0x01 : 0x00; // AKD2G: only bit 0 is used
    }
    od_.set<std::uint8_t>(0x1001, 0, reg);
    return reg;
}

} // namespace codrive::sim
