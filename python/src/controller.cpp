// SPDX-License-Identifier: Apache-2.0
// codrive.Controller and its axes: a bus file booted by codrive::controller, run from Python.
// The cycle stays in C++: Python calls run_for() (the loop runs, GIL released), reads snapshots
// and queues set-points between runs; nothing of Python is on the cyclic path.
#include "errors.hpp"
#include "module.hpp"
#include "wait.hpp"

#include <codrive/controller/controller.hpp>
#include <codrive/drives/axis.hpp>
#include <codrive/drives/cia402.hpp>
#include <codrive/master/boot_report.hpp>

#include <pybind11/stl.h>

namespace py = pybind11;

namespace codrive::python {

namespace {

/// Owns the controller; every call runs on the calling thread with the GIL released and the
/// controller held (Threading::Single: the controller belongs to whichever thread runs it).
class PyController {
public:
    /// Runs fn() with the GIL released and the controller held.
    template <typename Fn>
    decltype(auto) locked(Fn&& fn) {
        py::gil_scoped_release nogil;
        std::lock_guard lock(mutex_);
        return fn();
    }
    static std::shared_ptr<PyController> from_file(const std::string& path) {
        auto c = controller::Controller::from_file(path);
        if (!c) {
            raise_controller_error(c.error());
        }
        auto self = std::shared_ptr<PyController>(new PyController());
        self->c_ = std::move(*c);
        self->c_->set_event_callback([raw = self.get()](const std::string& text) {
            raw->events_.push_back(text); // on the loop thread, which holds mutex_
        });
        return self;
    }
    ~PyController() {
        py::gil_scoped_release nogil;
        std::lock_guard lock(mutex_);
        c_->shutdown();
    }
    PyController(const PyController&) = delete;
    PyController& operator=(const PyController&) = delete;

    void start() {
        auto r = locked([&] { return c_->start(); });
        if (!r) {
            raise_controller_error(r.error());
        }
    }
    void run_for(double seconds) {
        const Duration d = seconds_arg(seconds, "run_for");
        locked([&] {
            c_->run_for(d);
            return 0;
        });
    }
    void shutdown() {
        locked([&] {
            c_->shutdown();
            return 0;
        });
    }
    py::dict stats() {
        const auto s = locked([&] { return c_->stats(); });
        py::dict d;
        d["cycles"] = s.cycles;
        d["overruns"] = s.overruns;
        d["period_error_p50"] = std::chrono::duration<double>(s.period_error_p50).count();
        d["period_error_p99"] = std::chrono::duration<double>(s.period_error_p99).count();
        d["period_error_max"] = std::chrono::duration<double>(s.period_error_max).count();
        d["tpdos_received"] = s.tpdos_received;
        d["tpdos_missing"] = s.tpdos_missing;
        d["rpdos_sent"] = s.rpdos_sent;
        d["sdo_completed"] = s.sdo_completed;
        d["sdo_failed"] = s.sdo_failed;
        d["bus_errors"] = s.bus_errors;
        d["text"] = s.to_string();
        return d;
    }
    std::vector<std::string> events() {
        return locked([&] { return events_; });
    }
    std::vector<std::string> boot_reports() {
        return locked([&] {
            std::vector<std::string> out;
            for (const auto& r : c_->boot_reports()) {
                out.push_back(r.to_string());
            }
            return out;
        });
    }
    py::list axes() {
        const auto refs = locked([&] { return c_->axes(); });
        py::list out;
        for (const auto& a : refs) {
            py::dict d;
            d["bus"] = a.bus;
            d["node"] = a.node;
            d["axis"] = a.number;
            d["name"] = a.name;
            out.append(d);
        }
        return out;
    }
    bool running() {
        return locked([&] { return c_->running(); });
    }

    controller::Controller& get() { return *c_; }

private:
    PyController() = default;
    std::unique_ptr<controller::Controller> c_;
    std::mutex mutex_;
    std::vector<std::string> events_;
};

/// One axis of a started controller.
class PyAxis {
public:
    PyAxis(std::shared_ptr<PyController> c, drives::Axis* axis) : c_(std::move(c)), axis_(axis) {}

    /// Starts an operation on the axis and runs the controller until it ends.
    template <typename Start>
    void operate(Start&& start, std::optional<double> timeout) {
        const Duration t =
            timeout ? seconds_arg(*timeout, "timeout") : Duration::zero(); // zero: the axis's
        std::optional<drives::DriveVoid> out;
        c_->locked([&] {
            start([&out](drives::DriveVoid r) { out.emplace(std::move(r)); }, t);
            // The axis enforces its own timeout; the outer bound only guards a stopped loop.
            const Duration bound = (t == Duration::zero() ? seconds(2) : t) + seconds(5);
            return c_->get().run_until([&out] { return out.has_value(); }, bound);
        });
        if (!out) {
            axis_->cancel();
            raise_drive_error(axis_->name() + ": the controller stopped before the operation "
                                              "ended");
        }
        if (!*out) {
            raise_drive_error(out->error().message);
        }
    }

    py::dict status() {
        struct Snapshot {
            drives::cia402::State state;
            std::uint16_t statusword, controlword;
            std::optional<std::int8_t> mode;
            std::optional<std::int32_t> position, velocity;
            bool busy;
            std::string diagnosis;
            std::uint16_t error_code; ///< of the last EMCY (603Fh on CAN) the axis saw
            std::string error_text;   ///< the drive's text for it (profile fault table)
        };
        const Snapshot s = c_->locked([&] {
            return Snapshot{axis_->state(),
                            axis_->statusword(),
                            axis_->controlword(),
                            axis_->mode_display(),
                            axis_->position_actual(),
                            axis_->velocity_actual(),
                            axis_->busy(),
                            axis_->diagnose(),
                            axis_->last_error_code(),
                            axis_->last_error_code() != 0
                                ? axis_->profile().fault_text(axis_->last_error_code())
                                : std::string()};
        });
        py::dict d;
        d["state"] = std::string(drives::cia402::to_string(s.state));
        d["statusword"] = s.statusword;
        d["controlword"] = s.controlword;
        d["mode"] = optional_int(s.mode);
        d["position"] = optional_int(s.position);
        d["velocity"] = optional_int(s.velocity);
        d["busy"] = s.busy;
        d["diagnosis"] = s.diagnosis;
        // The last emergency: its error code and the drive's own text (None before any).
        d["error_code"] = s.error_code != 0 ? py::object(py::int_(s.error_code)) : py::none();
        d["error_text"] = s.error_code != 0 ? py::object(py::str(s.error_text)) : py::none();
        return d;
    }
    void set_target_position(long target) {
        c_->locked([&] {
            axis_->set_target_position(static_cast<std::int32_t>(target));
            return 0;
        });
    }
    void set_target_velocity(long target) {
        c_->locked([&] {
            axis_->set_target_velocity(static_cast<std::int32_t>(target));
            return 0;
        });
    }
    [[nodiscard]] std::string name() const { return axis_->name(); }
    drives::Axis& axis() { return *axis_; }

private:
    template <typename T>
    static py::object optional_int(std::optional<T> v) {
        return v ? py::object(py::int_(*v)) : py::object(py::none());
    }
    std::shared_ptr<PyController> c_;
    drives::Axis* axis_;
};

std::int32_t i32_arg(long v, const char* what) {
    if (v < INT32_MIN || v > INT32_MAX) {
        throw py::value_error(std::string(what) + " " + std::to_string(v) +
                              " does not fit a 32-bit set-point");
    }
    return static_cast<std::int32_t>(v);
}

} // namespace

void bind_controller(py::module_& m) {
    using Done = drives::Axis::Done;
    py::class_<PyAxis>(m, "Axis",
                       "A CiA 402 axis of a started Controller. Operations block until the "
                       "drive confirms (GIL released) and raise DriveError otherwise.")
        .def_property_readonly("name", &PyAxis::name)
        .def_property_readonly("status", &PyAxis::status,
                               "Snapshot: state, statusword, controlword, mode, position, "
                               "velocity, busy, diagnosis, error_code and error_text (the last "
                               "emergency and the drive's text for it, None before any).")
        .def(
            "enable",
            [](PyAxis& a, std::optional<double> t) {
                a.operate([&](Done d, Duration to) { a.axis().enable(std::move(d), to); }, t);
            },
            py::arg("timeout") = py::none(), "To OPERATION ENABLED (fault reset if needed).")
        .def(
            "disable",
            [](PyAxis& a, std::optional<double> t) {
                a.operate([&](Done d, Duration to) { a.axis().disable(std::move(d), to); }, t);
            },
            py::arg("timeout") = py::none(), "To SWITCH ON DISABLED.")
        .def(
            "quick_stop",
            [](PyAxis& a, std::optional<double> t) {
                a.operate([&](Done d, Duration to) { a.axis().quick_stop(std::move(d), to); }, t);
            },
            py::arg("timeout") = py::none(), "Quick stop (605Ah decides the end state).")
        .def(
            "fault_reset",
            [](PyAxis& a, std::optional<double> t) {
                a.operate([&](Done d, Duration to) { a.axis().fault_reset(std::move(d), to); }, t);
            },
            py::arg("timeout") = py::none(), "Fault reset (ends in SWITCH ON DISABLED).")
        .def(
            "set_mode",
            [](PyAxis& a, int mode, std::optional<double> t) {
                if (mode < -128 || mode > 127) {
                    throw py::value_error("mode " + std::to_string(mode) + " is not -128..127");
                }
                a.operate(
                    [&](Done d, Duration to) {
                        a.axis().set_mode(static_cast<std::int8_t>(mode), std::move(d), to);
                    },
                    t);
            },
            py::arg("mode"), py::arg("timeout") = py::none(),
            "Writes 6060h and waits for 6061h (1 PP, 3 PV, 6 homing, 8 CSP, 9 CSV, ...).")
        .def(
            "move_to",
            [](PyAxis& a, long target, bool relative, std::optional<long> velocity,
               std::optional<double> t) {
                drives::MoveOptions o;
                o.relative = relative;
                if (velocity) {
                    o.velocity = static_cast<std::uint32_t>(i32_arg(*velocity, "velocity"));
                }
                const std::int32_t x = i32_arg(target, "target");
                a.operate([&](Done d, Duration to) { a.axis().move_to(x, o, std::move(d), to); },
                          t);
            },
            py::arg("target"), py::arg("relative") = false, py::arg("velocity") = py::none(),
            py::arg("timeout") = py::none(),
            "Profile position move; returns when target reached (statusword bit 10).")
        .def(
            "run_velocity",
            [](PyAxis& a, long velocity, std::optional<double> t) {
                const std::int32_t v = i32_arg(velocity, "velocity");
                a.operate([&](Done d, Duration to) { a.axis().run_velocity(v, std::move(d), to); },
                          t);
            },
            py::arg("velocity"), py::arg("timeout") = py::none(),
            "Profile velocity: writes 60FFh; returns when target reached (statusword bit 10).")
        .def(
            "home",
            [](PyAxis& a, int method, long offset, std::optional<double> t) {
                if (method < -128 || method > 127) {
                    throw py::value_error("homing method " + std::to_string(method) +
                                          " is not -128..127");
                }
                drives::HomingParams p;
                p.method = static_cast<std::int8_t>(method);
                p.offset = i32_arg(offset, "offset");
                a.operate([&](Done d, Duration to) { a.axis().home(p, std::move(d), to); }, t);
            },
            py::arg("method") = 35, py::arg("offset") = 0, py::arg("timeout") = py::none(),
            "Homing (the axis must be in homing mode 6): 6098h = method, 607Ch = offset; "
            "returns when homing attained (statusword bits 12 and 10).")
        .def("set_target_position", &PyAxis::set_target_position, py::arg("target"),
             "CSP: the set-point sent with the next cycles (run the controller to send it).")
        .def("set_target_velocity", &PyAxis::set_target_velocity, py::arg("target"),
             "CSV: the velocity set-point sent with the next cycles.")
        .def("__repr__", [](const PyAxis& a) { return "<codrive.Axis " + a.name() + ">"; });

    py::class_<PyController, std::shared_ptr<PyController>>(
        m, "Controller",
        "A bus file (docs/bus-file.md) booted by the C++ controller: SYNC, PDOs, supervision "
        "and the CiA 402 axes run in C++ while run_for() runs; Python reads snapshots and "
        "queues targets between runs.")
        .def_static("from_file", &PyController::from_file, py::arg("path"),
                    "Loads a bus file; codrive.Error lists every finding (\"bus.yml:14: ...\").")
        .def("start", &PyController::start,
             "Opens the buses, boots and configures every node, maps PDOs, starts SYNC. "
             "codrive.Error names the nodes that failed.")
        .def("run_for", &PyController::run_for, py::arg("seconds"),
             "Runs the controller (cycles, PDOs, SDO, supervision) for `seconds`.")
        .def("shutdown", &PyController::shutdown,
             "Safe shutdown: quick stop and disable every enabled axis, nodes to "
             "PRE-OPERATIONAL, SYNC off. Idempotent; also done when the object is collected.")
        .def("stats", &PyController::stats, "Cycle, PDO, SDO and bus counters as a dict.")
        .def_property_readonly("events", &PyController::events,
                               "Every event sentence so far (boot reports, EMCY, warnings).")
        .def_property_readonly("boot_reports", &PyController::boot_reports)
        .def_property_readonly("axes", &PyController::axes,
                               "Every axis: dicts with bus, node, axis, name.")
        .def_property_readonly("running", &PyController::running)
        .def(
            "axis",
            [](const std::shared_ptr<PyController>& self, long node, unsigned number,
               std::size_t bus) {
                drives::Axis* a = self->locked([&] {
                    return node >= 0 && node <= kMaxNodeId
                               ? self->get().axis(static_cast<NodeId>(node), number, bus)
                               : nullptr;
                });
                if (a == nullptr) {
                    throw py::key_error("no axis " + std::to_string(number) + " on node " +
                                        std::to_string(node) + " of bus " + std::to_string(bus) +
                                        " (start() first; see .axes)");
                }
                return PyAxis(self, a);
            },
            py::arg("node"), py::arg("axis") = 1, py::arg("bus") = 0,
            "An axis by node id, axis number (1-based) and bus index.");
}

} // namespace codrive::python
