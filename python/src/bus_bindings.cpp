// SPDX-License-Identifier: Apache-2.0
// codrive.Bus (SocketCAN) and codrive.VirtualNetwork (in-process, simulated time) for Python.
#include "errors.hpp"
#include "module.hpp"
#include "wait.hpp"

#include <cmath>

namespace py = pybind11;

namespace codrive::python {

Duration seconds_arg(double seconds, const char* what) {
    if (!std::isfinite(seconds) || seconds < 0 || seconds > 1e6) {
        throw py::value_error(std::string(what) + " must be 0..1e6 seconds, got " +
                              std::to_string(seconds));
    }
    return std::chrono::duration_cast<Duration>(std::chrono::duration<double>(seconds));
}

void bind_bus(py::module_& m, PyBusClass& bus) {
    bus.def(py::init([](const std::string& ifname, double timeout) -> std::shared_ptr<Bus> {
                const Duration t = seconds_arg(timeout, "timeout");
                auto b = SocketBus::open(ifname, t);
                if (!b) {
                    raise_bus_error(b.error());
                }
                return *b;
            }),
            py::arg("interface"), py::arg("timeout") = 1.0,
            "Opens a SocketCAN interface (\"vcan0\", \"can0\"). timeout: the default SDO "
            "response timeout in seconds. Raises BusError with the reason and what to do.")
        .def_property_readonly("name", &Bus::name, "Interface name, or \"virtual\".")
        .def(
            "run_for",
            [](Bus& self, double seconds) {
                const Duration d = seconds_arg(seconds, "run_for");
                with_bus(self, [&] { return self.run_until([] { return false; }, d); });
            },
            py::arg("seconds"),
            "Runs the bus for `seconds` (receiving heartbeats, boot-ups, ...); on a "
            "VirtualNetwork the time is simulated and passes at once.")
        .def("__repr__", [](const Bus& self) { return "<codrive.Bus " + self.name() + ">"; });

    py::class_<VirtualNet, Bus, std::shared_ptr<VirtualNet>>(
        m, "VirtualNetwork",
        "An in-process CAN network on simulated time, for tests without vcan: the master's "
        "endpoint plus the simulated drives added with codrive.sim.VirtualDrive. Waiting "
        "advances the clock straight to the next event, so a test runs as fast as the CPU "
        "allows and repeats exactly; timeouts are simulated seconds.")
        .def(py::init([](double timeout) {
                 return std::make_shared<VirtualNet>(seconds_arg(timeout, "timeout"));
             }),
             py::arg("timeout") = 1.0, "timeout: the default SDO response timeout (seconds).")
        .def_property_readonly(
            "time", [](VirtualNet& self) { return with_bus(self, [&] { return self.seconds(); }); },
            "Simulated seconds since the network was made.")
        .def("__repr__", [](VirtualNet& self) {
            return "<codrive.VirtualNetwork t=" +
                   std::to_string(with_bus(self, [&] { return self.seconds(); })) + "s>";
        });
}

} // namespace codrive::python
