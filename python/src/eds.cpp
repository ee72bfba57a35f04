// SPDX-License-Identifier: Apache-2.0
// codrive.eds: EDS/DCF files (CiA 306) through the core parser: objects by index or name, lint
// findings as objects.
#include "errors.hpp"
#include "module.hpp"

#include <codrive/core/eds.hpp>

#include <pybind11/stl.h>

#include <algorithm>
#include <cctype>
#include <cerrno>

namespace py = pybind11;

namespace codrive::python {

namespace {

/// A value as Python sees it: int for integer types, float for reals, str for visible and
/// unicode strings, bytes for octet strings and domains.
py::object value_to_python(const Value& v) {
    const DataType t = v.type();
    if (t == DataType::VisibleString || t == DataType::UnicodeString) {
        const auto b = v.bytes();
        return py::reinterpret_steal<py::object>(PyUnicode_DecodeUTF8(
            reinterpret_cast<const char*>(b.data()), static_cast<Py_ssize_t>(b.size()), "replace"));
    }
    if (t == DataType::Real32 || t == DataType::Real64) {
        if (auto d = v.as_double()) {
            return py::float_(*d);
        }
    } else if (t == DataType::Boolean || t == DataType::Integer8 || t == DataType::Integer16 ||
               t == DataType::Integer24 || t == DataType::Integer32 || t == DataType::Integer40 ||
               t == DataType::Integer48 || t == DataType::Integer56 || t == DataType::Integer64) {
        if (auto i = v.as_int()) {
            return py::int_(*i);
        }
    } else if (auto u = v.as_uint()) {
        return py::int_(*u);
    }
    const auto b = v.bytes();
    return py::bytes(reinterpret_cast<const char*>(b.data()), b.size());
}

py::object optional_value(const std::optional<Value>& v) {
    return v ? value_to_python(*v) : py::none();
}

bool same_name(const std::string& a, const std::string& b) {
    return a.size() == b.size() && std::equal(a.begin(), a.end(), b.begin(), [](char x, char y) {
               return std::tolower(static_cast<unsigned char>(x)) ==
                      std::tolower(static_cast<unsigned char>(y));
           });
}

/// A loaded file; the objects handed out keep it alive.
struct Eds {
    DeviceDescription desc;
    std::string path;

    const Object& object(const py::object& key) const {
        if (py::isinstance<py::int_>(key)) {
            const long index = key.cast<long>();
            const Object* o = index >= 0 && index <= 0xFFFF
                                  ? desc.od.find(static_cast<std::uint16_t>(index))
                                  : nullptr;
            if (o == nullptr) {
                char buf[80];
                std::snprintf(buf, sizeof buf, "%s has no object 0x%04lX", path.c_str(), index);
                throw py::key_error(buf);
            }
            return *o;
        }
        const std::string name = key.cast<std::string>();
        for (const auto& [index, o] : desc.od.objects()) {
            if (same_name(o.name, name)) {
                return o;
            }
        }
        throw py::key_error(path + " has no object named '" + name + "'");
    }
};

const SubObject& sub_of(const Object& o, const py::object& key, const std::string& path) {
    if (py::isinstance<py::int_>(key)) {
        const long sub = key.cast<long>();
        const SubObject* s =
            sub >= 0 && sub <= 0xFF ? o.find(static_cast<std::uint8_t>(sub)) : nullptr;
        if (s == nullptr) {
            char buf[120];
            std::snprintf(buf, sizeof buf, "%s: object 0x%04X has no sub-index %ld", path.c_str(),
                          o.index, sub);
            throw py::key_error(buf);
        }
        return *s;
    }
    const std::string name = key.cast<std::string>();
    for (const auto& [i, s] : o.subs) {
        if (same_name(s.name, name)) {
            return s;
        }
    }
    char buf[80];
    std::snprintf(buf, sizeof buf, ": object 0x%04X has no sub-object named '", o.index);
    throw py::key_error(path + buf + name + "'");
}

std::string hex_index(std::uint16_t index) {
    char buf[8];
    std::snprintf(buf, sizeof buf, "0x%04X", index);
    return buf;
}

} // namespace

void bind_eds(py::module_& m) {
    py::module_ e = m.def_submodule("eds", "EDS/DCF device descriptions (CiA 306).");

    py::class_<EdsFinding>(e, "Finding", "One problem the parser found in a file.")
        .def_readonly("file", &EdsFinding::file)
        .def_readonly("line", &EdsFinding::line, "1-based line (0: the file as a whole).")
        .def_property_readonly(
            "severity", [](const EdsFinding& f) { return std::string(to_string(f.severity)); },
            "'info', 'warning' or 'error'.")
        .def_readonly("message", &EdsFinding::message)
        .def("__str__", &format_finding, "FILE:LINE: severity: message")
        .def("__repr__",
             [](const EdsFinding& f) { return "<codrive.eds.Finding " + format_finding(f) + ">"; });

    py::class_<SubObject>(e, "SubObject", "A sub-object (a VAR is its own sub-index 0).")
        .def_readonly("subindex", &SubObject::subindex)
        .def_readonly("name", &SubObject::name)
        .def_property_readonly(
            "type", [](const SubObject& s) { return std::string(to_string(s.type)); },
            "The CiA 301 data type name, e.g. 'UNSIGNED32'.")
        .def_property_readonly(
            "access", [](const SubObject& s) { return std::string(to_string(s.access)); },
            "'ro', 'wo', 'rw', 'rwr', 'rww' or 'const'.")
        .def_readonly("pdo_mappable", &SubObject::pdo_mappable)
        .def_property_readonly(
            "value", [](const SubObject& s) { return value_to_python(s.value); },
            "The value (DefaultValue, or a DCF's ParameterValue).")
        .def_property_readonly("default",
                               [](const SubObject& s) { return optional_value(s.default_value); })
        .def_property_readonly("low_limit",
                               [](const SubObject& s) { return optional_value(s.low_limit); })
        .def_property_readonly("high_limit",
                               [](const SubObject& s) { return optional_value(s.high_limit); })
        .def_readonly("default_text", &SubObject::default_text,
                      "DefaultValue as written (may use $NODEID).")
        .def("__repr__", [](const SubObject& s) {
            return "<codrive.eds.SubObject " + std::to_string(s.subindex) + " '" + s.name + "' " +
                   std::string(to_string(s.type)) + " " + std::string(to_string(s.access)) + ">";
        });

    py::class_<Object>(e, "Object", "An object (index) with its sub-objects.")
        .def_readonly("index", &Object::index)
        .def_readonly("name", &Object::name)
        .def_property_readonly(
            "code", [](const Object& o) { return std::string(to_string(o.code)); },
            "'VAR', 'ARRAY', 'RECORD', ...")
        .def_property_readonly(
            "subs",
            [](const Object& o) {
                py::list l;
                for (const auto& [i, s] : o.subs) {
                    l.append(py::cast(&s, py::return_value_policy::reference));
                }
                return l;
            },
            py::keep_alive<0, 1>(), "Sub-objects in sub-index order.")
        .def(
            "__getitem__",
            [](const Object& o, const py::object& key) -> const SubObject& {
                return sub_of(o, key, "object " + hex_index(o.index));
            },
            py::return_value_policy::reference_internal, py::arg("key"),
            "A sub-object by sub-index or name (case-insensitive); KeyError if absent.")
        .def("__len__", [](const Object& o) { return o.subs.size(); })
        .def("__repr__", [](const Object& o) {
            return "<codrive.eds.Object " + hex_index(o.index) + " '" + o.name + "' " +
                   std::string(to_string(o.code)) + ">";
        });

    py::class_<Eds, std::shared_ptr<Eds>>(
        e, "Eds",
        "A parsed EDS or DCF: eds[0x1018] or eds['Identity object'] is an Object, "
        "eds[0x1018, 1] a SubObject; findings lists what the parser (`codrive eds lint`) "
        "found.")
        .def_readonly("path", &Eds::path)
        .def_property_readonly(
            "findings",
            [](const Eds& self) {
                return std::vector<EdsFinding>(self.desc.findings.begin(),
                                               self.desc.findings.end());
            },
            "Every finding, in file order (severity 'error', 'warning' or 'info').")
        .def_property_readonly("has_errors", [](const Eds& self) { return self.desc.has_errors(); })
        .def_property_readonly(
            "device_info",
            [](const Eds& self) {
                const DeviceInfo& d = self.desc.device_info;
                py::dict out;
                out["vendor_name"] = d.vendor_name;
                out["vendor_number"] = d.vendor_number;
                out["product_name"] = d.product_name;
                out["product_number"] = d.product_number;
                out["revision_number"] = d.revision_number;
                out["order_code"] = d.order_code;
                out["baud_rates"] = d.baud_rates;
                out["nr_of_rx_pdo"] = d.nr_of_rx_pdo;
                out["nr_of_tx_pdo"] = d.nr_of_tx_pdo;
                return out;
            },
            "[DeviceInfo] as a dict.")
        .def_property_readonly(
            "node_id", [](const Eds& self) { return self.desc.node_id; },
            "The node-ID $NODEID was evaluated with (argument, else DCF NodeID), or None.")
        .def(
            "__getitem__",
            [](py::object self, const py::object& key) -> py::object {
                const Eds& eds = self.cast<const Eds&>();
                if (py::isinstance<py::tuple>(key) && py::len(key) == 2) {
                    const auto t = key.cast<py::tuple>();
                    const Object& o = eds.object(t[0]);
                    const SubObject& s = sub_of(o, t[1], eds.path);
                    return py::cast(&s, py::return_value_policy::reference_internal, self);
                }
                return py::cast(&eds.object(key), py::return_value_policy::reference_internal,
                                self);
            },
            py::arg("key"),
            "An object by index or name, or a sub-object by (index or name, sub-index or "
            "name); KeyError if absent.")
        .def("__contains__",
             [](const Eds& self, const py::object& key) {
                 try {
                     (void)self.object(key);
                     return true;
                 } catch (const py::key_error&) {
                     return false;
                 }
             })
        .def("__len__", [](const Eds& self) { return self.desc.od.size(); })
        .def(
            "__iter__",
            [](py::object self) {
                const Eds& eds = self.cast<const Eds&>();
                py::list l;
                for (const auto& [i, o] : eds.desc.od.objects()) {
                    l.append(py::cast(&o, py::return_value_policy::reference_internal, self));
                }
                return py::iter(l);
            },
            "The objects in index order.")
        .def("__repr__", [](const Eds& self) {
            return "<codrive.eds.Eds " + self.path + ": " + std::to_string(self.desc.od.size()) +
                   " objects, " + std::to_string(self.desc.findings.size()) + " findings>";
        });

    e.def(
        "load",
        [](const std::string& path, std::optional<long> node_id) {
            std::optional<NodeId> node;
            if (node_id) {
                if (*node_id < 1 || *node_id > kMaxNodeId) {
                    throw py::value_error("node_id " + std::to_string(*node_id) + " is not 1..127");
                }
                node = static_cast<NodeId>(*node_id);
            }
            auto desc = load_eds(path, node);
            if (!desc) {
                errno = desc.error().value();
                PyErr_SetFromErrnoWithFilename(PyExc_OSError, path.c_str());
                throw py::error_already_set();
            }
            auto out = std::make_shared<Eds>();
            out->desc = std::move(*desc);
            out->path = path;
            return out;
        },
        py::arg("path"), py::arg("node_id") = py::none(),
        "Parses an EDS or DCF file. Never fails on content: whatever cannot be read becomes a "
        "finding (eds.findings) and the rest is loaded. OSError if the file cannot be read. "
        "node_id: evaluates $NODEID with it (default: the DCF's NodeID).");
}

} // namespace codrive::python
