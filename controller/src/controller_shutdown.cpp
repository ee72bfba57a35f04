// SPDX-License-Identifier: Apache-2.0
// The controller's end: the safe stop of every axis within the shutdown budget, NMT
// pre-operational and EtherCAT PRE-OP, an abandoned boot-up, stop requests and SIGINT/SIGTERM.
#include <codrive/controller/controller.hpp>

#include "controller_parts.hpp"

#include <codrive/drives/safe_stop.hpp>

#include <fmt/format.h>

#include <algorithm>
#include <cerrno>
#include <csignal>
#include <ctime>

namespace codrive::controller {

namespace {

/// The controller SIGINT/SIGTERM stop (stop_on_signals()); atomic because the handler reads it.
std::atomic<Controller*> g_signal_target{nullptr};
static_assert(std::atomic<Controller*>::is_always_lock_free, "read in a signal handler");

} // namespace

Controller::~Controller() {
    if (started_ && !stopped_) {
        shutdown();
    }
    Controller* self = this;
    (void)g_signal_target.compare_exchange_strong(self, nullptr);
    if (limiter_) {
        loop_->remove_timed(limiter_.get());
    }
    for (auto& b : buses_) {
        for (auto& [id, n] : b->nodes) {
            for (auto& a : n->axes) {
                loop_->remove_timed(a.get());
            }
        }
        if (b->master) {
            loop_->remove_timed(b->master.get());
        }
        if (b->pdo) {
            loop_->remove_timed(b->pdo.get());
        }
        if (b->sync) {
            loop_->remove_timed(b->sync.get());
        }
    }
    for (auto& seg : segments_) {
        loop_->remove_timed(seg.get());
    }
}

void Controller::begin_safe_stop(TimePoint now) {
    safe_stop_ = SafeStop{true, 0, now + options_.shutdown_timeout};
    for_each_axis([this](drives::Axis& a) {
        drives::Axis* ax = &a;
        ++safe_stop_.pending; // before: done may run before safe_stop() returns
        const bool started = drives::safe_stop(
            a, safe_stop_.deadline, RealClock::instance(), [this, ax](drives::DriveVoid r) {
                if (!safe_stop_.active) {
                    return; // cancelled by end_safe_stop(): the shutdown is over
                }
                if (!r && !dedicated()) {
                    emit(fmt::format("{}: safe stop during shutdown failed: {}", ax->name(),
                                     r.error().message));
                }
                --safe_stop_.pending;
            });
        if (!started) {
            --safe_stop_.pending;
        }
    });
}

bool Controller::safe_stop_over(TimePoint now) const {
    return safe_stop_.pending == 0 || now >= safe_stop_.deadline;
}

void Controller::end_safe_stop() {
    // Out of time: the operations still running on drives that did not answer end here, so no
    // callback of this shutdown runs during a later run_for().
    safe_stop_.active = false;
    for_each_axis([](drives::Axis& a) {
        if (a.busy()) {
            a.cancel();
        }
    });
    safe_stop_.pending = 0;
}

void Controller::stop_buses() {
    for (auto& b : buses_) {
        (void)b->master->nmt().enter_pre_operational(0);
        if (b->sync) {
            b->sync->stop();
        }
    }
    for (auto& seg : segments_) {
        seg->stop(); // ESM back to PRE-OP: outputs no longer applied
        loop_->remove_timed(seg.get());
    }
    // Let the NMT frames and any queued frames leave.
    const TimePoint flushed = loop_->now() + milliseconds(20);
    run_loop_until([] { return false; }, flushed);
}

tl::expected<void, ControllerError> Controller::abandon_start(std::string why) {
    // The boot-up state machines must not start a node after the NMT command below: they get
    // no more frames and no more ticks.
    for (auto& b : buses_) {
        if (b->master) {
            loop_->remove_timed(b->master.get());
            b->bus->set_frame_handler(nullptr);
            b->bus->set_event_handler(nullptr);
        }
    }
    stop_buses();
    if (caller_schedule_) {
        caller_schedule_->restore();
        caller_schedule_.reset();
    }
    return tl::unexpected(ControllerError(ControllerErrc::StopRequested, std::move(why)));
}

void Controller::shutdown() {
    if (!started_ || stopped_) {
        return;
    }
    stopped_ = true;
    if (dedicated()) {
        // The axes belong to the cyclic thread: it stops them while this thread keeps serving
        // their SDO accesses, then it stops SYNC and exits.
        safe_stop_requested_.store(true, std::memory_order_release);
        run_loop_until([&] { return axes_safe_.load(std::memory_order_acquire); },
                       loop_->now() + options_.shutdown_timeout + milliseconds(100));
        cyclic_exit_.store(true, std::memory_order_release);
        if (cyclic_thread_.joinable()) {
            cyclic_thread_.join();
        }
        if (safe_stop_.active) {
            end_safe_stop(); // the cyclic thread did not get to it; it has exited now
        }
        loop_->remove_timed(pump_.get());
        pump_acyclic(); // the last PDO events
    } else {
        begin_safe_stop(loop_->now());
        run_loop_until([&] { return safe_stop_over(loop_->now()); }, safe_stop_.deadline);
        end_safe_stop();
    }
    for_each_axis([this](drives::Axis& a) {
        if (a.state() == drives::cia402::State::QuickStopActive) {
            // Not disabled on purpose: disable voltage during the ramp would let it coast.
            emit(fmt::format("{}: still QUICK STOP ACTIVE after the safe shutdown: no standstill "
                             "(statusword bit 10) within {:.0f} ms; left decelerating on its "
                             "quick-stop ramp, not disabled",
                             a.name(), to_ms(options_.shutdown_timeout)));
        } else if (drives::needs_safe_stop(a.state())) {
            emit(fmt::format("{}: still {} after the safe shutdown: the drive did not confirm "
                             "quick stop and disable within {:.0f} ms",
                             a.name(), drives::cia402::to_string(a.state()),
                             to_ms(options_.shutdown_timeout)));
        }
    });
    // No thread cycles the segments any more (the cyclic thread has been joined, or the loop
    // ran the cycles): an object access still waiting for its slave would never call back.
    for (auto& seg : segments_) {
        seg->abandon_object_accesses("the controller shut down before the slave answered");
    }
    // The same on CAN: an SDO still waiting for its node would end only if someone ran the
    // loop on to its timeout (not after a stop request), and then as "timed out". Its server
    // gets the abort (0x08000000) while the bus is still up.
    for (auto& b : buses_) {
        if (b->master) {
            (void)b->master->sdo().cancel_all("the controller shut down before the node answered");
        }
    }
    stop_buses();
    if (caller_schedule_) {
        caller_schedule_->restore();
        caller_schedule_.reset();
    }
    publish_cyclic_stats(true); // cycles have ended (cyclic thread joined): exact figures
}

void Controller::request_stop() {
    stop_requested_ = true;
    if (loop_) {
        loop_->stop(); // an atomic store and an eventfd write: async-signal-safe
    }
}

void Controller::on_signal(int sig) {
    if (Controller* c = g_signal_target.load(); c != nullptr) {
        int none = 0;
        (void)c->stop_signal_.compare_exchange_strong(none, sig); // the first signal counts
        c->request_stop();
    }
}

void Controller::stop_on_signals() {
    g_signal_target = this;
    struct sigaction sa {};
    sa.sa_handler = &Controller::on_signal;
    sigemptyset(&sa.sa_mask);
    sa.sa_flags = SA_RESTART; // stdio and blocking calls elsewhere need not handle EINTR
    (void)::sigaction(SIGINT, &sa, nullptr);
    (void)::sigaction(SIGTERM, &sa, nullptr);
}

} // namespace codrive::controller
