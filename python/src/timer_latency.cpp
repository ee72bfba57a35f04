// SPDX-License-Identifier: Apache-2.0
// codrive.measure_timer_latency(): the controller's timer probe (`codrive latency`) from Python,
// GIL released while it measures, Ctrl-C ending it early as it ends the command.
#include "interrupt.hpp"
#include "module.hpp"

#include <codrive/controller/timer_probe.hpp>

#include <pybind11/functional.h>
#include <pybind11/stl.h>

#include <cmath>
#include <optional>
#include <string>

namespace py = pybind11;

namespace codrive::python {
namespace {

double secs(Duration d) {
    return std::chrono::duration<double>(d).count();
}

Duration duration_arg(double seconds, const char* what) {
    if (!std::isfinite(seconds) || seconds < 0 || seconds > 86400) {
        throw py::value_error(std::string(what) + " must be 0..86400 seconds, not " +
                              std::to_string(seconds));
    }
    return std::chrono::duration_cast<Duration>(std::chrono::duration<double>(seconds));
}

py::dict window_dict(const controller::TimerWindow& w) {
    py::dict d;
    d["number"] = w.number;
    d["start"] = secs(w.from);
    d["end"] = secs(w.to);
    d["wakeups"] = w.wakeups;
    d["max"] = secs(w.max);
    d["late_half_cycle"] = w.late_half_cycle;
    d["late_whole_cycle"] = w.late_whole_cycle;
    d["skipped_slots"] = w.skipped_slots;
    d["text"] = w.to_string();
    return d;
}

const char* verdict_name(controller::TimerVerdict v) {
    switch (v) {
    case controller::TimerVerdict::Sound:
        return "sound";
    case controller::TimerVerdict::Jittery:
        return "jittery";
    case controller::TimerVerdict::SkipsCycles:
        return "not sound";
    }
    return "?";
}

py::dict measure(double cycle, double seconds, double window, int fifo, int cpu, bool lock_memory,
                 std::optional<py::function> on_window) {
    if (!std::isfinite(cycle) || cycle < 50e-6 || cycle > 1.0) {
        throw py::value_error("cycle must be 50e-6..1 seconds, not " + std::to_string(cycle));
    }
    if (fifo < 0 || fifo > 99) {
        throw py::value_error("fifo must be a SCHED_FIFO priority 1..99 (0: normal scheduling), "
                              "not " +
                              std::to_string(fifo));
    }
    controller::TimerProbeOptions o;
    o.cycle = duration_arg(cycle, "cycle");
    o.duration = duration_arg(seconds, "seconds");
    o.window = duration_arg(window, "window");
    o.realtime.fifo = fifo > 0;
    o.realtime.priority = fifo;
    o.realtime.cpu = cpu;
    o.realtime.lock_memory = lock_memory;
    // The callback runs on this thread between the probe's windows: with the GIL, and a Python
    // exception in it ends the run and is raised here.
    std::optional<py::error_already_set> raised;
    if (on_window) {
        o.on_window = [&](const controller::TimerWindow& w) {
            py::gil_scoped_acquire gil;
            if (raised) {
                return;
            }
            try {
                (*on_window)(window_dict(w));
            } catch (py::error_already_set& e) {
                raised = std::move(e);
            }
        };
    }
    const bool interruptible = on_main_thread();
    if (interruptible) {
        clear_sigint();
    }
    o.stop = [&] { return raised.has_value() || (interruptible && sigint_seen()); };
    controller::TimerLatency r;
    {
        py::gil_scoped_release released;
        r = controller::measure_timer_latency(o);
    }
    if (raised) {
        throw std::move(*raised);
    }
    if (interruptible && sigint_seen() && PyErr_CheckSignals() != 0) {
        throw py::error_already_set(); // KeyboardInterrupt, as Python raises it
    }
    py::dict d;
    d["cycle"] = secs(r.cycle);
    d["measured"] = secs(r.measured);
    d["wakeups"] = r.wakeups;
    d["skipped_slots"] = r.skipped_slots;
    d["p50"] = secs(r.p50);
    d["p99"] = secs(r.p99);
    d["p999"] = secs(r.p999);
    d["max"] = secs(r.max);
    d["late_half_cycle"] = r.late_half_cycle;
    d["late_whole_cycle"] = r.late_whole_cycle;
    d["verdict"] = verdict_name(r.verdict());
    d["warnings"] = r.warnings;
    py::list windows;
    for (const auto& w : r.windows) {
        windows.append(window_dict(w));
    }
    d["windows"] = windows;
    const controller::TimerWindow* worst = r.worst_window();
    d["worst_window"] = worst != nullptr ? py::object(window_dict(*worst)) : py::none();
    d["text"] = r.to_string();
    return d;
}

} // namespace

void bind_timer_latency(py::module_& m) {
    m.def("measure_timer_latency", &measure, py::arg("cycle") = 0.001, py::arg("seconds") = 10.0,
          py::kw_only(), py::arg("window") = 0.0, py::arg("fifo") = 0, py::arg("cpu") = -1,
          py::arg("lock_memory") = false, py::arg("on_window") = py::none(),
          "How late this machine wakes a periodic thread at `cycle` seconds, measured for "
          "`seconds` exactly as the controller's cyclic thread waits (`codrive latency`, "
          "docs/cli/codrive-latency.md). Returns a dict: wakeups, skipped_slots, p50/p99/p999/"
          "max (seconds), verdict ('sound', 'jittery', 'not sound'), text, windows. With "
          "window=, each window's dict also goes to on_window(dict) as it ends. The GIL is "
          "released while measuring; Ctrl-C ends the run early and raises KeyboardInterrupt.");
}

} // namespace codrive::python
