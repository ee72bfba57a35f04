// SPDX-License-Identifier: Apache-2.0
// In-process CAN network: ordered delivery with latency, fault injection and bus-off.
#include <codrive/core/virtual_bus.hpp>

#include <algorithm>

namespace codrive {

VoidResult VirtualBus::send(const Frame& frame) {
    if (!frame.valid()) {
        return fail(CoreErrc::InvalidFrame);
    }
    if (!connected_) {
        return fail(CoreErrc::InterfaceDown);
    }
    return net_.transmit(*this, frame);
}

VirtualNetwork::VirtualNetwork(const IClock& clock, Duration latency)
    : clock_(clock), latency_(latency) {}

VirtualBus& VirtualNetwork::endpoint(std::string name) {
    endpoints_.push_back(std::unique_ptr<VirtualBus>(new VirtualBus(*this, std::move(name))));
    return *endpoints_.back();
}

void VirtualNetwork::set_fault_rates(const FaultRates& rates) {
    rates_ = rates;
    have_rates_ = rates.drop > 0 || rates.duplicate > 0 || rates.reorder > 0 || rates.corrupt > 0;
    rng_.seed(rates.seed);
}

FaultAction VirtualNetwork::decide(const std::string& sender, const Frame& frame) {
    if (fault_filter_) {
        return fault_filter_(sender, frame);
    }
    FaultAction a;
    if (!have_rates_) {
        return a;
    }
    std::uniform_real_distribution<double> u(0.0, 1.0);
    a.drop = u(rng_) < rates_.drop;
    a.duplicates = u(rng_) < rates_.duplicate ? 1 : 0;
    if (u(rng_) < rates_.reorder) {
        a.delay = rates_.reorder_delay;
    }
    a.corrupt = u(rng_) < rates_.corrupt;
    return a;
}

VoidResult VirtualNetwork::transmit(VirtualBus& from, const Frame& frame) {
    if (bus_off_) {
        return fail(CoreErrc::BusOff);
    }
    ++from.stats_.tx_frames;
    ++frames_sent_;
    const FaultAction action = decide(from.name(), frame);
    if (action.drop) {
        ++frames_dropped_;
        return {};
    }
    Frame f = frame;
    if (action.corrupt && f.len > 0 && !f.rtr()) {
        const std::size_t byte = static_cast<std::size_t>(rng_() % f.len);
        f.data[byte] = static_cast<std::uint8_t>(f.data[byte] ^ (1U << (rng_() % 8)));
    }
    const TimePoint due = clock_.now() + latency_ + action.delay;
    for (int copy = 0; copy <= action.duplicates; ++copy) {
        InFlight item{due, seq_++, &from, f};
        // Keep the queue sorted by (due, seq): frames with equal due time stay in send order.
        auto pos = std::upper_bound(queue_.begin(), queue_.end(), item,
                                    [](const InFlight& a, const InFlight& b) {
                                        return a.due < b.due || (a.due == b.due && a.seq < b.seq);
                                    });
        queue_.insert(pos, item);
    }
    return {};
}

std::size_t VirtualNetwork::deliver() {
    if (delivering_) {
        return 0; // frames sent from a handler are picked up by the outer loop
    }
    delivering_ = true;
    std::size_t delivered = 0;
    // Bounded: a pair of handlers that answer each other forever cannot hang a test.
    constexpr std::size_t kMaxPerCall = 10'000'000;
    while (!queue_.empty() && queue_.front().due <= clock_.now() && delivered < kMaxPerCall) {
        InFlight item = queue_.front();
        queue_.pop_front();
        if (recording_) {
            recorded_.push_back(item.frame);
        }
        for (auto& ep : endpoints_) {
            if (!ep->connected_ || (ep.get() == item.from && !ep->loopback_)) {
                continue;
            }
            ++ep->stats_.rx_frames;
            if (ep->frame_handler_) {
                ep->frame_handler_(item.frame, item.due);
            }
        }
        ++delivered;
    }
    delivering_ = false;
    return delivered;
}

TimePoint VirtualNetwork::next_deadline() const {
    return queue_.empty() ? kNever : queue_.front().due;
}

void VirtualNetwork::on_tick(TimePoint /*now*/) {
    deliver();
}

void VirtualNetwork::run_until(FakeClock& clock, TimePoint until, std::vector<ITimed*> services) {
    services.push_back(this);
    for (std::size_t guard = 0; guard < 100'000'000; ++guard) {
        deliver();
        for (ITimed* s : services) {
            if (s->next_deadline() <= clock.now()) {
                s->on_tick(clock.now());
            }
        }
        deliver();
        TimePoint next = kNever;
        for (ITimed* s : services) {
            next = std::min(next, s->next_deadline());
        }
        if (next <= clock.now()) {
            continue; // more work due now
        }
        if (next > until) {
            clock.set(std::max(clock.now(), until));
            deliver();
            return;
        }
        clock.set(next);
    }
}

void VirtualNetwork::set_bus_off(bool on) {
    if (on == bus_off_) {
        return;
    }
    bus_off_ = on;
    if (on) {
        queue_.clear();
    }
    for (auto& ep : endpoints_) {
        if (!ep->event_handler_) {
            continue;
        }
        if (on) {
            BusEvent e;
            e.kind = BusEvent::Kind::StateChanged;
            e.state = BusState::BusOff;
            ep->event_handler_(e);
        } else {
            BusEvent restarted;
            restarted.kind = BusEvent::Kind::Restarted;
            ep->event_handler_(restarted);
            BusEvent active;
            active.kind = BusEvent::Kind::StateChanged;
            active.state = BusState::ErrorActive;
            ep->event_handler_(active);
        }
    }
}

} // namespace codrive
