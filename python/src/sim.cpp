// SPDX-License-Identifier: Apache-2.0
// codrive.sim.VirtualDrive: a simulated drive (codrive::sim::SimDevice) on a VirtualNetwork.
#include "errors.hpp"
#include "module.hpp"
#include "wait.hpp"

#include <codrive/drives/cia402.hpp>
#include <codrive/sim/profile.hpp>
#include <codrive/sim/sim_device.hpp>

namespace py = pybind11;

namespace codrive::python {

namespace {

/// One simulated node on a VirtualNetwork, alive as long as the Python object (it leaves the
/// network, like a powered-off node, when collected).
class VirtualDrive {
public:
    VirtualDrive(std::shared_ptr<VirtualNet> net, long node, const std::string& profile,
                 unsigned axes)
        : net_(std::move(net)) {
        if (node < 1 || node > kMaxNodeId) {
            throw py::value_error("simulated node id " + std::to_string(node) + " is not 1..127");
        }
        const sim::SimProfile* p = sim::find_profile(profile);
        if (p == nullptr) {
            std::string names;
            for (const auto* q : sim::all_profiles()) {
                names += (names.empty() ? "" : ", ") + std::string(q->name());
            }
            throw py::value_error("unknown drive profile '" + profile + "' (known: " + names + ")");
        }
        sim::SimDeviceConfig config;
        config.node = static_cast<NodeId>(node);
        config.profile = p;
        config.axes = axes;
        with_bus(*net_, [&] {
            endpoint_ = &net_->endpoint("node " + std::to_string(node));
            device_ = std::make_unique<sim::SimDevice>(*endpoint_, config);
            endpoint_->set_frame_handler(
                [d = device_.get()](const Frame& f, TimePoint t) { d->on_frame(f, t); });
            net_->add_service(device_.get());
            device_->start(net_->now()); // power-on: boot-up, pre-operational
            // Deliver the boot-up now: a transfer started before it would see it as a reboot.
            return net_->run_until([] { return true; }, Duration{0});
        });
    }
    ~VirtualDrive() {
        py::gil_scoped_release nogil;
        std::lock_guard lock(net_->mutex());
        net_->remove_service(device_.get());
        endpoint_->set_frame_handler(nullptr);
        endpoint_->set_connected(false);
    }
    VirtualDrive(const VirtualDrive&) = delete;
    VirtualDrive& operator=(const VirtualDrive&) = delete;

    [[nodiscard]] NodeId node() const { return device_->node(); }
    [[nodiscard]] std::string profile() const { return std::string(device_->profile().name()); }
    std::size_t axes() {
        return with_bus(*net_, [&] { return device_->axis_count(); });
    }
    std::string nmt_state() {
        return with_bus(*net_, [&] { return std::string(nmt::to_string(device_->nmt_state())); });
    }
    std::uint16_t statusword(unsigned axis) {
        return with_bus(*net_, [&] { return axis_at(axis).statusword(); });
    }
    void inject(unsigned axis, const std::string& kind) {
        sim::FaultKind k{};
        if (!sim::parse_fault_kind(kind, k)) {
            throw py::value_error("unknown fault '" + kind +
                                  "' (sto, overcurrent, following-error, heartbeat, reset)");
        }
        with_bus(*net_, [&] {
            (void)axis_at(axis);
            device_->inject(axis - 1, k, net_->now());
            return 0;
        });
    }
    std::string summary() {
        return with_bus(*net_, [&] { return device_->summary(); });
    }

private:
    sim::DriveCore& axis_at(unsigned axis) {
        if (axis < 1 || axis > device_->axis_count()) {
            throw std::out_of_range("node " + std::to_string(device_->node()) + " has axes 1.." +
                                    std::to_string(device_->axis_count()) + ", not " +
                                    std::to_string(axis));
        }
        return device_->axis(axis - 1);
    }

    std::shared_ptr<VirtualNet> net_;
    VirtualBus* endpoint_ = nullptr;
    std::unique_ptr<sim::SimDevice> device_;
};

} // namespace

void bind_sim(py::module_& m) {
    py::module_ s = m.def_submodule("sim", "Simulated drives (the codrive::sim library).");
    s.attr("CONTROL_OBJECT") = sim::kControlObject;
    s.def(
        "control_subindex",
        [](const std::string& kind) {
            sim::FaultKind k{};
            if (!sim::parse_fault_kind(kind, k)) {
                throw py::value_error("unknown fault '" + kind +
                                      "' (sto, overcurrent, following-error, heartbeat, reset)");
            }
            switch (k) {
            case sim::FaultKind::Sto:
                return sim::kControlSto;
            case sim::FaultKind::OverCurrent:
                return sim::kControlOverCurrent;
            case sim::FaultKind::FollowingError:
                return sim::kControlFollowingError;
            case sim::FaultKind::HeartbeatLoss:
                return sim::kControlHeartbeatLoss;
            case sim::FaultKind::NodeReset:
                break;
            }
            return sim::kControlNodeReset;
        },
        py::arg("fault"),
        "The sub-index of the simulator's control object (CONTROL_OBJECT + axis - 1) that "
        "injects `fault` when 1 is written (docs/codrive-sim.md, Fault injection).");
    py::class_<VirtualDrive>(
        s, "VirtualDrive",
        "A simulated CiA 402 drive (codrive::sim::SimDevice: object dictionary from the "
        "profile, SDO server, NMT, heartbeat, EMCY, PDO, motor model) on a VirtualNetwork. It "
        "boots (boot-up, PRE-OPERATIONAL) when made and leaves the network when collected.")
        .def(py::init<std::shared_ptr<VirtualNet>, long, const std::string&, unsigned>(),
             py::arg("network"), py::arg("node"), py::arg("profile") = "akd2g", py::arg("axes") = 0,
             "profile: 'akd2g', 'ds-bvs' or 'fio'; axes: 0 for the profile's default.")
        .def_property_readonly("node", &VirtualDrive::node)
        .def_property_readonly("profile", &VirtualDrive::profile)
        .def_property_readonly("axes", &VirtualDrive::axes, "Number of axes.")
        .def_property_readonly("nmt_state", &VirtualDrive::nmt_state, "The device's own NMT state.")
        .def("statusword", &VirtualDrive::statusword, py::arg("axis") = 1,
             "The statusword (6041h) of `axis` (1-based), read from the simulation.")
        .def("inject", &VirtualDrive::inject, py::arg("axis"), py::arg("fault"),
             "Injects a fault on `axis` (1-based): 'sto', 'overcurrent', 'following-error', "
             "'heartbeat' or 'reset' (the whole node); the drive reports it with EMCY and "
             "603Fh as its manual says.")
        .def("__repr__",
             [](VirtualDrive& d) { return "<codrive.sim.VirtualDrive " + d.summary() + ">"; });
}

} // namespace codrive::python
