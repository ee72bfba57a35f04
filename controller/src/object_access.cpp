// SPDX-License-Identifier: Apache-2.0
// Controller::read_object()/write_object(): one object access to a CAN node (SDO) or an EtherCAT
// slave (CoE SDO) through the same DriveTransport the device's axes use.
#include <codrive/controller/controller.hpp>

#include "controller_parts.hpp"
#include "ecat_segment.hpp"

#include <fmt/format.h>

#include <memory>

namespace codrive::controller {

namespace {

/// Runs a completion on the loop thread, never inside the call that started the access: a
/// transport that fails at once (a full queue) calls back synchronously, and the caller's code
/// after read_object()/write_object() must not see its callback already run.
template <class Done, class Result>
struct Deferred {
    EventLoop* loop;
    Done done;
    std::shared_ptr<bool> returned;
    void operator()(Result r) {
        if (*returned) {
            done(std::move(r));
            return;
        }
        loop->post([d = std::move(done), res = std::move(r)]() mutable { d(std::move(res)); });
    }
};

} // namespace

drives::DriveResult<drives::DriveTransport*> Controller::object_transport(std::size_t bus,
                                                                          NodeId node) {
    const auto error = [](ControllerErrc code, std::string sentence) {
        return tl::unexpected(drives::DriveError(make_error_code(code), std::move(sentence)));
    };
    if (!started_) {
        return error(ControllerErrc::NotStarted,
                     "the controller is not started (call start() first)");
    }
    if (stopped_) {
        return error(ControllerErrc::NotStarted, "the controller has shut down");
    }
    if (bus < buses_.size()) {
        auto it = buses_[bus]->nodes.find(node);
        if (it == buses_[bus]->nodes.end() || !it->second->transport) {
            return error(ControllerErrc::NoSuchDevice,
                         fmt::format("node {} is not in the bus file of CAN bus {} ({})", node, bus,
                                     buses_[bus]->config.iface));
        }
        // The CAN transport's SDO client lives on the loop thread in both threading modes.
        return it->second->transport.get();
    }
    const std::size_t seg = bus - buses_.size();
    if (seg >= segments_.size()) {
        return error(ControllerErrc::NoSuchDevice,
                     fmt::format("there is no bus {} ({} CAN bus(es), {} EtherCAT segment(s))", bus,
                                 buses_.size(), segments_.size()));
    }
    EcatSegment& s = *segments_[seg];
    // In Threading::DedicatedCyclic the slave's mailbox rides in the cyclic frame, which the
    // cyclic thread owns: the access is handed to it lock-free and its completion comes back
    // here (HandoffTransport); otherwise the loop runs the cycles and the CoE transport itself.
    drives::DriveTransport* t = s.loop_transport(node);
    if (t == nullptr) {
        return error(ControllerErrc::NoSuchDevice,
                     fmt::format("slave {} is not in the bus file's EtherCAT segment on {}", node,
                                 s.config().iface));
    }
    return t;
}

void Controller::read_object(std::size_t bus, NodeId node, std::uint16_t index,
                             std::uint8_t subindex, ObjectRead done) {
    auto t = object_transport(bus, node);
    if (!t) {
        drives::DriveError why(t.error().code, fmt::format("read of object {:04X}h:{:02X}h: {}",
                                                           index, subindex, t.error().message));
        loop_->post([d = std::move(done), why = std::move(why)]() { d(tl::unexpected(why)); });
        return;
    }
    auto returned = std::make_shared<bool>(false);
    // The transport's error already names the device and the object.
    (*t)->read(index, subindex,
               Deferred<drives::DriveTransport::ReadDone, drives::DriveResult<drives::Bytes>>{
                   loop_.get(), std::move(done), returned});
    *returned = true;
}

void Controller::write_object(std::size_t bus, NodeId node, std::uint16_t index,
                              std::uint8_t subindex, drives::Bytes data, ObjectWritten done) {
    auto t = object_transport(bus, node);
    if (!t) {
        drives::DriveError why(t.error().code, fmt::format("write of object {:04X}h:{:02X}h: {}",
                                                           index, subindex, t.error().message));
        loop_->post([d = std::move(done), why = std::move(why)]() { d(tl::unexpected(why)); });
        return;
    }
    auto returned = std::make_shared<bool>(false);
    (*t)->write(index, subindex, std::move(data),
                Deferred<drives::DriveTransport::WriteDone, drives::DriveVoid>{
                    loop_.get(), std::move(done), returned});
    *returned = true;
}

Duration Controller::cycle_period(std::size_t bus) const {
    if (bus < buses_.size()) {
        return microseconds(buses_[bus]->config.sync_period_us);
    }
    const std::size_t seg = bus - buses_.size();
    return seg < segments_.size() ? microseconds(segments_[seg]->config().cycle_us)
                                  : Duration::zero();
}

} // namespace codrive::controller
