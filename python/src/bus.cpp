// SPDX-License-Identifier: Apache-2.0
// The buses Python talks through: SocketCAN via the blocking SDO client's loop, and the virtual
// network on simulated time.
#include "bus.hpp"

#include <codrive/core/socket_can_bus.hpp>

#include <algorithm>

namespace codrive::python {

void Bus::attach(ICanBus& can, sdo::SdoClientManager& clients) {
    clients_ = &clients;
    nmt_ = std::make_unique<nmt::NmtMaster>(can);
    can.set_frame_handler([this](const Frame& f, TimePoint t) {
        (void)clients_->on_frame(f, t);
        nmt_->on_frame(f, t);
    });
}

tl::expected<std::shared_ptr<SocketBus>, std::string> SocketBus::open(const std::string& ifname,
                                                                      Duration default_timeout) {
    sdo::ClientConfig defaults;
    defaults.timeout = default_timeout;
    auto blocking = sdo::BlockingSdo::open(ifname, defaults);
    if (!blocking) {
        return tl::unexpected(describe_can_open_error(ifname, blocking.error()));
    }
    return std::shared_ptr<SocketBus>(new SocketBus(std::move(*blocking), ifname, default_timeout));
}

SocketBus::SocketBus(std::unique_ptr<sdo::BlockingSdo> blocking, std::string ifname,
                     Duration default_timeout)
    : Bus(default_timeout), blocking_(std::move(blocking)), ifname_(std::move(ifname)) {
    attach(blocking_->bus(), blocking_->manager());
}

bool SocketBus::run_until(const std::function<bool()>& done, Duration limit) {
    if (done()) {
        (void)blocking_->loop().poll_once(Duration{0});
        return true;
    }
    if (limit != Duration::max()) {
        return blocking_->loop().run_until(done, limit);
    }
    // No limit (a transfer, which always ends by itself): in day-long steps, as BlockingSdo
    // does, since the loop adds the limit to the current time.
    while (!blocking_->loop().run_until(done, std::chrono::hours(24))) {
    }
    return true;
}

VirtualNet::VirtualNet(Duration default_timeout)
    : Bus(default_timeout), start_(clock_.now()), net_(clock_), master_(net_.endpoint("master")) {
    sdo::ClientConfig defaults;
    defaults.timeout = default_timeout;
    clients_ = std::make_unique<sdo::SdoClientManager>(master_, clock_, defaults);
    attach(master_, *clients_);
}

VirtualNet::~VirtualNet() {
    master_.set_frame_handler(nullptr);
}

void VirtualNet::remove_service(ITimed* service) {
    services_.erase(std::remove(services_.begin(), services_.end(), service), services_.end());
}

double VirtualNet::seconds() const {
    return std::chrono::duration<double>(clock_.now() - start_).count();
}

bool VirtualNet::run_until(const std::function<bool()>& done, Duration limit) {
    std::vector<ITimed*> services = services_;
    services.push_back(clients_.get());
    const TimePoint end = limit == Duration::max() ? kNever : clock_.now() + limit;
    // Everything due now first, then from deadline to deadline (VirtualNetwork::run_until
    // delivers and ticks at each), checking `done` in between.
    net_.run_until(clock_, clock_.now(), services);
    while (!done()) {
        TimePoint next = net_.next_deadline();
        for (const ITimed* s : services) {
            next = std::min(next, s->next_deadline());
        }
        if (next == kNever || next > end) {
            if (end != kNever) {
                net_.run_until(clock_, end, services);
            }
            return done();
        }
        net_.run_until(clock_, std::max(next, clock_.now()), services);
    }
    return true;
}

} // namespace codrive::python
