// SPDX-License-Identifier: Apache-2.0
// How a Python call waits on a bus: without the GIL, holding the bus, until the C++ side is done.
#pragma once

#include "bus.hpp"

#include <pybind11/pybind11.h>

#include <chrono>
#include <optional>
#include <utility>

namespace codrive::python {

/// Runs `start(done_callback)` on `bus` and the bus until the callback delivered a result of
/// type R, with the GIL released (other Python threads run meanwhile) and the bus held.
template <typename R, typename Start>
R wait_for_result(Bus& bus, Start&& start) {
    std::optional<R> out;
    {
        pybind11::gil_scoped_release nogil;
        std::lock_guard lock(bus.mutex());
        start([&out](R r) { out.emplace(std::move(r)); });
        // Every C++ request ends by itself (SDO requests have a timeout), so no outer limit.
        bus.run_until([&out] { return out.has_value(); }, Duration::max());
    }
    if (!out) {
        throw std::runtime_error("codrive: the bus stopped before the request ended");
    }
    return std::move(*out);
}

/// Runs `fn()` with the GIL released and the bus held (for short calls that touch the bus).
template <typename Fn>
decltype(auto) with_bus(Bus& bus, Fn&& fn) {
    pybind11::gil_scoped_release nogil;
    std::lock_guard lock(bus.mutex());
    return fn();
}

/// Seconds from Python as a Duration. ValueError if negative or not finite.
Duration seconds_arg(double seconds, const char* what);

} // namespace codrive::python
