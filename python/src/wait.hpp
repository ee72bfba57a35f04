// SPDX-License-Identifier: Apache-2.0
// How a Python call waits on a bus: without the GIL, holding the bus, until the C++ side is done.
#pragma once

#include "bus.hpp"
#include "interrupt.hpp"

#include <pybind11/pybind11.h>

#include <chrono>
#include <cstdint>
#include <mutex>
#include <optional>
#include <thread>
#include <utility>

namespace codrive::python {

/// The bus for one thread: announces the thread (the thread running the bus sees
/// submitters() and lets go at its next wake-up, which interrupt() makes immediate), then holds
/// mutex(). Release the GIL first.
class BusTurn {
public:
    explicit BusTurn(Bus& bus) : bus_(bus) {
        bus.submitters().fetch_add(1);
        // A thread that starts running after this sees submitters() in its predicate first, so
        // only a running one needs the interrupt (a system call a lone caller does not pay).
        if (bus.running().load()) {
            bus.interrupt();
        }
        lock_ = std::unique_lock(bus.mutex());
        bus.submitters().fetch_sub(1);
        bus.handoff().store(false);
    }
    /// Lets go of the bus for the thread that is waiting for it (a result of its came, or it
    /// wants to start a request) and waits until that thread has it, or a millisecond passed.
    void hand_over() {
        bus_.handoff().store(true);
        lock_.unlock();
        const auto until = std::chrono::steady_clock::now() + std::chrono::milliseconds(1);
        while (bus_.handoff().load() && std::chrono::steady_clock::now() < until) {
            std::this_thread::yield();
        }
    }
    /// Takes the bus again after hand_over(), without interrupting anyone: this thread only
    /// waits for a result the bus will deliver to whoever runs it.
    void take_back() {
        lock_.lock();
        bus_.handoff().store(false);
    }

private:
    Bus& bus_;
    std::unique_lock<std::mutex> lock_;
};

/// Runs `start(done_callback)` on `bus` and the bus until the callback delivered a result of
/// type R, with the GIL released (other Python threads run meanwhile). One thread at a time runs
/// the bus, for everyone's requests: it runs with no time limit of its own (so the event loop's
/// one-system-call-per-frame path stays on) and lets go of the bus only when another thread wants
/// to start a request or another thread's result came. So requests from several threads
/// (asyncio's executor) to different nodes run side by side in the one loop, each returns as
/// soon as its own result is in, and a lone caller pays nothing for the sharing.
///
/// Ctrl-C on the main thread waiting on a real bus (interrupt.hpp) ends every SDO transfer on the
/// bus at once (the nodes get abort 0x08000000), waits for this request's end, and raises
/// KeyboardInterrupt instead of returning.
template <typename R, typename Start>
R wait_for_result(Bus& bus, Start&& start) {
    std::optional<R> out;
    const bool interruptible = !bus.simulated() && on_main_thread();
    bool interrupted = false;
    if (interruptible) {
        clear_sigint();
    }
    const auto interrupt_pending = [&] { return interruptible && !interrupted && sigint_seen(); };
    {
        pybind11::gil_scoped_release nogil;
        BusTurn turn(bus);
        start([&out, &bus](R r) {
            out.emplace(std::move(r));
            bus.delivered().fetch_add(1);
        });
        // Every C++ request ends by itself (SDO requests have a timeout), so no outer limit. A
        // simulated network runs on its own clock, one caller at a time: it is not shared.
        while (!out && !bus.simulated()) {
            const std::uint64_t seen = bus.delivered().load();
            bus.running().store(true);
            bus.run_until(
                [&] {
                    return out.has_value() || bus.submitters().load() > 0 ||
                           bus.delivered().load() != seen || interrupt_pending();
                },
                Duration::max());
            bus.running().store(false);
            if (!out && interrupt_pending()) {
                interrupted = true;
                bus.sdo_clients().cancel_all("interrupted by KeyboardInterrupt");
                continue; // an SDO request has its result now; others end on their timeout
            }
            if (!out) {
                turn.hand_over();
                turn.take_back();
            }
        }
        if (!out) {
            bus.run_until([&out] { return out.has_value(); }, Duration::max());
        }
    }
    if (interrupted && PyErr_CheckSignals() != 0) {
        throw pybind11::error_already_set(); // KeyboardInterrupt (or what the handler raised)
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
    BusTurn turn(bus);
    return fn();
}

/// Seconds from Python as a Duration. ValueError if negative or not finite.
Duration seconds_arg(double seconds, const char* what);

} // namespace codrive::python
