// SPDX-License-Identifier: Apache-2.0
// How long a Controller takes to stop: another thread calls request_stop() after `after`, and
// the time until run() (safe shutdown included) returns is measured.
#pragma once

#include <codrive/controller/controller.hpp>

#include <atomic>
#include <chrono>
#include <thread>

namespace codrive::testing {

/// Runs `c.run()` on this thread, requests a stop from another one after `after`; returns the
/// milliseconds from the request to run() returning.
inline double
run_and_measure_stop(controller::Controller& c,
                     std::chrono::milliseconds after = std::chrono::milliseconds(100)) {
    std::atomic<std::int64_t> requested_ns{0};
    std::thread stopper([&] {
        std::this_thread::sleep_for(after);
        requested_ns = SteadyClock::now().time_since_epoch().count();
        c.request_stop();
    });
    c.run(); // safe shutdown, then returns
    const auto returned = SteadyClock::now().time_since_epoch().count();
    stopper.join();
    return static_cast<double>(returned - requested_ns.load()) / 1e6;
}

} // namespace codrive::testing
