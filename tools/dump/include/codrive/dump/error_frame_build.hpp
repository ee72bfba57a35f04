// SPDX-License-Identifier: Apache-2.0
// SocketCAN error frames built from the error and status lines of trace files.
#pragma once

#include <codrive/core/frame.hpp>

#include <cstdint>

namespace codrive::dump {

/// Controller state a trace line reports.
enum class TraceBusState : std::uint8_t { Active, Warning, Passive, BusOff, RxOverflow, Unknown };

/// A SocketCAN error frame (linux/can/error.h layout) for a protocol error seen on the bus, class
/// CAN_ERR_PROT | CAN_ERR_BUSERROR as a Linux CAN driver reports a bus error: `prot` is the
/// CAN_ERR_PROT_* type byte (0: unspecified), `on_tx` marks CAN_ERR_PROT_TX, `location` the
/// CAN_ERR_PROT_LOC_* byte. Error counters (`tec`/`rec` >= 0) are added as CAN_ERR_CNT when known.
[[nodiscard]] Frame protocol_error_frame(std::uint8_t prot, bool on_tx, std::uint8_t location,
                                         int tec = -1, int rec = -1);

/// A protocol error from an SJA1000 error code capture register (Vector ASC `ECC:` and BLF
/// CAN_ERROR_EXT with flag 1): bits 7-6 the type (bit, form, stuff, other), bit 5 the direction
/// (1 receive), bits 4-0 the segment code, which is SocketCAN's CAN_ERR_PROT_LOC_* value.
[[nodiscard]] Frame sja1000_ecc_error_frame(std::uint8_t ecc);

/// A protocol error from Vector's CAN-Core error register (ASC `Flags = 0x2.. Code = ...` and
/// BLF CAN_ERROR_EXT with flag 2): bits 5-0 the error (0 bit, 1 form, 2 stuff, 3 other, 4 CRC,
/// 5 ACK delimiter), bits 7-6 the direction (0 receive NAK, 1 transmit NAK, 2 receive,
/// 3 transmit). A transmit NAK is a missing acknowledge (CAN_ERR_ACK); a receive NAK, which no
/// source explains, is taken as a receive error.
[[nodiscard]] Frame can_core_error_frame(std::uint8_t code);

/// A protocol error of a transmitter that saw no acknowledge: protocol_error_frame() with
/// CAN_ERR_ACK, at the ACK slot unless `location` says otherwise.
[[nodiscard]] Frame no_ack_error_frame(std::uint8_t prot, bool on_tx, std::uint8_t location);

/// A SocketCAN error frame for a controller state (CAN_ERR_CRTL / CAN_ERR_BUSOFF).
[[nodiscard]] Frame state_error_frame(TraceBusState state, int tec = -1, int rec = -1);

/// The state error counters put the controller in (ISO 11898-1: passive from 128, warning from
/// 96 as SocketCAN and PEAK report it).
[[nodiscard]] TraceBusState state_from_counters(int tec, int rec);

} // namespace codrive::dump
