// SPDX-License-Identifier: Apache-2.0
// The bus configuration file (YAML): interface, SYNC, master heartbeat and, per node, identity,
// error control, PDO mappings, object writes and axes. Mistakes come back as
// "bus.yml:14: <what is wrong> (<how to fix it>)".
#pragma once

#include <codrive/master/node_config.hpp>

#include <codrive/core/data_type.hpp>
#include <codrive/core/object_dictionary.hpp>
#include <codrive/core/value.hpp>

#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace codrive::master {

/// One problem in a bus file, with its location.
struct ConfigFinding {
    std::string file;
    int line = 0; ///< 1-based; 0 when the file itself is the problem
    std::string message;
    [[nodiscard]] std::string to_string() const; ///< "bus.yml:14: message"
};

/// A mapped object in a PDO: given by name ("Statusword") or index ("0x6041:00").
struct PdoEntryConfig {
    std::string text; ///< as written
    std::uint16_t index = 0;
    std::uint8_t subindex = 0;
    std::uint8_t bits = 0; ///< from the dictionary, or ":bits" suffix for dummies/unknown nodes
    int line = 0;
};

struct PdoConfig {
    bool transmit = false; ///< TPDO (node → master) or RPDO (master → node)
    unsigned number = 1;   ///< 1..512
    bool enabled = true;
    std::optional<std::uint32_t> cob_id; ///< default: predefined connection set
    std::uint8_t transmission = 1;       ///< 0, 1..240, 252..255
    std::optional<std::uint16_t> inhibit_100us;
    std::optional<std::uint16_t> event_timer_ms;
    std::optional<std::uint8_t> sync_start;
    std::vector<PdoEntryConfig> map;
    int line = 0;
    [[nodiscard]] std::string name() const; ///< "TPDO1", "RPDO2"
    [[nodiscard]] unsigned total_bits() const;
};

struct WriteConfig {
    std::uint16_t index = 0;
    std::uint8_t subindex = 0;
    Value value;
    int line = 0;
};

struct AxisConfig {
    unsigned axis = 1;
    std::optional<std::int8_t> mode; ///< 6060h value
    /// Drive increments per user unit (position), from "units: {increments_per_unit: N}".
    std::optional<double> increments_per_unit;
    std::string unit = "inc"; ///< "m", "mm", "rad", "deg", "rev" or "inc"
    int line = 0;
};

struct NodeEntry {
    NodeId id = 0;
    std::string name;
    std::string profile;  ///< "akd2g", "ds-bvs", "fio", "generic" (resolved by the caller)
    std::string eds_path; ///< absolute, or relative to the bus file
    ExpectedIdentity identity;
    milliseconds heartbeat{0};
    milliseconds consumer{0};
    /// Boot-up SDO timeout; 0: the bus default (`bus.sdo_timeout_ms`), else NodeConfig's.
    milliseconds sdo_timeout{0};
    milliseconds guard_time{0};
    std::uint8_t life_time_factor = 0;
    bool start = true;
    /// `boot_reset`; unset: the bus's (already applied when parsing succeeds).
    std::optional<BootReset> boot_reset;
    std::vector<PdoConfig> pdos;
    std::vector<WriteConfig> writes;
    std::vector<AxisConfig> axes;
    int line = 0;
};

struct BusConfig {
    std::string file;
    std::string iface;
    std::optional<std::uint32_t> bitrate;
    std::uint32_t sync_period_us = 0; ///< 0: no SYNC producer
    NodeId master_id = 0;
    milliseconds master_heartbeat{0};
    /// Default boot-up SDO timeout of every node (0: NodeConfig's default); already applied to
    /// the nodes without their own `sdo_timeout_ms` when parsing succeeds.
    milliseconds sdo_timeout{0};
    /// `bus.boot_reset`: the default NMT state step of every node's boot-up.
    BootReset boot_reset = BootReset::PreOperational;
    std::vector<NodeEntry> nodes;
};

/// Supplies the object dictionary of a node (from its profile or EDS) so names resolve and
/// mappings are checked; return nullptr and set `error` if it cannot. Without a resolver, or
/// for a node with neither profile nor EDS, entries must be given by index with ":bits".
using DictionaryResolver =
    std::function<std::shared_ptr<const ObjectDictionary>(const NodeEntry&, std::string& error)>;

struct BusConfigResult {
    std::optional<BusConfig> config; ///< set when there are no errors
    std::vector<ConfigFinding> errors;
    [[nodiscard]] std::string to_string() const; ///< one finding per line
};

/// Parses and validates YAML text. `file` names it in findings and anchors relative EDS paths.
[[nodiscard]] BusConfigResult parse_bus_config(const std::string& yaml, const std::string& file,
                                               const DictionaryResolver& resolver = {});
/// Reads and parses a file.
[[nodiscard]] BusConfigResult load_bus_config(const std::string& path,
                                              const DictionaryResolver& resolver = {});

/// A resolver that loads EDS/DCF files (`eds:` keys) with the core EDS parser and defers
/// `profile:` nodes to `profiles` (may be empty).
[[nodiscard]] DictionaryResolver eds_resolver(DictionaryResolver profiles = {});

/// The master's boot configuration for a node: identity, writes (incl. 6060h per axis), error
/// control. PDO configuration is added by the caller as boot steps.
[[nodiscard]] NodeConfig to_node_config(const NodeEntry& node);

/// Mode names accepted in bus files: pp, vl, pv, pt, hm, ip, csp, csv, cst (or a number).
[[nodiscard]] std::optional<std::int8_t> parse_mode_name(const std::string& text);

} // namespace codrive::master
