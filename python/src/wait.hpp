// SPDX-License-Identifier: Apache-2.0
// How a Python call waits on a bus: without the GIL, holding the bus, until the C++ side is done.
#pragma once

#include "bus.hpp"

#include <pybind11/pybind11.h>

#include <chrono>
#include <optional>
#include <thread>
#include <utility>

namespace codrive::python {

/// How long one thread runs a bus before others waiting to start a request get it.
inline constexpr Duration kBusSlice = std::chrono::milliseconds(2);

/// Runs `start(done_callback)` on `bus` and the bus until the callback delivered a result of
/// type R, with the GIL released (other Python threads run meanwhile). The bus is held while
/// it runs, in slices of kBusSlice: between slices a thread that is waiting to start its own
/// request gets the bus first, so requests from several threads (asyncio's executor) to
/// different nodes run side by side in the one loop instead of one after the other.
template <typename R, typename Start>
R wait_for_result(Bus& bus, Start&& start) {
    std::optional<R> out;
    {
        pybind11::gil_scoped_release nogil;
        bus.submitters().fetch_add(1);
        {
            std::lock_guard lock(bus.mutex());
            start([&out](R r) { out.emplace(std::move(r)); });
        }
        bus.submitters().fetch_sub(1);
        // Every C++ request ends by itself (SDO requests have a timeout), so no outer limit. A
        // simulated network runs on its own clock, one caller at a time: it is not sliced.
        const Duration slice = bus.simulated() ? Duration::max() : kBusSlice;
        for (;;) {
            {
                std::lock_guard lock(bus.mutex());
                if (out || bus.run_until([&out] { return out.has_value(); }, slice) ||
                    bus.simulated()) {
                    break;
                }
            }
            while (bus.submitters().load() > 0) {
                std::this_thread::yield(); // let the other thread start its request
            }
        }
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
