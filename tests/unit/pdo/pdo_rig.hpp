// SPDX-License-Identifier: Apache-2.0
// Test rig: a master (SDO client + PDO engine) and a PDO device on one virtual CAN network.
#pragma once

#include <codrive/core/virtual_bus.hpp>
#include <codrive/pdo/configure.hpp>
#include <codrive/pdo/device.hpp>
#include <codrive/pdo/master.hpp>
#include <codrive/pdo/od_objects.hpp>
#include <codrive/pdo/readback.hpp>
#include <codrive/sdo/client.hpp>
#include <codrive/sdo/server.hpp>

#include <memory>
#include <optional>
#include <vector>

namespace codrive::pdo::test {

template <typename T>
inline Value val(DataType t, T v) {
    std::vector<std::uint8_t> b(sizeof(T));
    put_le<T>(b.data(), v);
    return Value(t, std::move(b));
}

/// A CiA 402-like dictionary: RPDO-only (rww), TPDO-only (ro/rwr), both (rw) and unmappable
/// objects, plus the PDO parameter objects shaped by the quirks.
inline void fill_drive_od(ObjectDictionary& od, NodeId node, const PdoQuirks& q,
                          const PdoObjectDefaults& d = {}) {
    od.add_var(0x6040, "Controlword", DataType::Unsigned16, Access::Rww,
               val<std::uint16_t>(DataType::Unsigned16, 0), true);
    od.add_var(0x607A, "Target position", DataType::Integer32, Access::Rww,
               val<std::int32_t>(DataType::Integer32, 0), true);
    od.add_var(0x60FF, "Target velocity", DataType::Integer32, Access::Rww,
               val<std::int32_t>(DataType::Integer32, 0), true);
    od.add_var(0x6060, "Modes of operation", DataType::Integer8, Access::Rw,
               val<std::int8_t>(DataType::Integer8, 0), true);
    od.add_var(0x6041, "Statusword", DataType::Unsigned16, Access::Ro,
               val<std::uint16_t>(DataType::Unsigned16, 0), true);
    od.add_var(0x6064, "Position actual value", DataType::Integer32, Access::Ro,
               val<std::int32_t>(DataType::Integer32, 0), true);
    od.add_var(0x606C, "Velocity actual value", DataType::Integer32, Access::Ro,
               val<std::int32_t>(DataType::Integer32, 0), true);
    od.add_var(0x6061, "Modes of operation display", DataType::Integer8, Access::Ro,
               val<std::int8_t>(DataType::Integer8, 0), true);
    od.add_var(0x6062, "Position demand value", DataType::Integer32, Access::Ro,
               val<std::int32_t>(DataType::Integer32, 0), false);
    od.add_var(0x2000, "Loopback A", DataType::Unsigned32, Access::Rw,
               val<std::uint32_t>(DataType::Unsigned32, 0), true);
    od.add_var(0x2001, "Loopback B", DataType::Unsigned32, Access::Rw,
               val<std::uint32_t>(DataType::Unsigned32, 0), true);
    od.add_var(0x2002, "Flags", DataType::Boolean, Access::Rw,
               val<std::uint8_t>(DataType::Boolean, 0), true);
    add_pdo_objects(od, node, q, d);
}

/// Master endpoint with an SDO client and a PDO engine; device endpoint with an SDO server and
/// a DevicePdo on the dictionary above.
struct Rig {
    explicit Rig(NodeId node_id = 3, PdoQuirks q = quirks::standard(), PdoObjectDefaults d = {})
        : node(node_id), quirks(q) {
        fill_drive_od(od, node, quirks, d);
        sdo::ServerConfig sc;
        sc.node = node;
        server = std::make_unique<sdo::SdoServer>(od, node_bus, sc);
        DevicePdoOptions dopt;
        dopt.node = node;
        dopt.quirks = quirks;
        device = std::make_unique<DevicePdo>(od, node_bus, dopt);
        node_bus.set_frame_handler([this](const Frame& f, TimePoint t) {
            server->on_frame(f, t);
            device->on_frame(f, t);
        });
        sdo::ClientConfig cc;
        cc.node = node;
        client = std::make_unique<sdo::SdoClient>(master_bus, clock, cc);
        master = std::make_unique<PdoMaster>(master_bus);
        master_bus.set_frame_handler([this](const Frame& f, TimePoint t) {
            client->on_frame(f, t);
            master->on_frame(f, t);
            rx.push_back(f);
        });
    }

    void run(Duration d) {
        net.run_until(clock, clock.now() + d,
                      {server.get(), client.get(), device.get(), master.get()});
    }

    /// Configures over SDO and returns the result.
    PdoResult<ConfigureReport> configure(std::vector<PdoConfig> pdos) {
        DeviceModel dm;
        dm.od = &od;
        dm.quirks = quirks;
        PdoConfigurator cfg(*client, dm);
        std::optional<PdoResult<ConfigureReport>> out;
        cfg.configure(std::move(pdos), [&](PdoResult<ConfigureReport> r) { out = std::move(r); });
        for (int i = 0; i < 1000 && !out; ++i) {
            run(milliseconds(1));
        }
        return out ? std::move(*out) : pdo_fail(PdoErrc::SdoFailed, "configuration hung");
    }

    PdoResult<NodePdoConfiguration> read_back() {
        PdoReader reader(*client);
        std::optional<PdoResult<NodePdoConfiguration>> out;
        reader.read(quirks.rpdo_count, quirks.tpdo_count,
                    [&](PdoResult<NodePdoConfiguration> r) { out = std::move(r); });
        for (int i = 0; i < 1000 && !out; ++i) {
            run(milliseconds(1));
        }
        return out ? std::move(*out) : pdo_fail(PdoErrc::SdoFailed, "read-back hung");
    }

    NodeId node;
    PdoQuirks quirks;
    FakeClock clock;
    VirtualNetwork net{clock, microseconds(50)};
    VirtualBus& master_bus = net.endpoint("master");
    VirtualBus& node_bus = net.endpoint("node");
    ObjectDictionary od;
    std::unique_ptr<sdo::SdoServer> server;
    std::unique_ptr<DevicePdo> device;
    std::unique_ptr<sdo::SdoClient> client;
    std::unique_ptr<PdoMaster> master;
    std::vector<Frame> rx; ///< frames the master endpoint received
};

inline MappingEntry entry(std::uint16_t index, std::uint8_t sub, std::uint8_t bits) {
    return MappingEntry{index, sub, bits};
}

} // namespace codrive::pdo::test
