// SPDX-License-Identifier: Apache-2.0
// CiA 402 (IEC 61800-7-201) constants shared by the master-side axis model and the simulated
// drives: object indexes, statusword/controlword bits, states, commands, transitions and modes.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <string_view>

namespace codrive::drives::cia402 {

/// Object indexes of axis 1. Axis n of a multi-axis device adds the profile's axis offset
/// (AKD2G: 0x800 per axis).
namespace obj {
inline constexpr std::uint16_t kErrorCode = 0x603F;
inline constexpr std::uint16_t kControlword = 0x6040;
inline constexpr std::uint16_t kStatusword = 0x6041;
inline constexpr std::uint16_t kQuickStopOption = 0x605A;
inline constexpr std::uint16_t kShutdownOption = 0x605B;
inline constexpr std::uint16_t kDisableOperationOption = 0x605C;
inline constexpr std::uint16_t kHaltOption = 0x605D;
inline constexpr std::uint16_t kFaultReactionOption = 0x605E;
inline constexpr std::uint16_t kModesOfOperation = 0x6060;
inline constexpr std::uint16_t kModesOfOperationDisplay = 0x6061;
inline constexpr std::uint16_t kPositionDemand = 0x6062;
inline constexpr std::uint16_t kPositionActual = 0x6064;
inline constexpr std::uint16_t kFollowingErrorWindow = 0x6065;
inline constexpr std::uint16_t kFollowingErrorTimeout = 0x6066;
inline constexpr std::uint16_t kPositionWindow = 0x6067;
inline constexpr std::uint16_t kPositionWindowTime = 0x6068;
inline constexpr std::uint16_t kVelocityDemand = 0x606B;
inline constexpr std::uint16_t kVelocityActual = 0x606C;
inline constexpr std::uint16_t kTargetTorque = 0x6071;
inline constexpr std::uint16_t kMaxTorque = 0x6072;
inline constexpr std::uint16_t kTorqueActual = 0x6077;
inline constexpr std::uint16_t kTargetPosition = 0x607A;
inline constexpr std::uint16_t kHomeOffset = 0x607C;
inline constexpr std::uint16_t kSoftwarePositionLimit = 0x607D;
inline constexpr std::uint16_t kPolarity = 0x607E;
inline constexpr std::uint16_t kMaxProfileVelocity = 0x607F;
inline constexpr std::uint16_t kProfileVelocity = 0x6081;
inline constexpr std::uint16_t kProfileAcceleration = 0x6083;
inline constexpr std::uint16_t kProfileDeceleration = 0x6084;
inline constexpr std::uint16_t kQuickStopDeceleration = 0x6085;
inline constexpr std::uint16_t kMotionProfileType = 0x6086;
inline constexpr std::uint16_t kTorqueSlope = 0x6087;
inline constexpr std::uint16_t kPositionEncoderResolution = 0x608F;
inline constexpr std::uint16_t kGearRatio = 0x6091;
inline constexpr std::uint16_t kFeedConstant = 0x6092;
inline constexpr std::uint16_t kVelocityFactor = 0x6096;
inline constexpr std::uint16_t kAccelerationFactor = 0x6097;
inline constexpr std::uint16_t kHomingMethod = 0x6098;
inline constexpr std::uint16_t kHomingSpeeds = 0x6099;
inline constexpr std::uint16_t kHomingAcceleration = 0x609A;
inline constexpr std::uint16_t kSiUnitPosition = 0x60A8;
inline constexpr std::uint16_t kSiUnitVelocity = 0x60A9;
inline constexpr std::uint16_t kPositionOffset = 0x60B0;
inline constexpr std::uint16_t kVelocityOffset = 0x60B1;
inline constexpr std::uint16_t kTorqueOffset = 0x60B2;
inline constexpr std::uint16_t kInterpolationDataRecord = 0x60C1;
inline constexpr std::uint16_t kInterpolationTimePeriod = 0x60C2;
inline constexpr std::uint16_t kFollowingErrorActual = 0x60F4;
inline constexpr std::uint16_t kDigitalInputs = 0x60FD;
inline constexpr std::uint16_t kTargetVelocity = 0x60FF;
inline constexpr std::uint16_t kSupportedDriveModes = 0x6502;
} // namespace obj

/// Statusword bits (CiA 402 §6.2 / object 6041h).
namespace sw {
inline constexpr std::uint16_t kReadyToSwitchOn = 1U << 0;
inline constexpr std::uint16_t kSwitchedOn = 1U << 1;
inline constexpr std::uint16_t kOperationEnabled = 1U << 2;
inline constexpr std::uint16_t kFault = 1U << 3;
inline constexpr std::uint16_t kVoltageEnabled = 1U << 4;
inline constexpr std::uint16_t kQuickStop = 1U << 5; ///< 0 = quick stop active
inline constexpr std::uint16_t kSwitchOnDisabled = 1U << 6;
inline constexpr std::uint16_t kWarning = 1U << 7;
inline constexpr std::uint16_t kManufacturer8 = 1U << 8;
inline constexpr std::uint16_t kRemote = 1U << 9;
inline constexpr std::uint16_t kTargetReached = 1U << 10;
inline constexpr std::uint16_t kInternalLimit = 1U << 11;
inline constexpr std::uint16_t kOpMode12 = 1U << 12; ///< PP set-point ack, PV speed zero,
                                                     ///< HM homing attained, CSx target ignored
inline constexpr std::uint16_t kOpMode13 = 1U << 13; ///< PP/CSP following error, HM homing error
} // namespace sw

/// Controlword bits (object 6040h).
namespace cw {
inline constexpr std::uint16_t kSwitchOn = 1U << 0;
inline constexpr std::uint16_t kEnableVoltage = 1U << 1;
inline constexpr std::uint16_t kQuickStop = 1U << 2; ///< 0 = quick stop
inline constexpr std::uint16_t kEnableOperation = 1U << 3;
inline constexpr std::uint16_t kOpMode4 = 1U << 4; ///< PP new set-point, HM start homing
inline constexpr std::uint16_t kOpMode5 = 1U << 5; ///< PP change set immediately
inline constexpr std::uint16_t kOpMode6 = 1U << 6; ///< PP relative
inline constexpr std::uint16_t kFaultReset = 1U << 7;
inline constexpr std::uint16_t kHalt = 1U << 8;
inline constexpr std::uint16_t kOpMode9 = 1U << 9; ///< PP change on set-point
/// Bits that select the device control command.
inline constexpr std::uint16_t kCommandMask = 0x008F;
} // namespace cw

/// The states of the CiA 402 power state machine.
enum class State : std::uint8_t {
    NotReadyToSwitchOn,
    SwitchOnDisabled,
    ReadyToSwitchOn,
    SwitchedOn,
    OperationEnabled,
    QuickStopActive,
    FaultReactionActive,
    Fault,
    Unknown, ///< statusword pattern matches no state
};

/// Decodes the state from statusword bits 0–3, 5, 6 (CiA 402 table "state coding").
[[nodiscard]] constexpr State decode_state(std::uint16_t statusword) {
    if ((statusword & 0x4F) == 0x00) {
        return State::NotReadyToSwitchOn;
    }
    if ((statusword & 0x4F) == 0x40) {
        return State::SwitchOnDisabled;
    }
    if ((statusword & 0x6F) == 0x21) {
        return State::ReadyToSwitchOn;
    }
    if ((statusword & 0x6F) == 0x23) {
        return State::SwitchedOn;
    }
    if ((statusword & 0x6F) == 0x27) {
        return State::OperationEnabled;
    }
    if ((statusword & 0x6F) == 0x07) {
        return State::QuickStopActive;
    }
    if ((statusword & 0x4F) == 0x0F) {
        return State::FaultReactionActive;
    }
    if ((statusword & 0x4F) == 0x08) {
        return State::Fault;
    }
    return State::Unknown;
}

/// The statusword bits 0–3, 5, 6 a device reports in `state` (the inverse of decode_state).
[[nodiscard]] constexpr std::uint16_t state_bits(State s) {
    switch (s) {
    case State::NotReadyToSwitchOn:
        return 0x00;
    case State::SwitchOnDisabled:
        return 0x40;
    case State::ReadyToSwitchOn:
        return 0x21;
    case State::SwitchedOn:
        return 0x23;
    case State::OperationEnabled:
        return 0x27;
    case State::QuickStopActive:
        return 0x07;
    case State::FaultReactionActive:
        return 0x0F;
    case State::Fault:
        return 0x08;
    case State::Unknown:
        break;
    }
    return 0x00;
}

/// Device control commands (controlword bits 0–3 and 7).
enum class Command : std::uint8_t {
    Shutdown,          ///< transitions 2, 6, 8
    SwitchOn,          ///< transition 3
    SwitchOnAndEnable, ///< transitions 3 + 4
    DisableVoltage,    ///< transitions 7, 9, 10, 12
    QuickStop,         ///< transitions 7, 10, 11
    DisableOperation,  ///< transition 5
    EnableOperation,   ///< transitions 4, 16
    FaultReset,        ///< transition 15 (on the rising edge of bit 7)
};

/// Controlword command bits for a command (bits outside kCommandMask are 0).
[[nodiscard]] constexpr std::uint16_t command_bits(Command c) {
    switch (c) {
    case Command::Shutdown:
        return 0x0006;
    case Command::SwitchOn:
    case Command::DisableOperation:
        return 0x0007;
    case Command::SwitchOnAndEnable:
    case Command::EnableOperation:
        return 0x000F;
    case Command::DisableVoltage:
        return 0x0000;
    case Command::QuickStop:
        return 0x0002;
    case Command::FaultReset:
        return 0x0080;
    }
    return 0;
}

/// Which command controlword bits 0–3, 7 express (fault reset wins while bit 7 is set). The
/// device side of the state machine uses this; "don't care" bits follow CiA 402 table 41.
[[nodiscard]] constexpr std::optional<Command> decode_command(std::uint16_t controlword) {
    if ((controlword & cw::kFaultReset) != 0) {
        return Command::FaultReset;
    }
    if ((controlword & cw::kEnableVoltage) == 0) {
        return Command::DisableVoltage;
    }
    if ((controlword & cw::kQuickStop) == 0) {
        return Command::QuickStop;
    }
    switch (controlword & 0x0F) {
    case 0x06:
    case 0x0E:
        return Command::Shutdown;
    case 0x07:
        return Command::SwitchOn; // also "disable operation" from Operation Enabled
    case 0x0F:
        return Command::EnableOperation; // also "switch on + enable" from Ready to Switch On
    default:
        return std::nullopt;
    }
}

/// Modes of operation (6060h / 6061h); manufacturer modes are negative.
enum class Mode : std::int8_t {
    NoMode = 0,
    ProfilePosition = 1,
    Velocity = 2,
    ProfileVelocity = 3,
    ProfileTorque = 4,
    Homing = 6,
    InterpolatedPosition = 7,
    CyclicSyncPosition = 8,
    CyclicSyncVelocity = 9,
    CyclicSyncTorque = 10,
};

/// Bit of 6502h (supported drive modes) for a standard mode, or 0 for others.
[[nodiscard]] constexpr std::uint32_t supported_mode_bit(Mode m) {
    switch (m) {
    case Mode::ProfilePosition:
        return 1U << 0;
    case Mode::Velocity:
        return 1U << 1;
    case Mode::ProfileVelocity:
        return 1U << 2;
    case Mode::ProfileTorque:
        return 1U << 3;
    case Mode::Homing:
        return 1U << 5;
    case Mode::InterpolatedPosition:
        return 1U << 6;
    case Mode::CyclicSyncPosition:
        return 1U << 7;
    case Mode::CyclicSyncVelocity:
        return 1U << 8;
    case Mode::CyclicSyncTorque:
        return 1U << 9;
    case Mode::NoMode:
        break;
    }
    return 0;
}

/// "SWITCH ON DISABLED", "OPERATION ENABLED", ... (upper case as in CiA 402 figures).
[[nodiscard]] std::string_view to_string(State s);
/// "shutdown", "switch on", "enable operation", ...
[[nodiscard]] std::string_view to_string(Command c);
/// "profile position (PP)", "cyclic synchronous position (CSP)", or "manufacturer mode -3".
[[nodiscard]] std::string mode_name(std::int8_t mode);

} // namespace codrive::drives::cia402
