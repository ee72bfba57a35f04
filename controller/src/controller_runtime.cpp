// SPDX-License-Identifier: Apache-2.0
// The controller at run time: the loop (run, run_for, run_until, post), the dedicated cyclic
// thread and its hand-off to the acyclic side, the cycle callback and the published statistics.
#include <codrive/controller/controller.hpp>

#include "controller_parts.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <csignal>

namespace codrive::controller {

tl::expected<void, ControllerError> Controller::start_cyclic_thread() {
    // The segments cycled from the loop while the CAN nodes booted; the cyclic thread owns
    // their cycles from now on.
    for (auto& seg : segments_) {
        loop_->remove_timed(seg.get());
    }
    pump_ = std::make_unique<Pump>(*this);
    loop_->add_timed(pump_.get());
    cyclic_thread_ = std::thread([this] { cyclic_main(); });
    // The thread reports its real-time warnings before its first cycle.
    while (!cyclic_ready_.load(std::memory_order_acquire)) {
        std::this_thread::yield();
    }
    for (const auto& w : cyclic_warnings_) {
        emit("warning: " + w);
    }
    return {};
}

void Controller::for_each_axis(const std::function<void(drives::Axis&)>& fn) {
    for (auto& b : buses_) {
        for (auto& [id, n] : b->nodes) {
            for (auto& a : n->axes) {
                fn(*a);
            }
        }
    }
    for (auto& seg : segments_) {
        seg->for_each_axis(fn);
    }
}

void Controller::pump_acyclic() {
    for (auto& b : buses_) {
        for (auto& [id, n] : b->nodes) {
            if (n->handoff) {
                n->handoff->pump_requests();
            }
        }
        pdo::PdoEvent e;
        while (b->pdo_events.pop(e)) {
            emit(pdo::to_string(e), pdo::event_key(e));
        }
    }
    const TimePoint now = loop_->now();
    for (auto& seg : segments_) {
        seg->acyclic_step(now);
    }
}

void Controller::set_cycle_callback(CycleCallback cb) {
    if (!dedicated() || !cyclic_thread_.joinable() ||
        std::this_thread::get_id() == cyclic_thread_.get_id()) {
        cycle_cb_ = std::move(cb); // no other thread calls it
        return;
    }
    // The cyclic thread calls cycle_cb_: it swaps the new one in at its next wake-up (a swap of
    // two std::function objects allocates nothing); the old one comes back in pending_cb_ and is
    // destroyed here, off the cyclic thread.
    pending_cb_ = std::move(cb);
    cb_handoff_.store(true, std::memory_order_release);
    while (cb_handoff_.load(std::memory_order_acquire)) {
        std::this_thread::yield();
    }
    pending_cb_ = nullptr;
}

void Controller::cyclic_main() {
    cyclic_warnings_ = apply_realtime(options_.realtime);
    cyclic_ready_.store(true, std::memory_order_release);
    bool safe_stop_started = false;
    while (!cyclic_exit_.load(std::memory_order_acquire)) {
        // Sleep until the earliest SYNC (at most 20 ms, to notice a stop request).
        TimePoint wake = SteadyClock::now() + milliseconds(20);
        for (auto& b : buses_) {
            wake = std::min(wake, b->sync->next_deadline());
        }
        for (auto& seg : segments_) {
            wake = std::min(wake, seg->next_cycle());
        }
        sleep_until(wake);
        if (cb_handoff_.load(std::memory_order_acquire)) {
            std::swap(cycle_cb_, pending_cb_);
            cb_handoff_.store(false, std::memory_order_release);
        }
        const TimePoint now = SteadyClock::now();
        for (auto& b : buses_) {
            (void)b->cyclic_socket->read_available(); // this cycle's TPDOs into the image
            for (auto& [id, n] : b->nodes) {
                if (n->handoff) {
                    n->handoff->deliver_completions();
                }
                if (const std::uint16_t code = n->emcy_code.exchange(0); code != 0) {
                    for (auto& a : n->axes) {
                        a->note_error_code(code);
                    }
                }
            }
            if (b->sync->next_deadline() <= now) {
                b->sync->on_tick(now); // on_sync(): callback, axes, then SYNC + RPDOs
            }
            if (b->pdo->next_deadline() <= now) {
                b->pdo->on_tick(now);
            }
            for (auto& [id, n] : b->nodes) {
                for (auto& a : n->axes) {
                    if (a->next_deadline() <= now) {
                        a->on_tick(now); // operation timeouts (SDO polling without PDOs)
                    }
                }
            }
            (void)b->cyclic_socket->flush();
        }
        for (auto& seg : segments_) {
            seg->cyclic_step(now);
        }
        if (safe_stop_requested_.load(std::memory_order_acquire) && !safe_stop_started) {
            safe_stop_started = true;
            begin_safe_stop(now);
        }
        if (safe_stop_started && safe_stop_over(now)) {
            end_safe_stop();
            for (auto& b : buses_) {
                b->sync->stop();
            }
            axes_safe_.store(true, std::memory_order_release);
            safe_stop_started = false;
        }
    }
}

bool Controller::on_sync(Bus& b, const CycleInfo& info, const Frame& sync) {
    // Inputs of the last cycle are in the image: let the application compute set-points, the
    // axes turn them into controlwords and targets, then the SYNC and the RPDOs behind it go out
    // together (one sendmmsg() per cycle on SocketCAN).
    if (cycle_cb_) {
        cycle_cb_(info);
    }
    for (auto& [id, n] : b.nodes) {
        if (!n->image_bound) {
            continue;
        }
        for (auto& a : n->axes) {
            a->on_cycle(info.actual);
        }
    }
    const bool taken = b.pdo->on_sync(info.cycle, info.actual, sync);
    publish_cyclic_stats(false);
    return taken;
}

void Controller::run_loop_until(const std::function<bool()>& pred, TimePoint deadline) {
    while (!pred()) {
        const TimePoint now = loop_->now();
        if (now >= deadline) {
            return;
        }
        (void)loop_->run_until(pred, deadline - now);
    }
}

void Controller::run() {
    while (!stop_requested_ && !stopped_) {
        (void)loop_->poll_once(milliseconds(50));
    }
    shutdown();
}

void Controller::run_for(Duration d) {
    const TimePoint end = loop_->now() + d;
    // One clock read per turn: with two, the deadline could pass between the check and the
    // wait. A negative wait was once poll_once()'s "no limit" (a hang seen on a VM that
    // stalls); it now counts as zero, and only EventLoop::kForever waits without a limit.
    while (!stop_requested_) {
        const Duration left = end - loop_->now();
        if (left <= Duration::zero()) {
            break;
        }
        (void)loop_->poll_once(std::min<Duration>(left, milliseconds(50)));
    }
}

bool Controller::run_until(const std::function<bool()>& pred, Duration timeout) {
    return loop_->run_until([&] { return pred() || stop_requested_.load(); }, timeout) && pred();
}

void Controller::post(std::function<void()> fn) {
    loop_->post(std::move(fn));
}

void Controller::publish_cyclic_stats(bool exact_percentiles) {
    // Runs on the cycle owner: reads only what that thread owns (SYNC producers, PDO engines,
    // segments' cycle counters and histograms), allocates nothing.
    StatsCell& cell = *stats_cell_;
    const bool refresh = exact_percentiles || cell.publications % StatsCell::kPercentileEvery == 0;
    ++cell.publications;
    ControllerStats s;
    Duration p50{0};
    Duration p99{0};
    const auto add_period = [&](const sync::PeriodStats& pe) {
        if (refresh) {
            p50 = std::max(p50, pe.p50());
            p99 = std::max(p99, pe.p99());
        }
        s.period_error_max = std::max(s.period_error_max, pe.max());
    };
    for (const auto& b : buses_) {
        if (b->sync) {
            s.cycles += b->sync->sent();
            s.overruns += b->sync->skipped();
            add_period(b->sync->period_error());
        }
        if (b->pdo) {
            s.tpdos_received += b->pdo->stats().tpdos_received;
            s.tpdos_missing += b->pdo->stats().tpdos_missing;
            s.rpdos_sent += b->pdo->stats().rpdos_sent;
        }
    }
    for (const auto& seg : segments_) {
        s.cycles += seg->cycles();
        s.overruns += seg->overruns();
        add_period(seg->period_error());
        s.ecat_frame_errors += seg->frame_errors();
        s.ecat_late_frames += seg->late_frames();
    }
    if (refresh) {
        cell.p50 = p50;
        cell.p99 = p99;
    }
    s.period_error_p50 = cell.p50;
    s.period_error_p99 = cell.p99;
    cell.snapshot.store(s);
}

ControllerStats Controller::stats() const {
    ControllerStats s = stats_cell_->snapshot.load();
    // The loop thread's own figures.
    for (const auto& b : buses_) {
        if (b->master) {
            for (auto* n : const_cast<master::Master&>(*b->master).nodes()) {
                s.sdo_completed += n->sdo().stats().completed;
                s.sdo_failed += n->sdo().stats().failed;
            }
        }
        s.bus_errors += b->bus_errors + (b->bus != nullptr ? b->bus->stats().error_frames : 0);
    }
    return s;
}

} // namespace codrive::controller
