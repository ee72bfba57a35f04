// SPDX-License-Identifier: Apache-2.0
// bus.sdo(node): typed reads and writes, files, block transfers and progress through SdoClient.
#include "errors.hpp"
#include "module.hpp"
#include "wait.hpp"

#include <codrive/sdo/client.hpp>

#include <pybind11/functional.h>
#include <pybind11/stl.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <limits>
#include <memory>
#include <vector>

namespace py = pybind11;

namespace codrive::python {

namespace {

/// Calls `f.template operator()<T>()` with the C++ type named by `type` ("u16", "str", ...).
template <typename F>
py::object visit_type(const std::string& type, F&& f) {
    if (type == "u8")
        return f.template operator()<std::uint8_t>();
    if (type == "u16")
        return f.template operator()<std::uint16_t>();
    if (type == "u32")
        return f.template operator()<std::uint32_t>();
    if (type == "u64")
        return f.template operator()<std::uint64_t>();
    if (type == "i8")
        return f.template operator()<std::int8_t>();
    if (type == "i16")
        return f.template operator()<std::int16_t>();
    if (type == "i32")
        return f.template operator()<std::int32_t>();
    if (type == "i64")
        return f.template operator()<std::int64_t>();
    if (type == "f32")
        return f.template operator()<float>();
    if (type == "f64")
        return f.template operator()<double>();
    if (type == "str")
        return f.template operator()<std::string>();
    if (type == "bytes")
        return f.template operator()<sdo::Bytes>();
    throw py::value_error("unknown SDO type '" + type +
                          "' (use u8, u16, u32, u64, i8, i16, i32, i64, f32, f64, str or bytes)");
}

template <typename T>
py::object to_python(const T& v) {
    if constexpr (std::is_same_v<T, sdo::Bytes>) {
        return py::bytes(reinterpret_cast<const char*>(v.data()), v.size());
    } else if constexpr (std::is_same_v<T, std::string>) {
        // VISIBLE_STRING is ASCII (CiA 301 §7.1.6.3); a device sending other bytes gets them
        // replaced, never an exception for the device's mistake.
        return py::reinterpret_steal<py::object>(
            PyUnicode_DecodeUTF8(v.data(), static_cast<Py_ssize_t>(v.size()), "replace"));
    } else if constexpr (std::is_floating_point_v<T>) {
        return py::float_(static_cast<double>(v));
    } else {
        return py::int_(v);
    }
}

/// The value to write as T: integers must fit (a sentence names the range), reals, str, bytes.
template <typename T>
T from_python(py::handle value, const std::string& type, const std::string& where) {
    if constexpr (std::is_same_v<T, sdo::Bytes>) {
        // bytes, bytearray, memoryview, a list of ints...
        if (py::isinstance<py::str>(value)) {
            throw py::type_error(where + ": type bytes needs bytes, not str");
        }
        auto b = py::reinterpret_steal<py::object>(PyBytes_FromObject(value.ptr()));
        if (!b) {
            throw py::error_already_set();
        }
        const std::string s(py::reinterpret_borrow<py::bytes>(b));
        return sdo::Bytes(s.begin(), s.end());
    } else if constexpr (std::is_same_v<T, std::string>) {
        if (!py::isinstance<py::str>(value)) {
            throw py::type_error(where + ": type str needs a str value");
        }
        return value.cast<std::string>();
    } else if constexpr (std::is_floating_point_v<T>) {
        if (!py::isinstance<py::float_>(value) && !py::isinstance<py::int_>(value)) {
            throw py::type_error(where + ": type " + type + " needs a number");
        }
        return static_cast<T>(value.cast<double>());
    } else {
        if (!py::isinstance<py::int_>(value)) {
            throw py::type_error(where + ": type " + type + " needs an int");
        }
        int overflow = 0;
        const long long sv = PyLong_AsLongLongAndOverflow(value.ptr(), &overflow);
        bool fits = false;
        if (overflow == 0) {
            if constexpr (std::is_signed_v<T>) {
                fits = sv >= std::numeric_limits<T>::min() && sv <= std::numeric_limits<T>::max();
            } else {
                fits =
                    sv >= 0 && static_cast<unsigned long long>(sv) <= std::numeric_limits<T>::max();
            }
            if (fits) {
                return static_cast<T>(sv);
            }
        } else if (overflow > 0 && std::is_same_v<T, std::uint64_t>) {
            const unsigned long long uv = PyLong_AsUnsignedLongLongMask(value.ptr());
            if (py::int_(uv).equal(value)) {
                return static_cast<T>(uv);
            }
        }
        throw py::value_error(where + ": " + std::string(py::str(value)) + " does not fit " + type +
                              " (" + std::to_string(+std::numeric_limits<T>::min()) + ".." +
                              std::to_string(+std::numeric_limits<T>::max()) + ")");
    }
}

/// The object address as in every codrive message: "node 4: 0x6040:00".
std::string where(NodeId node, std::uint16_t index, std::uint8_t sub) {
    char buf[48];
    std::snprintf(buf, sizeof buf, "node %u: 0x%04X:%02X", node, index, sub);
    return buf;
}

/// An SDO index from Python, checked: ValueError names the value out of range. Index and
/// subindex come as two plain values, not a pair to unpack: clang 14 does not let a lambda
/// capture a structured binding, and the transfers' callbacks capture them.
std::uint16_t index_arg(long index) {
    if (index < 0 || index > 0xFFFF) {
        throw py::value_error("SDO index " + std::to_string(index) + " is not 0..0xFFFF");
    }
    return static_cast<std::uint16_t>(index);
}

/// An SDO subindex from Python, checked.
std::uint8_t sub_arg(long sub) {
    if (sub < 0 || sub > 0xFF) {
        throw py::value_error("SDO subindex " + std::to_string(sub) + " is not 0..0xFF");
    }
    return static_cast<std::uint8_t>(sub);
}

/// A node id from Python, checked (1..127).
NodeId node_arg(long node) {
    if (node < 1 || node > kMaxNodeId) {
        throw py::value_error("SDO node id " + std::to_string(node) + " is not 1..127");
    }
    return static_cast<NodeId>(node);
}

/// A pending Python exception raised by a progress callback, re-raised after the transfer.
struct CallbackError {
    std::optional<py::error_already_set> error;
};

/// bus.sdo(node): the client of the default SDO channel of one node.
class SdoNode {
public:
    SdoNode(std::shared_ptr<Bus> bus, NodeId node) : bus_(std::move(bus)), node_(node) {}

    py::object read(long index, long sub, const std::string& type, std::optional<double> timeout,
                    const std::string& mode, const py::object& progress) {
        const std::uint16_t i = index_arg(index);
        const std::uint8_t s = sub_arg(sub);
        CallbackError cb_error;
        sdo::TransferOptions options = make_options(timeout, mode, progress, cb_error);
        return visit_type(type, [&]<typename T>() -> py::object {
            auto r = wait_for_result<sdo::SdoResult<T>>(*bus_, [&](auto done) {
                bus_->sdo_clients().client(node_).template read<T>(i, s, std::move(done),
                                                                   std::move(options));
            });
            rethrow(cb_error);
            if (!r) {
                raise_sdo_error(r.error());
            }
            return to_python(*r);
        });
    }

    void write(long index, long sub, const py::object& value, std::optional<std::string> type,
               std::optional<double> timeout, const std::string& mode, const py::object& progress) {
        const std::uint16_t i = index_arg(index);
        const std::uint8_t s = sub_arg(sub);
        std::string t;
        if (type) {
            t = *type;
        } else if (py::isinstance<py::bytes>(value) || py::isinstance<py::bytearray>(value)) {
            t = "bytes";
        } else if (py::isinstance<py::str>(value)) {
            t = "str";
        } else {
            throw py::type_error(where(node_, i, s) +
                                 ": give the type of a numeric value (e.g. write(index, "
                                 "subindex, value, \"u16\"))");
        }
        CallbackError cb_error;
        sdo::TransferOptions options = make_options(timeout, mode, progress, cb_error);
        visit_type(t, [&]<typename T>() -> py::object {
            const T v = from_python<T>(value, t, where(node_, i, s));
            auto r = wait_for_result<sdo::SdoResult<void>>(*bus_, [&](auto done) {
                bus_->sdo_clients().client(node_).template write<T>(i, s, v, std::move(done),
                                                                    std::move(options));
            });
            rethrow(cb_error);
            if (!r) {
                raise_sdo_error(r.error());
            }
            return py::none();
        });
    }

    std::size_t upload_file(long index, long sub, const std::string& path,
                            std::optional<double> timeout, const std::string& mode,
                            const py::object& progress) {
        const std::uint16_t i = index_arg(index);
        const std::uint8_t s = sub_arg(sub);
        CallbackError cb_error;
        sdo::TransferOptions options = make_options(timeout, mode, progress, cb_error);
        std::unique_ptr<std::FILE, int (*)(std::FILE*)> file(std::fopen(path.c_str(), "wb"),
                                                             &std::fclose);
        if (!file) {
            PyErr_SetFromErrnoWithFilename(PyExc_OSError, path.c_str());
            throw py::error_already_set();
        }
        auto r = wait_for_result<sdo::SdoResult<void>>(*bus_, [&](auto done) {
            bus_->sdo_clients().client(node_).upload(i, s, sdo::file_sink(file.get()),
                                                     std::move(done), std::move(options));
        });
        const long size = std::ftell(file.get());
        file.reset();
        rethrow(cb_error);
        if (!r) {
            raise_sdo_error(r.error());
        }
        return size < 0 ? 0U : static_cast<std::size_t>(size);
    }

    void download_file(long index, long sub, const std::string& path, std::optional<double> timeout,
                       const std::string& mode, const py::object& progress) {
        const std::uint16_t i = index_arg(index);
        const std::uint8_t s = sub_arg(sub);
        CallbackError cb_error;
        sdo::TransferOptions options = make_options(timeout, mode, progress, cb_error);
        auto source = sdo::file_source(path);
        if (!source) {
            errno = source.error().value();
            PyErr_SetFromErrnoWithFilename(PyExc_OSError, path.c_str());
            throw py::error_already_set();
        }
        auto r = wait_for_result<sdo::SdoResult<void>>(*bus_, [&](auto done) {
            bus_->sdo_clients().client(node_).download(i, s, std::move(*source), std::move(done),
                                                       std::move(options));
        });
        rethrow(cb_error);
        if (!r) {
            raise_sdo_error(r.error());
        }
    }

    [[nodiscard]] NodeId node() const { return node_; }

    /// For the benchmark beside Python's own loop: `count` expedited reads of index:sub from a
    /// C++ loop on the same bus and client (the C++ blocking client's figure in the same run).
    /// Returns the seconds taken.
    double cpp_round_trips(long index, long sub, long count) {
        const std::uint16_t i = index_arg(index);
        const std::uint8_t s = sub_arg(sub);
        return with_bus(*bus_, [&] {
            const auto t0 = SteadyClock::now();
            for (long n = 0; n < count; ++n) {
                std::optional<sdo::SdoResult<std::uint32_t>> out;
                bus_->sdo_clients().client(node_).read<std::uint32_t>(
                    i, s, [&out](sdo::SdoResult<std::uint32_t> r) { out.emplace(std::move(r)); });
                bus_->run_until([&out] { return out.has_value(); }, Duration::max());
                if (!out || !*out) {
                    return -1.0;
                }
            }
            return std::chrono::duration<double>(SteadyClock::now() - t0).count();
        });
    }

private:
    sdo::TransferOptions make_options(std::optional<double> timeout, const std::string& mode,
                                      const py::object& progress, CallbackError& cb_error) const {
        sdo::TransferOptions o;
        if (timeout) {
            o.timeout = seconds_arg(*timeout, "timeout");
        }
        if (mode == "block") {
            o.mode = sdo::Mode::Block;
        } else if (mode == "segmented") {
            o.mode = sdo::Mode::Segmented;
        } else if (mode != "auto") {
            throw py::value_error("unknown SDO mode '" + mode +
                                  "' (use 'auto', 'segmented' or 'block')");
        }
        if (!progress.is_none()) {
            // The callback holds pointers only: the Python objects belong to the caller's
            // frame, which outlives the transfer, and are touched only with the GIL.
            const py::object* fn = &progress;
            CallbackError* err = &cb_error;
            o.progress = [fn, err](std::size_t done, std::optional<std::size_t> total) {
                py::gil_scoped_acquire gil;
                if (err->error) {
                    return;
                }
                try {
                    (*fn)(done, total ? py::object(py::int_(*total)) : py::object(py::none()));
                } catch (py::error_already_set& e) {
                    err->error.emplace(std::move(e));
                }
            };
        }
        return o;
    }

    static void rethrow(CallbackError& e) {
        if (e.error) {
            py::error_already_set pending = std::move(*e.error);
            e.error.reset();
            throw pending;
        }
    }

    std::shared_ptr<Bus> bus_;
    NodeId node_;
};

/// bus.read_many(): uploads from several nodes at once. Each node's transfer runs on its own
/// SDO channel, so they proceed side by side on the bus (one per node at a time, as CiA 301
/// allows per channel); the call returns when all have ended.
py::list read_many(const std::shared_ptr<Bus>& bus, const py::sequence& requests,
                   std::optional<double> timeout) {
    struct Slot {
        std::function<py::object()> value; ///< converts the result (with the GIL)
        std::optional<sdo::SdoError> error;
    };
    using Ended = std::function<void()>;
    const std::size_t n = static_cast<std::size_t>(py::len(requests));
    std::vector<std::function<void(Slot&, Ended&)>> starts;
    starts.reserve(n);
    sdo::TransferOptions options;
    if (timeout) {
        options.timeout = seconds_arg(*timeout, "timeout");
    }
    for (std::size_t k = 0; k < n; ++k) {
        const py::tuple r = py::reinterpret_borrow<py::object>(requests[k]).cast<py::tuple>();
        if (r.size() < 3 || r.size() > 4) {
            throw py::value_error("read_many: request " + std::to_string(k) +
                                  " is not (node, index, subindex[, type])");
        }
        const NodeId node = node_arg(r[0].cast<long>());
        const std::uint16_t index = index_arg(r[1].cast<long>());
        const std::uint8_t sub = sub_arg(r[2].cast<long>());
        const std::string type = r.size() == 4 ? r[3].cast<std::string>() : "bytes";
        visit_type(type, [&]<typename T>() -> py::object {
            starts.push_back([bus, node, index, sub, options](Slot& slot, Ended& ended) {
                bus->sdo_clients().client(node).template read<T>(
                    index, sub,
                    [&slot, &ended](sdo::SdoResult<T> res) {
                        if (res) {
                            slot.value = [v = std::move(*res)] { return to_python(v); };
                        } else {
                            slot.error.emplace(res.error());
                        }
                        ended();
                    },
                    options);
            });
            return py::none();
        });
    }
    // All started at once, then the bus runs (as for one transfer) until the last has ended.
    std::vector<Slot> slots(n);
    std::size_t left = n;
    Ended ended;
    wait_for_result<bool>(*bus, [&](auto done) {
        ended = [&left, done] {
            if (--left == 0) {
                done(true);
            }
        };
        if (n == 0) {
            done(true);
        }
        for (std::size_t k = 0; k < n; ++k) {
            starts[k](slots[k], ended);
        }
    });
    py::list out;
    for (auto& slot : slots) {
        if (slot.error) {
            raise_sdo_error(*slot.error); // the first failure, after every transfer ended
        }
        out.append(slot.value());
    }
    return out;
}

} // namespace

void bind_sdo(py::module_& m, PyBusClass& bus) {
    py::class_<SdoNode>(m, "SdoClient",
                        "The SDO client of one node's default channel (bus.sdo(node)). Calls "
                        "block until the transfer ends, with the GIL released.")
        .def_property_readonly("node", &SdoNode::node, "The node id (1..127).")
        .def("_cpp_round_trips", &SdoNode::cpp_round_trips, py::arg("index"), py::arg("subindex"),
             py::arg("count"),
             "Benchmark aid: `count` u32 reads from a C++ loop; seconds taken (-1 on failure).")
        .def("read", &SdoNode::read, py::arg("index"), py::arg("subindex"),
             py::arg("type") = "bytes", py::kw_only(), py::arg("timeout") = py::none(),
             py::arg("mode") = "auto", py::arg("progress") = py::none(),
             "Uploads index:subindex and returns it as `type` (u8, u16, u32, u64, i8, i16, i32, "
             "i64, f32, f64: the object must have exactly that size; str; bytes). timeout: "
             "seconds per response (the bus default if None); mode: 'auto', 'segmented' or "
             "'block'; progress: called as progress(done_bytes, total_or_None). Raises "
             "SdoAbortError, SdoTimeoutError or SdoError.")
        .def("write", &SdoNode::write, py::arg("index"), py::arg("subindex"), py::arg("value"),
             py::arg("type") = py::none(), py::kw_only(), py::arg("timeout") = py::none(),
             py::arg("mode") = "auto", py::arg("progress") = py::none(),
             "Downloads `value` as `type` (needed for numbers; bytes and str are taken as "
             "such). An int that does not fit the type raises ValueError before anything is "
             "sent. Raises SdoAbortError, SdoTimeoutError or SdoError.")
        .def("upload_file", &SdoNode::upload_file, py::arg("index"), py::arg("subindex"),
             py::arg("path"), py::kw_only(), py::arg("timeout") = py::none(),
             py::arg("mode") = "auto", py::arg("progress") = py::none(),
             "Uploads index:subindex into the file `path` (streamed); returns its size.")
        .def("download_file", &SdoNode::download_file, py::arg("index"), py::arg("subindex"),
             py::arg("path"), py::kw_only(), py::arg("timeout") = py::none(),
             py::arg("mode") = "auto", py::arg("progress") = py::none(),
             "Downloads the file `path` to index:subindex (streamed).");
    bus.def(
        "sdo",
        [](const std::shared_ptr<Bus>& self, long node) { return SdoNode(self, node_arg(node)); },
        py::arg("node"), "The SDO client of `node` (1..127).");
    bus.def("read_many", &read_many, py::arg("requests"), py::kw_only(),
            py::arg("timeout") = py::none(),
            "Reads from several nodes at once: requests is a list of (node, index, subindex[, "
            "type]) (type as for read(), default bytes); returns the values in that order. "
            "Transfers to different nodes run side by side (one SDO channel per node); those "
            "to the same node take turns. If any fails, the first failure is raised once all "
            "have ended (SdoAbortError, SdoTimeoutError, SdoError).");
}

} // namespace codrive::python
