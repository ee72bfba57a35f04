// SPDX-License-Identifier: Apache-2.0
// bus.nmt: NMT module control (CiA 301 §7.2.8.3.1) and the node states heard on the bus.
#include "errors.hpp"
#include "module.hpp"
#include "wait.hpp"

#include <codrive/nmt/state.hpp>

namespace py = pybind11;

namespace codrive::python {

namespace {

NodeId node_arg(long node, bool allow_all) {
    if (node < (allow_all ? 0 : 1) || node > kMaxNodeId) {
        throw py::value_error("NMT node id " + std::to_string(node) + " is not " +
                              (allow_all ? "0 (all nodes) or " : "") + "1..127");
    }
    return static_cast<NodeId>(node);
}

/// bus.nmt: the NMT master of the bus.
class NmtProxy {
public:
    explicit NmtProxy(std::shared_ptr<Bus> bus) : bus_(std::move(bus)) {}

    void send(nmt::NmtCommand command, long node) {
        const NodeId n = node_arg(node, true);
        const auto r = with_bus(*bus_, [&] {
            auto sent = bus_->nmt().send(command, n);
            // Let the frame leave and what is already waiting arrive.
            (void)bus_->run_until([] { return true; }, Duration{0});
            return sent;
        });
        if (!r) {
            raise_bus_error(std::string("NMT ") + std::string(nmt::to_string(command)) +
                            " to node " + std::to_string(n) + " on " + bus_->name() +
                            " failed: " + r.error().message());
        }
    }

    std::string state(long node) {
        const NodeId n = node_arg(node, false);
        return with_bus(*bus_, [&] {
            (void)bus_->run_until([] { return true; }, Duration{0});
            return std::string(nmt::to_string(bus_->nmt().states().state(n)));
        });
    }

    bool wait_for_state(long node, const std::string& state, double timeout) {
        const NodeId n = node_arg(node, false);
        const Duration t = seconds_arg(timeout, "timeout");
        return with_bus(*bus_, [&] {
            const auto holds = [&] {
                return nmt::to_string(bus_->nmt().states().state(n)) == state;
            };
            return bus_->run_until(holds, t);
        });
    }

    std::uint32_t boot_ups(long node) {
        const NodeId n = node_arg(node, false);
        return with_bus(*bus_, [&] {
            (void)bus_->run_until([] { return true; }, Duration{0});
            return bus_->nmt().states().entry(n).boot_ups;
        });
    }

private:
    std::shared_ptr<Bus> bus_;
};

} // namespace

void bind_nmt(py::module_& m, PyBusClass& bus) {
    py::class_<NmtProxy>(m, "Nmt",
                         "NMT master of a bus (bus.nmt). Node 0 addresses every node. States "
                         "are what the nodes' boot-up and heartbeat messages reported: "
                         "'boot-up', 'stopped', 'operational', 'pre-operational', 'unknown'.")
        .def(
            "start", [](NmtProxy& s, long n) { s.send(nmt::NmtCommand::Start, n); },
            py::arg("node"), "Start remote node (to OPERATIONAL).")
        .def(
            "stop", [](NmtProxy& s, long n) { s.send(nmt::NmtCommand::Stop, n); }, py::arg("node"),
            "Stop remote node (to STOPPED).")
        .def(
            "pre_operational",
            [](NmtProxy& s, long n) { s.send(nmt::NmtCommand::EnterPreOperational, n); },
            py::arg("node"), "Enter PRE-OPERATIONAL.")
        .def(
            "reset", [](NmtProxy& s, long n) { s.send(nmt::NmtCommand::ResetNode, n); },
            py::arg("node"), "Reset node (application and communication; a boot-up follows).")
        .def(
            "reset_communication",
            [](NmtProxy& s, long n) { s.send(nmt::NmtCommand::ResetCommunication, n); },
            py::arg("node"), "Reset communication (a boot-up follows).")
        .def("state", &NmtProxy::state, py::arg("node"),
             "The last state `node` reported ('unknown' if none).")
        .def("wait_for_state", &NmtProxy::wait_for_state, py::arg("node"), py::arg("state"),
             py::arg("timeout") = 1.0,
             "Runs the bus until `node` reports `state` (e.g. 'pre-operational' after a "
             "reset); False if it did not within `timeout` seconds.")
        .def("boot_ups", &NmtProxy::boot_ups, py::arg("node"),
             "How many boot-up messages `node` sent since the bus was opened.");
    bus.def_property_readonly(
        "nmt", [](const std::shared_ptr<Bus>& self) { return NmtProxy(self); },
        "The NMT master of this bus.");
}

} // namespace codrive::python
