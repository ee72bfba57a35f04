// SPDX-License-Identifier: Apache-2.0
// codrive._native: the pybind11 extension behind the `codrive` Python package.
#include "module.hpp"
#include "errors.hpp"
#include "interrupt.hpp"

namespace py = pybind11;

PYBIND11_MODULE(_native, m) {
    using namespace codrive::python;
    m.doc() = "codrive's C++ stack for Python (import codrive, not this module).";
    m.attr("__version__") = CODRIVE_VERSION;
    bind_errors(m);
    PyBusClass bus(m, "Bus",
                   "A CAN bus with the master's SDO clients and NMT master on it: "
                   "codrive.Bus(\"vcan0\") opens SocketCAN; codrive.VirtualNetwork() is the "
                   "in-process one.");
    bind_bus(m, bus);
    bind_sdo(m, bus);
    bind_nmt(m, bus);
    bind_scan(m, bus);
    bind_sim(m);
    bind_eds(m);
    bind_dump(m);
    bind_controller(m);
    bind_timer_latency(m);
    install_sigint_relay();
}
