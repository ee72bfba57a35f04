// SPDX-License-Identifier: Apache-2.0
// Bus file loading: a complete file, and each mistake reported with file, line and a fix.
#include <codrive/master/bus_config.hpp>

#include <gtest/gtest.h>

#include <fstream>
#include <sstream>

using namespace codrive;
using namespace codrive::master;

namespace {

std::shared_ptr<const ObjectDictionary> drive_od() {
    auto od = std::make_shared<ObjectDictionary>();
    od->add_var(0x6040, "Controlword", DataType::Unsigned16, Access::Rww,
                Value::zero(DataType::Unsigned16), true);
    od->add_var(0x6041, "Statusword", DataType::Unsigned16, Access::Ro,
                Value::zero(DataType::Unsigned16), true);
    od->add_var(0x607A, "Target position", DataType::Integer32, Access::Rww,
                Value::zero(DataType::Integer32), true);
    od->add_var(0x6064, "Position actual value", DataType::Integer32, Access::Ro,
                Value::zero(DataType::Integer32), true);
    od->add_var(0x6060, "Modes of operation", DataType::Integer8, Access::Rw,
                Value::zero(DataType::Integer8), true);
    od->add_var(0x1000, "Device type", DataType::Unsigned32, Access::Ro,
                Value::zero(DataType::Unsigned32));
    return od;
}

DictionaryResolver resolver() {
    return [](const NodeEntry& n, std::string& error) -> std::shared_ptr<const ObjectDictionary> {
        if (n.profile == "testdrive") {
            return drive_od();
        }
        error = "unknown profile `" + n.profile + "` (known: testdrive)";
        return nullptr;
    };
}

BusConfigResult parse(const std::string& yaml) {
    return parse_bus_config(yaml, "bus.yml", resolver());
}

} // namespace

TEST(BusConfig, LoadsACompleteBus) {
    const auto r = parse(R"(bus:
  interface: vcan0
  bitrate: 1000000
  sync_period_us: 1000
  master: {node_id: 127, heartbeat_ms: 100}
nodes:
  - id: 3
    name: x-axis
    profile: testdrive
    identity: {vendor_id: 0x6A, product_code: 0x1234}
    heartbeat_ms: 100
    pdos:
      rpdo1: {transmission: sync, map: [Controlword, Target position]}
      tpdo1: {transmission: 1, inhibit_100us: 10, map: [Statusword, 0x6064:00]}
    writes:
      - {object: 0x6060:00, value: 8}
    axes:
      - {mode: csp, units: {increments_per_unit: 1048576, unit: rev}}
  - id: 4
    guarding: {guard_time_ms: 100, life_time_factor: 3}
    pdos:
      tpdo2: {map: ["0x6041:00:16", "0x0005:00"]}
)");
    ASSERT_TRUE(r.config) << r.to_string();
    const BusConfig& c = *r.config;
    EXPECT_EQ(c.iface, "vcan0");
    EXPECT_EQ(c.sync_period_us, 1000U);
    EXPECT_EQ(c.master_id, 127);
    ASSERT_EQ(c.nodes.size(), 2U);
    const NodeEntry& n = c.nodes[0];
    EXPECT_EQ(n.identity.vendor_id, 0x6AU);
    ASSERT_EQ(n.pdos.size(), 2U);
    EXPECT_EQ(n.pdos[0].name(), "RPDO1");
    EXPECT_EQ(n.pdos[0].total_bits(), 48U);
    EXPECT_EQ(n.pdos[1].map[1].index, 0x6064);
    EXPECT_EQ(n.pdos[1].inhibit_100us, 10);
    EXPECT_EQ(n.writes[0].value.as_int(), 8);
    EXPECT_EQ(n.axes[0].mode, 8);
    EXPECT_EQ(c.nodes[1].life_time_factor, 3);
    EXPECT_EQ(c.nodes[1].pdos[0].total_bits(), 24U) << "16 bits + an UNSIGNED8 dummy";

    const NodeConfig nc = to_node_config(n);
    EXPECT_EQ(nc.heartbeat_producer, std::chrono::milliseconds(100));
    ASSERT_EQ(nc.writes.size(), 2U) << "the write plus 6060h for the axis mode";
    EXPECT_EQ(nc.writes[1].index, 0x6060);
}

TEST(BusConfig, SdoTimeoutComesFromTheNodeOrTheBusDefault) {
    const auto r = parse(R"(bus: {interface: can0, sdo_timeout_ms: 2000}
nodes:
  - {id: 3, sdo_timeout_ms: 7500}
  - {id: 4}
)");
    ASSERT_TRUE(r.config) << r.to_string();
    EXPECT_EQ(to_node_config(r.config->nodes[0]).sdo_timeout, std::chrono::milliseconds(7500));
    EXPECT_EQ(to_node_config(r.config->nodes[1]).sdo_timeout, std::chrono::milliseconds(2000));
    const auto d = parse("bus: {interface: can0}\nnodes:\n  - {id: 3}\n");
    ASSERT_TRUE(d.config) << d.to_string();
    EXPECT_EQ(to_node_config(d.config->nodes[0]).sdo_timeout, NodeConfig{}.sdo_timeout);
    const auto bad = parse("bus: {interface: can0}\nnodes:\n  - {id: 3, sdo_timeout_ms: 0}\n");
    ASSERT_FALSE(bad.config);
    EXPECT_NE(bad.to_string().find("sdo_timeout_ms is 0 but must be between 1 and 600000"),
              std::string::npos)
        << bad.to_string();
}

TEST(BusConfig, MappingInTheWrongDirectionIsExplained) {
    const auto r = parse(R"(bus: {interface: can0}
nodes:
  - id: 3
    profile: testdrive
    pdos:
      tpdo1:
        map:
          - Statusword
          - 0x607A:00
)");
    ASSERT_FALSE(r.config);
    ASSERT_EQ(r.errors.size(), 1U) << r.to_string();
    EXPECT_EQ(r.errors[0].to_string(), "bus.yml:9: node 3 maps 0x607A:00 (INTEGER32) into TPDO1 "
                                       "but it is only RPDO-mappable");
}

TEST(BusConfig, EachMistakeGetsItsLineAndAFix) {
    const auto r = parse(R"(bus:
  interface: can0
  sync_perod_us: 1000
nodes:
  - id: 3
    profile: testdrive
    pdos:
      tpdo1: {transmission: 245, map: [Statusword, Position actual value, Position actual value]}
      xpdo2: {}
    writes:
      - {object: 0x1000:00, value: 1}
      - {object: 0x6060:00, value: 300}
  - id: 3
    profile: nosuch
  - id: 200
    axes:
      - {mode: fast}
)");
    ASSERT_FALSE(r.config);
    const std::string all = r.to_string();
    EXPECT_NE(all.find("bus.yml:3: unknown key `sync_perod_us` in `bus` (did you mean "
                       "`sync_period_us`?)"),
              std::string::npos)
        << all;
    EXPECT_NE(all.find("bus.yml:8: node 3 TPDO1 transmission type 245 is reserved"),
              std::string::npos)
        << all;
    EXPECT_NE(all.find("bus.yml:8: node 3 TPDO1 maps 80 bits but a CAN PDO carries at most 64"),
              std::string::npos)
        << all;
    EXPECT_NE(all.find("bus.yml:9: node 3: `xpdo2` is not a PDO"), std::string::npos) << all;
    EXPECT_NE(all.find("bus.yml:11: node 3 writes 0x1000:00 (Device type), which is read-only"),
              std::string::npos)
        << all;
    EXPECT_NE(all.find("bus.yml:12: node 3 write to 0x6060:00: `300` is not a valid INTEGER8"),
              std::string::npos)
        << all;
    EXPECT_NE(all.find("bus.yml:13: node 3 is configured twice"), std::string::npos) << all;
    EXPECT_NE(all.find("bus.yml:13: node 3: unknown profile `nosuch`"), std::string::npos) << all;
    EXPECT_NE(all.find("bus.yml:15: node id is 200 but must be between 1 and 127"),
              std::string::npos)
        << all;
    EXPECT_NE(all.find("unknown mode `fast`"), std::string::npos) << all;
}

TEST(BusConfig, NamesNeedADictionary) {
    const auto r = parse(R"(bus: {interface: can0}
nodes:
  - id: 5
    pdos:
      tpdo1: {map: [Statusword, 0x6064:00]}
)");
    ASSERT_FALSE(r.config);
    const std::string all = r.to_string();
    EXPECT_NE(all.find("bus.yml:5: node 5 TPDO1: `Statusword` is a name, but the node has no "
                       "profile or EDS"),
              std::string::npos)
        << all;
    EXPECT_NE(all.find("`0x6064:00` needs a bit length (e.g. 0x6064:00:16)"), std::string::npos)
        << all;
}

TEST(BusConfig, InvalidYamlAndMissingFile) {
    const auto bad = parse("bus: {interface: can0\nnodes: [");
    ASSERT_FALSE(bad.config);
    EXPECT_NE(bad.errors[0].to_string().find("not valid YAML"), std::string::npos);
    const auto missing = load_bus_config("/nonexistent/bus.yml");
    ASSERT_FALSE(missing.config);
    EXPECT_EQ(missing.errors[0].to_string(), "/nonexistent/bus.yml: cannot open the bus file");
}

TEST(BusConfig, EdsNodesResolveThroughTheEdsParser) {
    const std::string eds =
        std::string(CODRIVE_SOURCE_DIR) + "/tests/data/eds/real/canopennode-ds301-profile.eds";
    const auto r = parse_bus_config(R"(bus: {interface: can0}
nodes:
  - id: 4
    eds: )" + eds + R"(
    writes:
      - {object: 0x1017:00, value: 100}
)",
                                    "bus.yml", eds_resolver());
    EXPECT_TRUE(r.config) << r.to_string();
}

TEST(BusConfig, ModeNames) {
    EXPECT_EQ(parse_mode_name("CSP"), 8);
    EXPECT_EQ(parse_mode_name("pp"), 1);
    EXPECT_EQ(parse_mode_name("-3"), -3);
    EXPECT_FALSE(parse_mode_name("warp"));
}

TEST(BusConfig, BootResetExampleOfTheDocsParses) {
    // The `boot_reset` example in docs/bus-file.md, exactly as printed there.
    std::ifstream in(std::string(CODRIVE_SOURCE_DIR) + "/docs/bus-file.md");
    std::stringstream doc;
    doc << in.rdbuf();
    const std::string text = doc.str();
    const auto at = text.find("boot_reset: communication");
    ASSERT_NE(at, std::string::npos);
    const auto begin = text.rfind("```yaml\n", at);
    const auto end = text.find("```", at);
    ASSERT_TRUE(begin != std::string::npos && end != std::string::npos);
    const std::string yaml = text.substr(begin + 8, end - begin - 8);
    const auto r = parse_bus_config(yaml, "bus-file.md");
    ASSERT_TRUE(r.config) << r.to_string();
    EXPECT_EQ(r.config->boot_reset, BootReset::Communication);
    ASSERT_EQ(r.config->nodes.size(), 1U);
    EXPECT_EQ(to_node_config(r.config->nodes[0]).boot_reset, BootReset::PreOperational);
}

TEST(BusConfig, BootResetDefaultsToPreOperationalAndTheBusValueApplies) {
    auto r = parse("bus: {interface: vcan0, boot_reset: none}\nnodes:\n  - id: 1\n"
                   "  - {id: 2, boot_reset: Communication}\n");
    ASSERT_TRUE(r.config) << r.to_string();
    EXPECT_EQ(to_node_config(r.config->nodes[0]).boot_reset, BootReset::None);
    EXPECT_EQ(to_node_config(r.config->nodes[1]).boot_reset, BootReset::Communication);
    r = parse("bus: {interface: vcan0}\nnodes:\n  - id: 1\n");
    ASSERT_TRUE(r.config) << r.to_string();
    EXPECT_EQ(to_node_config(r.config->nodes[0]).boot_reset, BootReset::PreOperational);
}

TEST(BusConfig, BootResetUnknownWordNamesLineAndChoices) {
    const auto r = parse("bus: {interface: vcan0}\nnodes:\n  - id: 4\n    boot_reset: reboot\n");
    EXPECT_FALSE(r.config);
    EXPECT_NE(r.to_string().find("bus.yml:4: node 4 boot_reset is \"reboot\" but must be "
                                 "pre-operational, communication or none"),
              std::string::npos)
        << r.to_string();
}
