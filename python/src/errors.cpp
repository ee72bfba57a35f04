// SPDX-License-Identifier: Apache-2.0
// The Python exception classes and the raising of C++ failures as them.
#include "errors.hpp"

#include <chrono>

namespace py = pybind11;

namespace codrive::python {

namespace {
// Borrowed from the module, which keeps them alive for the interpreter's life.
PyObject* g_error = nullptr;
PyObject* g_bus_error = nullptr;
PyObject* g_sdo_error = nullptr;
PyObject* g_sdo_abort = nullptr;
PyObject* g_sdo_timeout = nullptr;
PyObject* g_drive_error = nullptr;

PyObject* make_class(py::module_& m, const char* name, PyObject* base, const char* doc) {
    const std::string qualified = std::string("codrive.") + name;
    PyObject* cls = PyErr_NewExceptionWithDoc(qualified.c_str(), doc, base, nullptr);
    if (cls == nullptr) {
        throw py::error_already_set();
    }
    m.add_object(name, py::handle(cls));
    return cls;
}

[[noreturn]] void raise(PyObject* cls, const std::string& message) {
    PyErr_SetString(cls, message.c_str());
    throw py::error_already_set();
}
} // namespace

void bind_errors(py::module_& m) {
    g_error = make_class(m, "Error", PyExc_Exception,
                         "Base class of every codrive error. Raised by Controller.from_file() "
                         "and Controller.start() with attribute reason: 'bus_file_invalid', "
                         "'node_boot_failed', 'bus_open_failed', ... (docs/controller.md).");
    g_bus_error = make_class(m, "BusError", g_error,
                             "A bus could not be opened or used (the message names the interface "
                             "and the cause).");
    g_sdo_error = make_class(
        m, "SdoError", g_error,
        "An SDO transfer failed. Attributes: node, index, subindex, direction ('upload' or "
        "'download'), protocol ('expedited', 'segmented', 'block' or ''), code (the abort code, "
        "or None). str() is one sentence naming node, object and cause.");
    g_sdo_abort = make_class(m, "SdoAbortError", g_sdo_error,
                             "The transfer ended with an SDO abort frame (CiA 301 §7.2.4.3.17). "
                             "code: the 32-bit abort code; origin: 'server' or 'client'.");
    g_sdo_timeout = make_class(m, "SdoTimeoutError", g_sdo_error,
                               "The node did not answer within the timeout (attribute timeout, "
                               "seconds).");
    g_drive_error = make_class(m, "DriveError", g_error,
                               "A CiA 402 axis operation failed (wrong state, fault, timeout); "
                               "the message names the axis and the cause.");
}

void raise_sdo_error(const sdo::SdoError& e) {
    const auto code = e.abort_code();
    PyObject* cls = g_sdo_error;
    if (code) {
        cls = g_sdo_abort;
    } else if (e.cause == sdo::SdoErrc::Timeout) {
        cls = g_sdo_timeout;
    }
    py::object exc = py::reinterpret_borrow<py::object>(cls)(e.to_string());
    exc.attr("node") = e.node;
    exc.attr("index") = e.index;
    exc.attr("subindex") = e.subindex;
    exc.attr("direction") = std::string(sdo::to_string(e.direction));
    exc.attr("protocol") = std::string(sdo::to_string(e.protocol));
    exc.attr("code") = code ? py::object(py::int_(*code)) : py::object(py::none());
    exc.attr("origin") = e.origin == sdo::AbortOrigin::Server   ? "server"
                         : e.origin == sdo::AbortOrigin::Client ? "client"
                                                                : "";
    exc.attr("timeout") = std::chrono::duration<double>(e.timeout).count();
    PyErr_SetObject(cls, exc.ptr());
    throw py::error_already_set();
}

void raise_bus_error(const std::string& message) {
    raise(g_bus_error, message);
}

void raise_drive_error(const std::string& message) {
    raise(g_drive_error, message);
}

void raise_error(const std::string& message) {
    raise(g_error, message);
}

void raise_controller_error(const controller::ControllerError& e) {
    py::object exc = py::reinterpret_borrow<py::object>(g_error)(e.detail);
    exc.attr("reason") =
        std::string(controller::to_string(static_cast<controller::ControllerErrc>(e.code.value())));
    PyErr_SetObject(g_error, exc.ptr());
    throw py::error_already_set();
}

} // namespace codrive::python
