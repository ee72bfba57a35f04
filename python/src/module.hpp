// SPDX-License-Identifier: Apache-2.0
// The parts of the codrive._native module, each bound by its own file.
#pragma once

#include "bus.hpp"

#include <pybind11/pybind11.h>

#include <memory>

namespace codrive::python {

using PyBusClass = pybind11::class_<Bus, std::shared_ptr<Bus>>;

void bind_bus(pybind11::module_& m, PyBusClass& bus);  ///< bus.cpp's classes: Bus, VirtualNetwork
void bind_sdo(pybind11::module_& m, PyBusClass& bus);  ///< bus.sdo(node)
void bind_nmt(pybind11::module_& m, PyBusClass& bus);  ///< bus.nmt
void bind_scan(pybind11::module_& m, PyBusClass& bus); ///< bus.scan()
void bind_sim(pybind11::module_& m);                   ///< sim.VirtualDrive
void bind_eds(pybind11::module_& m);                   ///< eds.load
void bind_dump(pybind11::module_& m);                  ///< dump.read
void bind_controller(pybind11::module_& m);            ///< Controller, Axis
void bind_timer_latency(pybind11::module_& m);         ///< measure_timer_latency

} // namespace codrive::python
