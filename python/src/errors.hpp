// SPDX-License-Identifier: Apache-2.0
// The Python exceptions of codrive (codrive.Error and its subclasses) and how C++ errors map.
#pragma once

#include <codrive/controller/error.hpp>
#include <codrive/sdo/error.hpp>

#include <pybind11/pybind11.h>

#include <string>

namespace codrive::python {

/// Creates codrive.Error, BusError, SdoError, SdoAbortError, SdoTimeoutError, DriveError in `m`.
void bind_errors(pybind11::module_& m);

/// Raises the Python exception for a failed transfer: SdoAbortError (an abort frame ended it),
/// SdoTimeoutError, else SdoError; str() is SdoError::to_string(). Needs the GIL.
[[noreturn]] void raise_sdo_error(const sdo::SdoError& e);
/// Raises codrive.BusError with `message` (a sentence naming the interface and the cause).
[[noreturn]] void raise_bus_error(const std::string& message);
/// Raises codrive.DriveError with `message` (a sentence naming the axis and the cause).
[[noreturn]] void raise_drive_error(const std::string& message);
/// Raises codrive.Error with `message`.
[[noreturn]] void raise_error(const std::string& message);
/// Raises codrive.Error for a failed Controller::from_file()/start(): str() is the detail
/// sentence, attribute `reason` the code's name ("node_boot_failed", controller::to_string()).
[[noreturn]] void raise_controller_error(const controller::ControllerError& e);

} // namespace codrive::python
