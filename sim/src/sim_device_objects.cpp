// SPDX-License-Identifier: Apache-2.0
// The communication objects of a simulated node (CiA 301 §7.5) and its EDS description.
#include <codrive/sim/sim_device.hpp>

#include "error_history.hpp"
#include "parameter_store.hpp"

#include <codrive/core/cob_id.hpp>
#include <codrive/drives/canopen_transport.hpp>
#include <codrive/pdo/od_objects.hpp>
#include <codrive/pdo/quirks.hpp>

namespace codrive::sim {

namespace {

Value u(DataType t, std::uint64_t v) {
    if (auto r = Value::from_uint(t, v)) {
        return *r;
    }
    return Value::zero(t);
}

SubObject sub(std::uint8_t si, std::string name, DataType t, Access a, std::uint64_t v) {
    return SubObject::make(si, std::move(name), t, a, u(t, v));
}

Object record(std::uint16_t index, std::string name, ObjectCode code, std::vector<SubObject> subs,
              DataType sub0_type = DataType::Unsigned8, Access sub0_access = Access::Ro) {
    Object o;
    o.index = index;
    o.name = std::move(name);
    o.code = code;
    std::uint8_t highest = 0;
    for (const auto& s : subs) {
        highest = std::max(highest, s.subindex);
    }
    o.subs.emplace(0, sub(0, "Highest sub-index supported", sub0_type, sub0_access, highest));
    for (auto& s : subs) {
        const std::uint8_t si = s.subindex;
        o.subs.emplace(si, std::move(s));
    }
    return o;
}

} // namespace

pdo::PdoQuirks sim_pdo_quirks(const SimProfile& p) {
    return drives::pdo_quirks(*p.drive); // the same PDO quirks the master configures with
}

void SimDevice::build_objects() {
    const SimProfile& p = *config_.profile;
    const NodeId node = config_.node;
    using DT = DataType;
    od_.add_var(0x1000, "Device type", DT::Unsigned32, Access::Ro,
                u(DT::Unsigned32, p.device_type()));
    od_.add_var(0x1001, "Error register", DT::Unsigned8, Access::Ro, u(DT::Unsigned8, 0), true);
    add_error_objects(od_, p); // 1003h, 1029h, 4080h as the manual lists them
    if (p.has_sync_objects) {
        od_.add_var(0x1005, "COB-ID SYNC", DT::Unsigned32, Access::Rw,
                    u(DT::Unsigned32, cob::kSync));
        od_.add_var(0x1006, "Communication cycle period", DT::Unsigned32, Access::Rw,
                    u(DT::Unsigned32, 0));
    }
    const Access string_access = p.name() == "ds-bvs" ? Access::Const : Access::Ro;
    od_.add_var(0x1008, "Manufacturer device name", DT::VisibleString, string_access,
                Value::from_string(p.device_name));
    od_.add_var(0x1009, "Manufacturer hardware version", DT::VisibleString, string_access,
                Value::from_string(p.hw_version));
    od_.add_var(0x100A, "Manufacturer software version", DT::VisibleString, string_access,
                Value::from_string(p.sw_version));
    if (p.node_guarding) {
        od_.add_var(0x100C, "Guard time", DT::Unsigned16, Access::Rw, u(DT::Unsigned16, 0));
        od_.add_var(0x100D, "Life time factor", DT::Unsigned8, Access::Rw, u(DT::Unsigned8, 0));
    }
    store_->add_objects(); // 1010h/1011h with the drive's categories
    od_.add_var(0x1014, "COB-ID EMCY", DT::Unsigned32, Access::Rw,
                u(DT::Unsigned32, cob::emcy(node)));
    od_.insert(record(0x1016, "Consumer heartbeat time", ObjectCode::Array,
                      {sub(1, "Consumer heartbeat time", DT::Unsigned32, Access::Rw, 0)},
                      p.drive->quirks.heartbeat_consumer_sub0_type));
    od_.add_var(0x1017, "Producer heartbeat time", DT::Unsigned16, Access::Rw,
                u(DT::Unsigned16, 0));
    const std::uint32_t product = p.identity_product_code(
        static_cast<unsigned>(std::max<std::size_t>(axes_.size(), config_.axes)));
    od_.insert(record(0x1018, "Identity object", ObjectCode::Record,
                      {sub(1, "Vendor-ID", DT::Unsigned32, Access::Ro, p.identity_vendor_id()),
                       sub(2, "Product code", DT::Unsigned32, Access::Ro, product),
                       sub(3, "Revision number", DT::Unsigned32, Access::Ro, p.revision),
                       sub(4, "Serial number", DT::Unsigned32, Access::Ro, 0x00510000U + node)}));
    if (p.akd2g_objects) {
        od_.insert(record(
            0x1200, "SDO server parameter", ObjectCode::Record,
            {sub(1, "COB-ID client to server", DT::Unsigned32, Access::Ro, cob::sdo_rx(node)),
             sub(2, "COB-ID server to client", DT::Unsigned32, Access::Ro, cob::sdo_tx(node))}));
    }

    // PDO communication and mapping objects, shaped by the profile's PDO quirks.
    const pdo::PdoQuirks q = sim_pdo_quirks(p);
    std::vector<pdo::PdoConfig> preset;
    if (p.default_can_maps) {
        // AKD2G: the manual gives no CAN default maps (AMB-10); the simulator offers the
        // profile's CSP layout, RPDO1/TPDO1 for axis 1 and RPDO2/TPDO2 for axis 2.
        if (const drives::ModeLayout* l =
                p.drive->layout(drives::cia402::Mode::CyclicSyncPosition)) {
            for (unsigned a = 0; a < axes_.size(); ++a) {
                const auto entries = [&](std::span<const drives::PdoEntry> es) {
                    std::vector<pdo::MappingEntry> m;
                    for (const auto& e : es) {
                        m.push_back({p.drive->axis_index(e.index, a + 1), e.subindex, e.bits});
                    }
                    return m;
                };
                const unsigned number = l->first_pdo + a + 1;
                preset.push_back(pdo::rpdo(number, entries(l->rx), p.rpdo_default_type));
                auto t = pdo::tpdo(number, entries(l->tx), p.tpdo_default_type);
                t.comm.inhibit_time = 100; // 10 ms: event TPDOs of a moving axis stay readable
                preset.push_back(std::move(t));
            }
        }
    }
    pdo::PdoObjectDefaults defaults;
    defaults.rpdo_transmission_type = p.rpdo_default_type;
    defaults.tpdo_transmission_type = p.tpdo_default_type;
    defaults.preset = preset;
    pdo::add_pdo_objects(od_, node, q, defaults);

    // Simulation control (manufacturer range): one record per axis.
    for (unsigned a = 0; a < axes_.size(); ++a) {
        std::vector<SubObject> control{
            sub(kControlSto, "STO input active", DT::Unsigned8, Access::Rw, 0),
            sub(kControlOverCurrent, "Inject over-current", DT::Unsigned8, Access::Rw, 0),
            sub(kControlFollowingError, "Inject following error", DT::Unsigned8, Access::Rw, 0),
            sub(kControlHeartbeatLoss, "Inject heartbeat loss", DT::Unsigned8, Access::Rw, 0),
            sub(kControlNodeReset, "Reset node", DT::Unsigned8, Access::Rw, 0)};
        if (axes_[a]->touch_probe() != nullptr) {
            control.push_back(
                sub(kControlProbe1Input, "Touch probe 1 input", DT::Unsigned8, Access::Rw, 0));
            control.push_back(
                sub(kControlProbe2Input, "Touch probe 2 input", DT::Unsigned8, Access::Rw, 0));
            control.push_back(sub(kControlProbe1At, "Touch probe 1 sensor position", DT::Integer32,
                                  Access::Rw, 0));
            control.push_back(sub(kControlProbe2At, "Touch probe 2 sensor position", DT::Integer32,
                                  Access::Rw, 0));
        }
        od_.insert(record(static_cast<std::uint16_t>(kControlObject + a), "Simulation control",
                          ObjectCode::Record, std::move(control)));
    }
}

DeviceDescription SimDevice::describe() const {
    const SimProfile& p = *config_.profile;
    DeviceDescription d;
    d.file_info.file_name = std::string(p.name()) + "-node" + std::to_string(config_.node) + ".eds";
    d.file_info.file_version = "1";
    d.file_info.file_revision = "0";
    d.file_info.eds_version = "4.0";
    d.file_info.description =
        "codrive-sim " + p.product_name + " (" + std::to_string(axes_.size()) + " axes), simulated";
    d.file_info.created_by = "codrive-sim";
    d.device_info.vendor_name = p.vendor_name;
    d.device_info.vendor_number = p.identity_vendor_id();
    d.device_info.product_name = p.product_name;
    d.device_info.product_number = od_.get<std::uint32_t>(0x1018, 2).value_or(0);
    d.device_info.revision_number = p.revision;
    d.device_info.baud_rates = p.name() == "ds-bvs"
                                   ? std::vector<unsigned>{20, 50, 125, 250, 500, 1000}
                                   : std::vector<unsigned>{125, 250, 500, 1000};
    d.device_info.simple_boot_up_slave = true;
    d.device_info.granularity = 8;
    d.device_info.nr_of_rx_pdo = 4;
    d.device_info.nr_of_tx_pdo = 4;
    d.od = od_;
    // An EDS carries factory values: put every current value back to its default.
    store_->write_factory(d.od);
    return d;
}

} // namespace codrive::sim
