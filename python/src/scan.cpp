// SPDX-License-Identifier: Apache-2.0
// bus.scan(): the master's network scan (1000h probe of every node, then identity and name).
#include "module.hpp"
#include "wait.hpp"

#include <codrive/master/network_scan.hpp>
#include <codrive/nmt/state.hpp>

namespace py = pybind11;

namespace codrive::python {

namespace {

py::object optional_int(const std::optional<std::uint32_t>& v) {
    return v ? py::object(py::int_(*v)) : py::object(py::none());
}

py::list scan(const std::shared_ptr<Bus>& bus, long first, long last, double timeout) {
    if (first < 1 || last > kMaxNodeId || first > last) {
        throw py::value_error("scan range " + std::to_string(first) + ".." + std::to_string(last) +
                              " is not within 1..127");
    }
    master::ScanOptions options;
    options.first = static_cast<NodeId>(first);
    options.last = static_cast<NodeId>(last);
    options.timeout = std::chrono::duration_cast<milliseconds>(seconds_arg(timeout, "timeout"));
    std::unique_ptr<master::NetworkScan> scanner;
    const auto rows = wait_for_result<std::vector<master::ScanRow>>(*bus, [&](auto done) {
        scanner = std::make_unique<master::NetworkScan>(bus->sdo_clients(), &bus->nmt().states(),
                                                        options);
        scanner->start(std::move(done));
    });
    with_bus(*bus, [&] {
        scanner.reset();
        return 0;
    });
    py::list out;
    for (const auto& r : rows) {
        py::dict d;
        d["node"] = r.node;
        d["state"] = std::string(nmt::to_string(r.state));
        d["device_type"] = r.device_type;
        d["vendor_id"] = optional_int(r.vendor_id);
        d["product_code"] = optional_int(r.product_code);
        d["revision"] = optional_int(r.revision);
        d["serial"] = optional_int(r.serial);
        d["name"] = r.name;
        out.append(d);
    }
    return out;
}

} // namespace

void bind_scan(py::module_& /*m*/, PyBusClass& bus) {
    bus.def("scan", &scan, py::arg("first") = 1, py::arg("last") = 127, py::arg("timeout") = 0.3,
            "Finds the nodes first..last (the master's NetworkScan, as `codrive scan`): probes "
            "1000h of every node in parallel, then reads identity (1018h) and name (1008h) of "
            "those that answered. Returns one dict per node found: node, state, device_type, "
            "vendor_id, product_code, revision, serial, name. timeout: seconds per request.");
}

} // namespace codrive::python
