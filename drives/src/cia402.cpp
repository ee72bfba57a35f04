// SPDX-License-Identifier: Apache-2.0
// Names of CiA 402 states, commands and modes for messages and decoders.
#include <codrive/drives/cia402.hpp>

#include <fmt/format.h>

namespace codrive::drives::cia402 {

std::string_view to_string(State s) {
    switch (s) {
    case State::NotReadyToSwitchOn:
        return "NOT READY TO SWITCH ON";
    case State::SwitchOnDisabled:
        return "SWITCH ON DISABLED";
    case State::ReadyToSwitchOn:
        return "READY TO SWITCH ON";
    case State::SwitchedOn:
        return "SWITCHED ON";
    case State::OperationEnabled:
        return "OPERATION ENABLED";
    case State::QuickStopActive:
        return "QUICK STOP ACTIVE";
    case State::FaultReactionActive:
        return "FAULT REACTION ACTIVE";
    case State::Fault:
        return "FAULT";
    case State::Unknown:
        break;
    }
    return "UNKNOWN STATE";
}

std::string_view to_string(Command c) {
    switch (c) {
    case Command::Shutdown:
        return "shutdown";
    case Command::SwitchOn:
        return "switch on";
    case Command::SwitchOnAndEnable:
        return "switch on + enable operation";
    case Command::DisableVoltage:
        return "disable voltage";
    case Command::QuickStop:
        return "quick stop";
    case Command::DisableOperation:
        return "disable operation";
    case Command::EnableOperation:
        return "enable operation";
    case Command::FaultReset:
        return "fault reset";
    }
    return "?";
}

std::string mode_name(std::int8_t mode) {
    switch (static_cast<Mode>(mode)) {
    case Mode::NoMode:
        return "no mode";
    case Mode::ProfilePosition:
        return "profile position (PP)";
    case Mode::Velocity:
        return "velocity (VL)";
    case Mode::ProfileVelocity:
        return "profile velocity (PV)";
    case Mode::ProfileTorque:
        return "profile torque (PT)";
    case Mode::Homing:
        return "homing (HM)";
    case Mode::InterpolatedPosition:
        return "interpolated position (IP)";
    case Mode::CyclicSyncPosition:
        return "cyclic synchronous position (CSP)";
    case Mode::CyclicSyncVelocity:
        return "cyclic synchronous velocity (CSV)";
    case Mode::CyclicSyncTorque:
        return "cyclic synchronous torque (CST)";
    }
    return mode < 0 ? fmt::format("manufacturer mode {}", mode) : fmt::format("mode {}", mode);
}

} // namespace codrive::drives::cia402
