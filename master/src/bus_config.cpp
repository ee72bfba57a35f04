// SPDX-License-Identifier: Apache-2.0
// Bus file loader: YAML → BusConfig with every mistake reported as "file:line: sentence".
#include <codrive/master/bus_config.hpp>

#include <codrive/core/eds.hpp>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <filesystem>
#include <fmt/format.h>
#include <fstream>
#include <set>
#include <sstream>
#include <yaml-cpp/yaml.h>

namespace codrive::master {
namespace {

std::string lower(std::string s) {
    std::transform(s.begin(), s.end(), s.begin(),
                   [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
    return s;
}

/// The largest edit distance at which an unknown key gets a "did you mean" suggestion.
constexpr std::size_t kMaxSuggestDistance = 3;

std::size_t edit_distance(const std::string& a, const std::string& b) {
    std::vector<std::size_t> prev(b.size() + 1);
    std::vector<std::size_t> cur(b.size() + 1);
    for (std::size_t j = 0; j <= b.size(); ++j) {
        prev[j] = j;
    }
    for (std::size_t i = 1; i <= a.size(); ++i) {
        cur[0] = i;
        for (std::size_t j = 1; j <= b.size(); ++j) {
            cur[j] = std::min(
                {prev[j] + 1, cur[j - 1] + 1, prev[j - 1] + (a[i - 1] == b[j - 1] ? 0U : 1U)});
        }
        std::swap(prev, cur);
    }
    return prev[b.size()];
}

bool parse_double(const std::string& t, double& out) {
    try {
        std::size_t used = 0;
        out = std::stod(t, &used);
        return used == t.size() && std::isfinite(out);
    } catch (const std::exception&) {
        return false;
    }
}

class Loader {
public:
    Loader(std::string file, const DictionaryResolver& resolver)
        : file_(std::move(file)), resolver_(resolver) {}

    BusConfigResult run(const std::string& text) {
        BusConfigResult result;
        YAML::Node root;
        try {
            root = YAML::Load(text);
        } catch (const YAML::ParserException& e) {
            error(e.mark.line + 1, fmt::format("not valid YAML: {}", e.msg));
            result.errors = std::move(errors_);
            return result;
        }
        if (!root.IsMap()) {
            error(1, "the file must be a map with the keys `bus` and `nodes`");
            result.errors = std::move(errors_);
            return result;
        }
        BusConfig cfg;
        cfg.file = file_;
        check_keys(root, {"bus", "nodes"}, "the top level");
        if (root["bus"]) {
            parse_bus(root["bus"], cfg);
        } else {
            error(1, "missing `bus:` section (add `bus: {interface: can0}`)");
        }
        if (root["nodes"]) {
            const YAML::Node nodes = root["nodes"];
            if (!nodes.IsSequence()) {
                error(line(nodes), "`nodes` must be a list (each item starts with `- id: N`)");
            } else {
                std::set<unsigned> seen;
                for (const auto& n : nodes) {
                    NodeEntry e = parse_node(n);
                    if (e.id != 0 && !seen.insert(e.id).second) {
                        error(e.line, fmt::format("node {} is configured twice (node ids must be "
                                                  "unique on a bus)",
                                                  e.id));
                    }
                    if (e.id != 0 && e.id == cfg.master_id) {
                        error(e.line, fmt::format("node {} has the master's own node id (change "
                                                  "bus.master.node_id or the node's id)",
                                                  e.id));
                    }
                    if (e.sdo_timeout.count() == 0) {
                        e.sdo_timeout = cfg.sdo_timeout;
                    }
                    if (!e.boot_reset) {
                        e.boot_reset = cfg.boot_reset;
                    }
                    cfg.nodes.push_back(std::move(e));
                }
            }
        }
        if (errors_.empty()) {
            result.config = std::move(cfg);
        }
        result.errors = std::move(errors_);
        return result;
    }

private:
    static int line(const YAML::Node& n) { return n.Mark().line + 1; }

    void error(int at, std::string message) {
        errors_.push_back(ConfigFinding{file_, at, std::move(message)});
    }

    static const char* kind_of(const YAML::Node& n) {
        if (n.IsMap()) {
            return "a map";
        }
        if (n.IsSequence()) {
            return "a list";
        }
        if (n.IsNull()) {
            return "empty";
        }
        return "a single value";
    }

    // A value that must be one scalar (a name, a path, an object): a list or a map there is a
    // finding at the value's line naming the key, and the caller carries on with the rest.
    std::optional<std::string> text(const YAML::Node& n, const std::string& what) {
        if (!n.IsScalar()) {
            error(line(n),
                  fmt::format("{} must be a single value, but it is {}", what, kind_of(n)));
            return std::nullopt;
        }
        return n.Scalar();
    }

    std::optional<bool> boolean(const YAML::Node& n, const std::string& what) {
        if (n.IsScalar()) {
            const std::string v = lower(n.Scalar());
            if (v == "true" || v == "yes" || v == "on") {
                return true;
            }
            if (v == "false" || v == "no" || v == "off") {
                return false;
            }
        }
        error(line(n), fmt::format("{} must be true or false, not {}", what,
                                   n.IsScalar() ? "`" + n.Scalar() + "`" : kind_of(n)));
        return std::nullopt;
    }

    // A list where yaml-cpp would otherwise iterate a map as pairs and throw "invalid node".
    bool is_list(const YAML::Node& n, const std::string& what, const char* example) {
        if (n.IsSequence()) {
            return true;
        }
        error(line(n), fmt::format("{} must be a list (each item starts with `- `, e.g. {}), but "
                                   "it is {}",
                                   what, example, kind_of(n)));
        return false;
    }

    bool is_map(const YAML::Node& n, const std::string& what, const char* example) {
        if (n.IsMap()) {
            return true;
        }
        error(line(n),
              fmt::format("{} must be a map (e.g. {}), but it is {}", what, example, kind_of(n)));
        return false;
    }

    void check_keys(const YAML::Node& map, std::initializer_list<const char*> known,
                    const std::string& where) {
        if (!map.IsMap()) {
            return;
        }
        for (const auto& kv : map) {
            const auto key = kv.first.as<std::string>("");
            bool ok = false;
            std::string best;
            std::size_t best_d = kMaxSuggestDistance + 1;
            const std::string key_lower = lower(key);
            for (const char* k : known) {
                if (key == k) {
                    ok = true;
                    break;
                }
                // Lengths further apart than the largest distance suggested cannot give a
                // suggestion: no O(n*m) distance for a long unknown key (a garbage file).
                const std::size_t klen = std::char_traits<char>::length(k);
                const std::size_t apart =
                    key_lower.size() > klen ? key_lower.size() - klen : klen - key_lower.size();
                if (apart > kMaxSuggestDistance) {
                    continue;
                }
                const std::size_t d = edit_distance(key_lower, k);
                if (d < best_d) {
                    best_d = d;
                    best = k;
                }
            }
            if (!ok) {
                error(line(kv.first),
                      best_d <= kMaxSuggestDistance
                          ? fmt::format("unknown key `{}` in {} (did you mean `{}`?)", key, where,
                                        best)
                          : fmt::format("unknown key `{}` in {}", key, where));
            }
        }
    }

    template <typename T>
    std::optional<T> number(const YAML::Node& n, const std::string& what, T min, T max) {
        if (!n || !n.IsScalar()) {
            error(n ? line(n) : 0, fmt::format("{} must be a number", what));
            return std::nullopt;
        }
        const std::string s = n.Scalar();
        std::optional<std::int64_t> v = parse_int(s);
        if (!v) {
            error(line(n), fmt::format("{} must be a number, not `{}`", what, s));
            return std::nullopt;
        }
        if (*v < static_cast<std::int64_t>(min) || *v > static_cast<std::int64_t>(max)) {
            error(line(n),
                  fmt::format("{} is {} but must be between {} and {}", what, *v,
                              static_cast<std::int64_t>(min), static_cast<std::int64_t>(max)));
            return std::nullopt;
        }
        return static_cast<T>(*v);
    }

    /// `boot_reset: pre-operational | communication | none` (NodeConfig::boot_reset).
    std::optional<BootReset> boot_reset(const YAML::Node& v, const std::string& what) {
        const std::string s = v.IsScalar() ? lower(v.Scalar()) : std::string();
        for (BootReset r : {BootReset::PreOperational, BootReset::Communication, BootReset::None}) {
            if (s == to_string(r)) {
                return r;
            }
        }
        error(line(v), fmt::format("{} is \"{}\" but must be pre-operational, communication or "
                                   "none",
                                   what, v.IsScalar() ? v.Scalar() : std::string("not a word")));
        return std::nullopt;
    }

    void parse_bus(const YAML::Node& bus, BusConfig& cfg) {
        if (!bus.IsMap()) {
            error(line(bus), "`bus` must be a map (e.g. `bus: {interface: can0}`)");
            return;
        }
        check_keys(
            bus,
            {"interface", "bitrate", "sync_period_us", "sdo_timeout_ms", "boot_reset", "master"},
            "`bus`");
        if (bus["interface"] && bus["interface"].IsScalar()) {
            cfg.iface = bus["interface"].Scalar();
        } else {
            error(line(bus), "`bus.interface` is missing (e.g. `interface: can0`)");
        }
        if (bus["bitrate"]) {
            cfg.bitrate = number<std::uint32_t>(bus["bitrate"], "bus.bitrate", 10'000, 8'000'000);
        }
        if (bus["sync_period_us"]) {
            cfg.sync_period_us =
                number<std::uint32_t>(bus["sync_period_us"], "bus.sync_period_us", 0, 10'000'000)
                    .value_or(0);
        }
        if (bus["sdo_timeout_ms"]) {
            cfg.sdo_timeout = milliseconds(
                number<std::uint32_t>(bus["sdo_timeout_ms"], "bus.sdo_timeout_ms", 1, 600'000)
                    .value_or(0));
        }
        if (bus["boot_reset"]) {
            cfg.boot_reset =
                boot_reset(bus["boot_reset"], "bus.boot_reset").value_or(cfg.boot_reset);
        }
        if (const YAML::Node m = bus["master"];
            m && is_map(m, "`bus.master`", "`master: {node_id: 127, heartbeat_ms: 100}`")) {
            check_keys(m, {"node_id", "heartbeat_ms"}, "`bus.master`");
            if (m["node_id"]) {
                cfg.master_id =
                    number<NodeId>(m["node_id"], "bus.master.node_id", 1, 127).value_or(0);
            }
            if (m["heartbeat_ms"]) {
                cfg.master_heartbeat = milliseconds(
                    number<std::uint16_t>(m["heartbeat_ms"], "bus.master.heartbeat_ms", 0, 65535)
                        .value_or(0));
            }
        }
    }

    NodeEntry parse_node(const YAML::Node& n) {
        NodeEntry e;
        e.line = line(n);
        if (!n.IsMap()) {
            error(e.line, "a node must be a map starting with `id:`");
            return e;
        }
        check_keys(n,
                   {"id", "name", "profile", "eds", "identity", "heartbeat_ms", "consumer_ms",
                    "sdo_timeout_ms", "boot_reset", "guarding", "start", "pdos", "writes", "axes"},
                   "a node");
        if (n["id"]) {
            e.id = number<NodeId>(n["id"], "node id", 1, 127).value_or(0);
        } else {
            error(e.line, "node without `id` (add `id: N`, 1..127)");
        }
        const std::string who = fmt::format("node {}", e.id);
        if (n["name"]) {
            e.name = text(n["name"], who + " name").value_or("");
        }
        if (n["profile"]) {
            e.profile = lower(text(n["profile"], who + " profile").value_or(""));
        }
        if (n["eds"]) {
            if (auto eds = text(n["eds"], who + " eds")) {
                std::filesystem::path p(*eds);
                if (p.is_relative()) {
                    p = std::filesystem::path(file_).parent_path() / p;
                }
                e.eds_path = p.lexically_normal().string();
            }
        }
        if (const YAML::Node id = n["identity"];
            id && is_map(id, who + " identity", "`identity: {vendor_id: 0x6A}`")) {
            check_keys(id, {"device_type", "vendor_id", "product_code", "revision", "serial"},
                       who + " identity");
            auto get = [&](const char* k) -> std::optional<std::uint32_t> {
                if (!id[k]) {
                    return std::nullopt;
                }
                return number<std::uint32_t>(id[k], who + " identity." + k, 0, 0xFFFFFFFF);
            };
            e.identity.device_type = get("device_type");
            e.identity.vendor_id = get("vendor_id");
            e.identity.product_code = get("product_code");
            e.identity.revision = get("revision");
            e.identity.serial = get("serial");
        }
        if (n["heartbeat_ms"]) {
            e.heartbeat = milliseconds(
                number<std::uint16_t>(n["heartbeat_ms"], who + " heartbeat_ms", 0, 65535)
                    .value_or(0));
        }
        if (n["consumer_ms"]) {
            e.consumer =
                milliseconds(number<std::uint16_t>(n["consumer_ms"], who + " consumer_ms", 0, 65535)
                                 .value_or(0));
        }
        if (n["sdo_timeout_ms"]) {
            e.sdo_timeout = milliseconds(
                number<std::uint32_t>(n["sdo_timeout_ms"], who + " sdo_timeout_ms", 1, 600'000)
                    .value_or(0));
        }
        if (n["boot_reset"]) {
            e.boot_reset = boot_reset(n["boot_reset"], who + " boot_reset");
        }
        if (const YAML::Node g = n["guarding"];
            g &&
            is_map(g, who + " guarding", "`guarding: {guard_time_ms: 100, life_time_factor: 3}`")) {
            check_keys(g, {"guard_time_ms", "life_time_factor"}, who + " guarding");
            if (!g["guard_time_ms"] || !g["life_time_factor"]) {
                error(line(g), fmt::format("{} guarding needs both `guard_time_ms` and "
                                           "`life_time_factor`",
                                           who));
            } else {
                e.guard_time =
                    milliseconds(number<std::uint16_t>(g["guard_time_ms"],
                                                       who + " guarding.guard_time_ms", 1, 65535)
                                     .value_or(0));
                e.life_time_factor =
                    number<std::uint8_t>(g["life_time_factor"], who + " guarding.life_time_factor",
                                         1, 255)
                        .value_or(0);
            }
            if (e.heartbeat.count() > 0) {
                error(line(g), fmt::format("{} has both heartbeat_ms and guarding (CiA 301: use "
                                           "one error control protocol; remove one)",
                                           who));
            }
        }
        if (n["start"]) {
            e.start = boolean(n["start"], who + " start").value_or(true);
        }
        std::shared_ptr<const ObjectDictionary> od;
        if (!e.profile.empty() || !e.eds_path.empty()) {
            if (resolver_) {
                std::string why;
                od = resolver_(e, why);
                if (!od) {
                    error(e.line, fmt::format("{}: {}", who, why));
                }
            }
        }
        if (const YAML::Node pdos = n["pdos"]) {
            if (!pdos.IsMap()) {
                error(line(pdos), fmt::format("{} pdos must be a map like `tpdo1: {{map: "
                                              "[Statusword]}}`",
                                              who));
            } else {
                for (const auto& kv : pdos) {
                    parse_pdo(kv.first, kv.second, e, od.get());
                }
            }
        }
        if (const YAML::Node writes = n["writes"];
            writes &&
            is_list(writes, who + " writes", "`- {object: 0x6060:00, type: i8, value: 8}`")) {
            for (const auto& w : writes) {
                parse_write(w, e, od.get());
            }
        }
        if (const YAML::Node axes = n["axes"];
            axes && is_list(axes, who + " axes", "`- {axis: 1, mode: csp}`")) {
            unsigned next = 1;
            for (const auto& a : axes) {
                parse_axis(a, e, next++);
            }
        }
        return e;
    }

    // "Statusword", "0x6041:00", "0x6041:00:16", "6041:0".
    bool resolve_object(const std::string& text, const ObjectDictionary* od, std::uint16_t& index,
                        std::uint8_t& sub, std::uint8_t* bits, std::string& why) {
        const std::size_t colon = text.find(':');
        if (colon != std::string::npos) {
            std::string idx = text.substr(0, colon);
            std::string rest = text.substr(colon + 1);
            std::string bits_text;
            if (const std::size_t c2 = rest.find(':'); c2 != std::string::npos) {
                bits_text = rest.substr(c2 + 1);
                rest = rest.substr(0, c2);
            }
            if (idx.rfind("0x", 0) != 0 && idx.rfind("0X", 0) != 0) {
                idx = "0x" + idx;
            }
            auto i = parse_uint(idx);
            auto s = parse_uint("0x" + (rest.rfind("0x", 0) == 0 ? rest.substr(2) : rest));
            if (!i || *i > 0xFFFF || !s || *s > 0xFF) {
                why = fmt::format("`{}` is not an object (write INDEX:SUB in hex, e.g. "
                                  "0x6041:00, or the object's name)",
                                  text);
                return false;
            }
            index = static_cast<std::uint16_t>(*i);
            sub = static_cast<std::uint8_t>(*s);
            if (!bits_text.empty() && bits != nullptr) {
                auto b = parse_uint(bits_text);
                if (!b || *b == 0 || *b > 64) {
                    why = fmt::format("`{}`: bit length must be 1..64", text);
                    return false;
                }
                *bits = static_cast<std::uint8_t>(*b);
            }
            return true;
        }
        if (od == nullptr) {
            why = fmt::format("`{}` is a name, but the node has no profile or EDS to look it up "
                              "(give it as INDEX:SUB:BITS, e.g. 0x6041:00:16)",
                              text);
            return false;
        }
        const std::string want = lower(text);
        for (const auto& [i, obj] : od->objects()) {
            if (obj.code == ObjectCode::Var && lower(obj.name) == want) {
                index = i;
                sub = 0;
                return true;
            }
            for (const auto& [s, so] : obj.subs) {
                if (lower(obj.name + "." + so.name) == want || (s != 0 && lower(so.name) == want)) {
                    index = i;
                    sub = s;
                    return true;
                }
            }
        }
        why = fmt::format("no object named `{}` in the node's dictionary (check the spelling, or "
                          "give INDEX:SUB)",
                          text);
        return false;
    }

    void parse_pdo(const YAML::Node& key, const YAML::Node& v, NodeEntry& e,
                   const ObjectDictionary* od) {
        const std::string who = fmt::format("node {}", e.id);
        PdoConfig p;
        p.line = line(key);
        const std::string k = lower(key.as<std::string>(""));
        unsigned num = 0;
        if ((k.rfind("tpdo", 0) == 0 || k.rfind("rpdo", 0) == 0) && k.size() > 4) {
            auto parsed = parse_uint(k.substr(4));
            num = parsed && *parsed >= 1 && *parsed <= 512 ? static_cast<unsigned>(*parsed) : 0;
        }
        if (num == 0) {
            error(p.line, fmt::format("{}: `{}` is not a PDO (use tpdo1..tpdo512 or "
                                      "rpdo1..rpdo512)",
                                      who, k));
            return;
        }
        p.transmit = k[0] == 't';
        p.number = num;
        if (!v.IsMap()) {
            error(p.line, fmt::format("{} {} must be a map like `{{transmission: 1, map: "
                                      "[...]}}`",
                                      who, p.name()));
            return;
        }
        check_keys(v,
                   {"enabled", "cob_id", "transmission", "inhibit_100us", "event_timer_ms",
                    "sync_start", "map"},
                   who + " " + p.name());
        if (v["enabled"]) {
            p.enabled = boolean(v["enabled"], who + " " + p.name() + " enabled").value_or(true);
        }
        if (v["cob_id"]) {
            p.cob_id =
                number<std::uint32_t>(v["cob_id"], who + " " + p.name() + " cob_id", 1, 0x7FF);
        }
        if (v["transmission"]) {
            const YAML::Node t = v["transmission"];
            std::optional<std::uint8_t> tt;
            const std::string s =
                t.IsScalar() ? lower(t.Scalar()) : std::string(); // else: number() reports it
            if (s == "sync" || s == "cyclic") {
                tt = 1;
            } else if (s == "acyclic") {
                tt = 0;
            } else if (s == "event" || s == "async") {
                tt = 255;
            } else if (s == "rtr") {
                tt = 253;
            } else {
                tt = number<std::uint8_t>(t, who + " " + p.name() + " transmission", 0, 255);
            }
            if (tt && *tt > 240 && *tt < 252) {
                error(line(t), fmt::format("{} {} transmission type {} is reserved (use 0, 1..240, "
                                           "252..255)",
                                           who, p.name(), *tt));
            } else if (tt && !p.transmit && (*tt == 252 || *tt == 253)) {
                error(line(t), fmt::format("{} {} transmission type {} (RTR) applies to TPDOs "
                                           "only",
                                           who, p.name(), *tt));
            }
            p.transmission = tt.value_or(1);
        }
        if (v["inhibit_100us"]) {
            p.inhibit_100us = number<std::uint16_t>(v["inhibit_100us"], who + " inhibit", 0, 65535);
        }
        if (v["event_timer_ms"]) {
            p.event_timer_ms =
                number<std::uint16_t>(v["event_timer_ms"], who + " event timer", 0, 65535);
        }
        if (v["sync_start"]) {
            p.sync_start = number<std::uint8_t>(v["sync_start"], who + " sync_start", 0, 240);
        }
        if (const YAML::Node map = v["map"]) {
            if (!map.IsSequence()) {
                error(line(map), fmt::format("{} {} map must be a list of objects", who, p.name()));
            } else {
                for (const auto& item : map) {
                    PdoEntryConfig ent;
                    ent.line = line(item);
                    auto written = text(item, fmt::format("{} {} map entry", who, p.name()));
                    if (!written) {
                        continue;
                    }
                    ent.text = *written;
                    std::string why;
                    if (!resolve_object(ent.text, od, ent.index, ent.subindex, &ent.bits, why)) {
                        error(ent.line, fmt::format("{} {}: {}", who, p.name(), why));
                        continue;
                    }
                    check_mapping(e, p, ent, od);
                    p.map.push_back(ent);
                }
            }
        }
        if (p.total_bits() > 64) {
            error(p.line, fmt::format("{} {} maps {} bits but a CAN PDO carries at most 64 "
                                      "(move objects to another PDO)",
                                      who, p.name(), p.total_bits()));
        }
        e.pdos.push_back(std::move(p));
    }

    void check_mapping(const NodeEntry& e, const PdoConfig& p, PdoEntryConfig& ent,
                       const ObjectDictionary* od) {
        const bool dummy = ent.index >= 0x0001 && ent.index <= 0x0007 && ent.subindex == 0;
        if (dummy) {
            const auto t = data_type_from_index(ent.index);
            if (ent.bits == 0 && t) {
                ent.bits = static_cast<std::uint8_t>(data_type_size(*t) * 8);
            }
            return;
        }
        if (od == nullptr) {
            if (ent.bits == 0) {
                error(ent.line, fmt::format("node {} {}: `{}` needs a bit length (e.g. {}:16) "
                                            "because the node has no profile or EDS",
                                            e.id, p.name(), ent.text, ent.text));
            }
            return;
        }
        const SubObject* s = od->find(ent.index, ent.subindex);
        if (s == nullptr) {
            error(ent.line, fmt::format("node {} {} maps 0x{:04X}:{:02X}, which does not exist in "
                                        "the node's dictionary",
                                        e.id, p.name(), ent.index, ent.subindex));
            return;
        }
        if (ent.bits == 0) {
            ent.bits = static_cast<std::uint8_t>(s->bit_length());
        }
        const PdoDir dir = p.transmit ? PdoDir::Tpdo : PdoDir::Rpdo;
        if (!s->mappable(dir)) {
            const PdoDir other = p.transmit ? PdoDir::Rpdo : PdoDir::Tpdo;
            error(ent.line,
                  s->mappable(other)
                      ? fmt::format("node {} maps 0x{:04X}:{:02X} ({}) into {} but it is only {}-"
                                    "mappable",
                                    e.id, ent.index, ent.subindex, codrive::to_string(s->type),
                                    p.name(), p.transmit ? "RPDO" : "TPDO")
                      : fmt::format("node {} maps 0x{:04X}:{:02X} ({}) into {} but it is not "
                                    "PDO-mappable",
                                    e.id, ent.index, ent.subindex, codrive::to_string(s->type),
                                    p.name()));
        }
    }

    void parse_write(const YAML::Node& w, NodeEntry& e, const ObjectDictionary* od) {
        const std::string who = fmt::format("node {}", e.id);
        WriteConfig wc;
        wc.line = line(w);
        if (!w.IsMap()) {
            error(wc.line, fmt::format("{} write must be a map `{{object: 0x6060:00, type: i8, "
                                       "value: 8}}`",
                                       who));
            return;
        }
        check_keys(w, {"object", "type", "value"}, who + " write");
        std::string why;
        if (!w["object"]) {
            error(wc.line, fmt::format("{} write: missing `object:`", who));
            return;
        }
        const auto object = text(w["object"], who + " write object");
        if (!object) {
            return;
        }
        if (!resolve_object(*object, od, wc.index, wc.subindex, nullptr, why)) {
            error(line(w["object"]), fmt::format("{} write: {}", who, why));
            return;
        }
        const SubObject* s = od != nullptr ? od->find(wc.index, wc.subindex) : nullptr;
        std::optional<DataType> type;
        if (w["type"]) {
            const auto name = text(w["type"], who + " write type");
            if (!name) {
                return;
            }
            type = data_type_from_name(*name);
            if (!type) {
                error(line(w["type"]), fmt::format("{} write: unknown type `{}` (use u8 u16 u32 "
                                                   "u64 i8 i16 i32 i64 f32 f64 str)",
                                                   who, *name));
                return;
            }
        } else if (s != nullptr) {
            type = s->type;
        } else {
            error(wc.line, fmt::format("{} write to 0x{:04X}:{:02X} needs `type:` (the node has no "
                                       "dictionary to take it from)",
                                       who, wc.index, wc.subindex));
            return;
        }
        if (od != nullptr && s == nullptr) {
            error(wc.line, fmt::format("{} writes 0x{:04X}:{:02X}, which does not exist in the "
                                       "node's dictionary",
                                       who, wc.index, wc.subindex));
            return;
        }
        if (s != nullptr && !writable(s->access)) {
            error(wc.line, fmt::format("{} writes 0x{:04X}:{:02X} ({}), which is read-only", who,
                                       wc.index, wc.subindex, od->name_of(wc.index, wc.subindex)));
            return;
        }
        if (!w["value"]) {
            error(wc.line, fmt::format("{} write to 0x{:04X}:{:02X} has no `value:`", who, wc.index,
                                       wc.subindex));
            return;
        }
        const auto value_text = text(w["value"], fmt::format("{} write to 0x{:04X}:{:02X} value",
                                                             who, wc.index, wc.subindex));
        if (!value_text) {
            return;
        }
        auto v = Value::parse(*type, *value_text);
        if (!v) {
            error(line(w["value"]),
                  fmt::format("{} write to 0x{:04X}:{:02X}: `{}` is not a valid {} ({})", who,
                              wc.index, wc.subindex, *value_text, codrive::to_string(*type),
                              v.error().message()));
            return;
        }
        wc.value = std::move(*v);
        e.writes.push_back(std::move(wc));
    }

    void parse_axis(const YAML::Node& a, NodeEntry& e, unsigned default_axis) {
        const std::string who = fmt::format("node {}", e.id);
        AxisConfig ax;
        ax.axis = default_axis;
        ax.line = line(a);
        if (!a.IsMap()) {
            error(ax.line, fmt::format("{} axis must be a map `{{axis: 1, mode: csp}}`", who));
            return;
        }
        check_keys(a, {"axis", "mode", "units"}, who + " axis");
        if (a["axis"]) {
            ax.axis = number<unsigned>(a["axis"], who + " axis", 1, 8).value_or(1);
        }
        if (a["mode"]) {
            if (const auto mode = text(a["mode"], fmt::format("{} axis {} mode", who, ax.axis))) {
                ax.mode = parse_mode_name(*mode);
                if (!ax.mode) {
                    error(line(a["mode"]), fmt::format("{} axis {}: unknown mode `{}` (use pp, pv, "
                                                       "pt, hm, ip, csp, csv, cst or a number)",
                                                       who, ax.axis, *mode));
                }
            }
        }
        if (const YAML::Node u = a["units"];
            u && is_map(u, fmt::format("{} axis {} units", who, ax.axis),
                        "`units: {increments_per_unit: 1000, unit: mm}`")) {
            check_keys(u, {"increments_per_unit", "unit"}, who + " axis units");
            if (const YAML::Node ipu = u["increments_per_unit"]) {
                const std::string what =
                    fmt::format("{} axis {}: increments_per_unit", who, ax.axis);
                double value = 0;
                if (const auto t = text(ipu, what); t && !parse_double(*t, value)) {
                    error(line(ipu), fmt::format("{} must be a number, not `{}`", what, *t));
                } else if (t && value <= 0) {
                    error(line(ipu), fmt::format("{} must be > 0", what));
                } else if (t) {
                    ax.increments_per_unit = value;
                }
            }
            if (u["unit"]) {
                ax.unit =
                    text(u["unit"], fmt::format("{} axis {} unit", who, ax.axis)).value_or("inc");
                static const std::set<std::string> kUnits{"m",   "mm",  "um", "rad",
                                                          "deg", "rev", "inc"};
                if (kUnits.count(ax.unit) == 0) {
                    error(line(u["unit"]), fmt::format("{} axis {}: unknown unit `{}` (use m, mm, "
                                                       "um, rad, deg, rev or inc)",
                                                       who, ax.axis, ax.unit));
                }
            }
        }
        e.axes.push_back(ax);
    }

    std::string file_;
    const DictionaryResolver& resolver_;
    std::vector<ConfigFinding> errors_;
};

} // namespace

std::string ConfigFinding::to_string() const {
    return line > 0 ? fmt::format("{}:{}: {}", file, line, message)
                    : fmt::format("{}: {}", file, message);
}

std::string PdoConfig::name() const {
    return fmt::format("{}PDO{}", transmit ? 'T' : 'R', number);
}

unsigned PdoConfig::total_bits() const {
    unsigned bits = 0;
    for (const auto& m : map) {
        bits += m.bits;
    }
    return bits;
}

std::string BusConfigResult::to_string() const {
    std::string out;
    for (const auto& e : errors) {
        out += e.to_string() + "\n";
    }
    return out;
}

BusConfigResult parse_bus_config(const std::string& yaml, const std::string& file,
                                 const DictionaryResolver& resolver) {
    Loader loader(file, resolver);
    try {
        return loader.run(yaml);
    } catch (const YAML::Exception& e) {
        // yaml-cpp throws on some malformed documents (e.g. a truncated file leaves an invalid
        // node); a bus file mistake must be a finding, never a crash.
        BusConfigResult r;
        r.errors.push_back(ConfigFinding{file, e.mark.is_null() ? 0 : e.mark.line + 1,
                                         fmt::format("not a valid bus file: {}", e.msg)});
        return r;
    }
}

BusConfigResult load_bus_config(const std::string& path, const DictionaryResolver& resolver) {
    std::ifstream in(path);
    if (!in) {
        BusConfigResult r;
        r.errors.push_back(ConfigFinding{path, 0, "cannot open the bus file"});
        return r;
    }
    std::stringstream ss;
    ss << in.rdbuf();
    return parse_bus_config(ss.str(), path, resolver);
}

DictionaryResolver eds_resolver(DictionaryResolver profiles) {
    return [profiles = std::move(profiles)](
               const NodeEntry& n, std::string& error) -> std::shared_ptr<const ObjectDictionary> {
        if (!n.eds_path.empty()) {
            auto d = load_eds(n.eds_path, n.id);
            if (!d) {
                error = fmt::format("cannot read EDS {}: {}", n.eds_path, d.error().message());
                return nullptr;
            }
            return std::make_shared<const ObjectDictionary>(std::move(d->od));
        }
        if (profiles) {
            return profiles(n, error);
        }
        error = fmt::format("profile `{}` is not known here", n.profile);
        return nullptr;
    };
}

NodeConfig to_node_config(const NodeEntry& n) {
    NodeConfig c;
    c.id = n.id;
    c.name = n.name;
    c.identity = n.identity;
    c.heartbeat_producer = n.heartbeat;
    c.heartbeat_consumer = n.consumer;
    if (n.sdo_timeout.count() > 0) {
        c.sdo_timeout = n.sdo_timeout;
    }
    c.guard_time = n.guard_time;
    c.life_time_factor = n.life_time_factor;
    c.start = n.start;
    c.boot_reset = n.boot_reset.value_or(BootReset::PreOperational);
    for (const auto& w : n.writes) {
        ObjectWrite ow;
        ow.index = w.index;
        ow.subindex = w.subindex;
        ow.data.assign(w.value.bytes().begin(), w.value.bytes().end());
        ow.what = w.value.to_string();
        c.writes.push_back(std::move(ow));
    }
    for (const auto& a : n.axes) {
        if (a.mode) {
            // CiA 402 axis n of a multi-axis device: the caller's profile may offset indexes;
            // the generic layout puts axis n at 0x6060 + 0x800 * (n - 1).
            c.writes.push_back(ObjectWrite::of<std::int8_t>(
                static_cast<std::uint16_t>(0x6060 + 0x800 * (a.axis - 1)), 0, *a.mode,
                fmt::format("axis {} modes of operation = {}", a.axis, *a.mode)));
        }
    }
    return c;
}

std::optional<std::int8_t> parse_mode_name(const std::string& text) {
    static const std::pair<const char*, std::int8_t> kModes[] = {
        {"pp", 1}, {"vl", 2},  {"pv", 3},  {"pt", 4},   {"tq", 4},    {"hm", 6},
        {"ip", 7}, {"csp", 8}, {"csv", 9}, {"cst", 10}, {"homing", 6}};
    const std::string t = lower(text);
    for (const auto& [name, v] : kModes) {
        if (t == name) {
            return v;
        }
    }
    if (auto v = parse_int(t); v && *v >= -128 && *v <= 127) {
        return static_cast<std::int8_t>(*v);
    }
    return std::nullopt;
}

} // namespace codrive::master
