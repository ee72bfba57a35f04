// SPDX-License-Identifier: Apache-2.0
// SocketCAN error frames built from the error and status lines of trace files.
#pragma once

#include <codrive/core/frame.hpp>

#include <cstdint>

namespace codrive::dump {

/// Controller state a trace line reports.
enum class TraceBusState : std::uint8_t { Active, Warning, Passive, BusOff, RxOverflow, Unknown };

/// A SocketCAN error frame (linux/can/error.h layout) for a protocol error seen on the bus:
/// `prot` is the CAN_ERR_PROT_* type byte (0: unspecified), `on_tx` marks CAN_ERR_PROT_TX,
/// `location` the CAN_ERR_PROT_LOC_* byte. Error counters (`tec`/`rec` >= 0) are added as
/// CAN_ERR_CNT when known.
[[nodiscard]] Frame protocol_error_frame(std::uint8_t prot, bool on_tx, std::uint8_t location,
                                         int tec = -1, int rec = -1);

/// A SocketCAN error frame for a controller state (CAN_ERR_CRTL / CAN_ERR_BUSOFF).
[[nodiscard]] Frame state_error_frame(TraceBusState state, int tec = -1, int rec = -1);

/// The state error counters put the controller in (ISO 11898-1: passive from 128, warning from
/// 96 as SocketCAN and PEAK report it).
[[nodiscard]] TraceBusState state_from_counters(int tec, int rec);

} // namespace codrive::dump
