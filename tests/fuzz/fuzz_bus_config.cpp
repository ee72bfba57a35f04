// SPDX-License-Identifier: Apache-2.0
// libFuzzer target: parse_bus_config() with arbitrary YAML text must never crash or throw; it
// returns either a configuration or located findings, never both and never neither.
#include "fuzz_input.hpp"

#include <codrive/master/bus_config.hpp>

#include <cstddef>
#include <cstdint>
#include <memory>
#include <string>

using namespace codrive;

namespace {

/// A small dictionary for `profile:` nodes so PDO entries given by name resolve and mappings
/// are checked against real sub-objects.
std::shared_ptr<const ObjectDictionary> make_dictionary() {
    auto od = std::make_shared<ObjectDictionary>();
    od->add_var(0x6040, "Controlword", DataType::Unsigned16, Access::Rww,
                Value::zero(DataType::Unsigned16), true);
    od->add_var(0x6041, "Statusword", DataType::Unsigned16, Access::Ro,
                Value::zero(DataType::Unsigned16), true);
    od->add_var(0x6060, "Modes of operation", DataType::Integer8, Access::Rw,
                Value::zero(DataType::Integer8), true);
    od->add_var(0x6064, "Position actual value", DataType::Integer32, Access::Ro,
                Value::zero(DataType::Integer32), true);
    od->add_var(0x607A, "Target position", DataType::Integer32, Access::Rww,
                Value::zero(DataType::Integer32), true);
    od->add_var(0x1008, "Manufacturer device name", DataType::VisibleString, Access::Const,
                Value::from_string("fuzz"));
    return od;
}

void check(const master::BusConfigResult& r) {
    // Exactly one of: a configuration, or at least one finding.
    CODRIVE_FUZZ_CHECK(r.config.has_value() == r.errors.empty());
    for (const auto& f : r.errors) {
        CODRIVE_FUZZ_CHECK(!f.message.empty());
        CODRIVE_FUZZ_CHECK(f.line >= 0);
        CODRIVE_FUZZ_CHECK(f.to_string().find("fuzz.yml") == 0);
    }
    (void)r.to_string();
    if (r.config) {
        for (const auto& node : r.config->nodes) {
            CODRIVE_FUZZ_CHECK(valid_node_id(node.id));
            for (const auto& pdo : node.pdos) {
                (void)pdo.name();
                (void)pdo.total_bits();
            }
            const master::NodeConfig nc = master::to_node_config(node);
            CODRIVE_FUZZ_CHECK(nc.id == node.id);
        }
    }
}

} // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    const std::string yaml(reinterpret_cast<const char*>(data), size);
    // Without a resolver, PDO entries must carry explicit sizes.
    check(master::parse_bus_config(yaml, "fuzz.yml"));
    // With one: `profile:` nodes get a dictionary, `eds:` nodes are refused without file access.
    static const auto od = make_dictionary();
    const master::DictionaryResolver resolver =
        [](const master::NodeEntry& node,
           std::string& error) -> std::shared_ptr<const ObjectDictionary> {
        if (!node.profile.empty()) {
            return od;
        }
        error = "no dictionary in the fuzz harness";
        return nullptr;
    };
    check(master::parse_bus_config(yaml, "fuzz.yml", resolver));
    return 0;
}
