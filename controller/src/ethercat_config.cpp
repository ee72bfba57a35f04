// SPDX-License-Identifier: Apache-2.0
// Parses the `ethercat:` section of a bus file and leaves the CAN part to the master's loader.
#include <codrive/controller/ethercat_segment.hpp>

#include <codrive/drives/profile.hpp>
#include <codrive/master/bus_config.hpp>

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <filesystem>
#include <set>
#include <sstream>
#include <yaml-cpp/yaml.h>

namespace codrive::controller {
namespace {

int line_of(const YAML::Node& n) {
    return n.Mark().line + 1;
}

bool starts_top_level_key(const std::string& l) {
    return !l.empty() && l[0] != ' ' && l[0] != '\t' && l[0] != '#' && l[0] != '-';
}

class SectionParser {
public:
    SectionParser(std::string file, std::vector<std::string>& errors)
        : file_(std::move(file)), errors_(errors) {}

    std::optional<EcatSegmentConfig> parse(const YAML::Node& s, int key_line) {
        EcatSegmentConfig c;
        c.file = file_;
        if (!s.IsMap()) {
            error(key_line, "`ethercat` must be a map with `interface`, `cycle_us` and `slaves`");
            return std::nullopt;
        }
        check_keys(s,
                   {"interface", "cycle_us", "lost_frames_event", "dc", "sync", "sync0_shift_us",
                    "esi", "slaves"},
                   "`ethercat`");
        if (s["interface"] && s["interface"].IsScalar()) {
            c.iface = s["interface"].as<std::string>();
        } else {
            error(key_line, "`ethercat` needs `interface: IFACE` (the Ethernet port of the "
                            "segment)");
        }
        if (s["cycle_us"]) {
            const auto v = number(s["cycle_us"]);
            if (!v || *v < 100 || *v > 1000000) {
                error(line_of(s["cycle_us"]),
                      "`ethercat.cycle_us` must be a number of microseconds, 100..1000000");
            } else {
                c.cycle_us = static_cast<std::uint32_t>(*v);
            }
        }
        if (s["lost_frames_event"]) {
            const auto v = number(s["lost_frames_event"]);
            if (!v || *v < 1 || *v > 1000) {
                error(line_of(s["lost_frames_event"]),
                      "`ethercat.lost_frames_event` must be a number of frames, 1..1000");
            } else {
                c.lost_frames_event = static_cast<unsigned>(*v);
            }
        }
        // A bad `dc`/`sync` is one finding, not a second one on the shift.
        const auto mode = sync_mode(s, "`ethercat.");
        const bool dc_readable = mode.has_value();
        c.sync = mode.value_or(std::nullopt).value_or(ethercat::SyncMode::FreeRun);
        std::optional<int> shift_line;
        if (s["sync0_shift_us"]) {
            shift_line = line_of(s["sync0_shift_us"]);
            c.sync0_shift_us =
                shift(s["sync0_shift_us"], c.cycle_us, "`ethercat.sync0_shift_us`").value_or(0);
        }
        if (shift_line && dc_readable && c.sync != ethercat::SyncMode::DcSync0) {
            error(*shift_line, "`ethercat.sync0_shift_us` needs `dc: true` (SYNC0 exists only "
                               "with distributed clocks)");
        }
        if (s["esi"]) {
            c.esi = esi(s["esi"], "`ethercat.esi`");
        }
        const YAML::Node slaves = s["slaves"];
        if (!slaves || !slaves.IsSequence()) {
            error(key_line, "`ethercat` needs `slaves:`, a list (each item starts with "
                            "`- position: N`)");
        } else {
            std::set<unsigned> seen;
            for (const auto& n : slaves) {
                auto e = parse_slave(n, c);
                if (e && !seen.insert(e->position).second) {
                    error(e->line,
                          fmt::format("slave position {} is configured twice", e->position));
                }
                if (e) {
                    c.slaves.push_back(std::move(*e));
                }
            }
        }
        if (errors_.size() != errors_at_start_) {
            return std::nullopt;
        }
        return c;
    }

private:
    void error(int line, const std::string& msg) {
        errors_.push_back(fmt::format("{}:{}: {}", file_, line, msg));
    }

    void check_keys(const YAML::Node& map, std::initializer_list<const char*> known,
                    const std::string& where) {
        for (const auto& kv : map) {
            const auto key = kv.first.as<std::string>("");
            bool ok = false;
            for (const char* k : known) {
                ok = ok || key == k;
            }
            if (!ok) {
                std::string list;
                for (const char* k : known) {
                    list += list.empty() ? std::string(k) : std::string(", ") + k;
                }
                error(line_of(kv.first),
                      fmt::format("unknown key `{}` in {} (known: {})", key, where, list));
            }
        }
    }

    // A name or mode written as a list or a map is a finding at its line, not an empty string.
    std::optional<std::string> text(const YAML::Node& n, const std::string& what) {
        if (n.IsScalar()) {
            return n.Scalar();
        }
        error(line_of(n), fmt::format("{} must be a single value, but it is {}", what,
                                      n.IsMap()        ? "a map"
                                      : n.IsSequence() ? "a list"
                                                       : "empty"));
        return std::nullopt;
    }

    static std::optional<long long> number(const YAML::Node& n) {
        if (!n.IsScalar()) {
            return std::nullopt;
        }
        try {
            std::size_t used = 0;
            const std::string t = n.as<std::string>();
            const long long v = std::stoll(t, &used, 0);
            if (used != t.size()) {
                return std::nullopt;
            }
            return v;
        } catch (const std::exception&) {
            return std::nullopt;
        }
    }

    /// `sync: free|sm|dc` and the older `dc: true|false` of a map (`what` starts the key's
    /// name in messages: "`ethercat." or "slave 2: `"). The outer nullopt: a finding was
    /// reported; the inner one: neither key is there.
    std::optional<std::optional<ethercat::SyncMode>> sync_mode(const YAML::Node& m,
                                                               const std::string& what) {
        std::optional<ethercat::SyncMode> from_dc;
        if (m["dc"]) {
            const auto dc = flag(m["dc"], what + "dc`");
            if (!dc) {
                return std::nullopt;
            }
            from_dc = *dc ? ethercat::SyncMode::DcSync0 : ethercat::SyncMode::FreeRun;
        }
        if (!m["sync"]) {
            return from_dc;
        }
        const auto name = text(m["sync"], what + "sync`");
        const auto mode = name ? ethercat::sync_mode_from_string(*name) : std::nullopt;
        if (!name) {
            return std::nullopt;
        }
        if (!mode) {
            error(line_of(m["sync"]),
                  fmt::format("{}sync` must be free, sm or dc (ETG.1020 sync modes 0, 1, 2), but "
                              "it is `{}`",
                              what, *name));
            return std::nullopt;
        }
        if (from_dc && *from_dc != *mode) {
            error(line_of(m["sync"]),
                  fmt::format("{}sync: {}` and `dc: {}` disagree: give `sync:` "
                              "alone",
                              what, *name, from_dc == ethercat::SyncMode::DcSync0));
            return std::nullopt;
        }
        return mode;
    }

    // `dc: true|false`: anything else is a finding naming the key, not a silent false.
    std::optional<bool> flag(const YAML::Node& n, const std::string& what) {
        if (n.IsScalar()) {
            const std::string t = n.Scalar();
            if (t == "true") {
                return true;
            }
            if (t == "false") {
                return false;
            }
        }
        error(line_of(n), fmt::format("{} must be true or false, but it is {}", what,
                                      n.IsScalar()     ? "`" + n.Scalar() + "`"
                                      : n.IsMap()      ? std::string("a map")
                                      : n.IsSequence() ? std::string("a list")
                                                       : std::string("empty")));
        return std::nullopt;
    }

    // SYNC0 shift in µs: 0 up to one cycle (a shift of a whole cycle is the next SYNC0).
    std::optional<std::uint32_t> shift(const YAML::Node& n, std::uint32_t cycle_us,
                                       const std::string& what) {
        const auto v = number(n);
        if (!v || *v < 0 || *v >= static_cast<long long>(cycle_us)) {
            error(line_of(n), fmt::format("{} must be a number of microseconds, 0..{} (less than "
                                          "the cycle of {} µs)",
                                          what, cycle_us - 1U, cycle_us));
            return std::nullopt;
        }
        return static_cast<std::uint32_t>(*v);
    }

    std::optional<EcatSlaveEntry> parse_slave(const YAML::Node& n, const EcatSegmentConfig& seg) {
        EcatSlaveEntry e;
        e.line = line_of(n);
        if (!n.IsMap()) {
            error(e.line, "an EtherCAT slave must be a map with `position` and `profile`");
            return std::nullopt;
        }
        check_keys(n,
                   {"position", "name", "profile", "axes", "dc", "sync", "sync0_shift_us", "esi"},
                   "an EtherCAT slave");
        const auto pos = n["position"] ? number(n["position"]) : std::nullopt;
        if (!pos || *pos < 0 || *pos > 65535) {
            error(e.line, "an EtherCAT slave needs `position: N` (0 = first slave after the "
                          "master)");
            return std::nullopt;
        }
        e.position = static_cast<unsigned>(*pos);
        if (n["name"]) {
            e.name = text(n["name"], fmt::format("slave {}: `name`", e.position)).value_or("");
        }
        const drives::Profile* profile = nullptr;
        if (n["profile"]) {
            const auto name = text(n["profile"], fmt::format("slave {}: `profile`", e.position));
            e.profile = name.value_or("");
            profile = name ? drives::find_profile(e.profile) : nullptr;
            if (name && profile == nullptr) {
                error(line_of(n["profile"]),
                      fmt::format("slave {}: unknown profile `{}` (known: akd2g, ds-bvs, fio, "
                                  "generic)",
                                  e.position, e.profile));
            }
        } else {
            error(e.line, fmt::format("slave {}: `profile` is required (akd2g, ds-bvs, fio, "
                                      "generic)",
                                      e.position));
        }
        const auto mode = sync_mode(n, fmt::format("slave {}: `", e.position));
        e.sync = mode.value_or(std::nullopt);
        if (n["sync0_shift_us"]) {
            e.sync0_shift_us = shift(n["sync0_shift_us"], seg.cycle_us,
                                     fmt::format("slave {}: `sync0_shift_us`", e.position));
            const bool dc_readable = mode.has_value();
            if (dc_readable && !slave_dc(seg, e)) {
                error(line_of(n["sync0_shift_us"]),
                      fmt::format("slave {}: `sync0_shift_us` needs `dc: true` (SYNC0 exists "
                                  "only with distributed clocks)",
                                  e.position));
            }
        }
        e.esi = n["esi"] ? esi(n["esi"], fmt::format("slave {}: `esi`", e.position)) : seg.esi;
        if (n["axes"]) {
            if (!n["axes"].IsSequence()) {
                error(line_of(n["axes"]), fmt::format("slave {}: `axes` must be a list of "
                                                      "`{{axis: N, mode: M}}`",
                                                      e.position));
            } else {
                for (const auto& a : n["axes"]) {
                    parse_axis(a, e, profile);
                }
                check_axis_numbers(e);
            }
        }
        return e;
    }

    /// The controller maps axis n into RxPDO/TxPDO n (1600h/1A00h + n - 1; AKD2G manual
    /// §3.11.2), so a slave's axes are 1..n, each once.
    void check_axis_numbers(const EcatSlaveEntry& e) {
        std::vector<unsigned> numbers;
        for (const auto& a : e.axes) {
            numbers.push_back(a.axis);
        }
        std::sort(numbers.begin(), numbers.end());
        for (std::size_t i = 0; i < numbers.size(); ++i) {
            if (numbers[i] != i + 1) {
                error(e.line, fmt::format("slave {}: the axes must be numbered 1..n, each once "
                                          "(axis n goes into RxPDO/TxPDO n); {} has axes {}",
                                          e.position, e.profile, fmt::join(numbers, ", ")));
                return;
            }
        }
    }

    void parse_axis(const YAML::Node& a, EcatSlaveEntry& e, const drives::Profile* profile) {
        if (!a.IsMap()) {
            error(line_of(a), fmt::format("slave {}: an axis must be a map `{{axis: N, mode: M}}`",
                                          e.position));
            return;
        }
        check_keys(a, {"axis", "mode"}, fmt::format("slave {} axis", e.position));
        EcatAxisEntry ax;
        if (a["axis"]) {
            const auto v = number(a["axis"]);
            const unsigned max_axes = profile != nullptr ? profile->max_axes : 8U;
            if (!v || *v < 1 || *v > static_cast<long long>(max_axes)) {
                error(line_of(a["axis"]),
                      fmt::format("slave {}: axis must be 1..{}", e.position, max_axes));
                return;
            }
            ax.axis = static_cast<unsigned>(*v);
        }
        if (a["mode"]) {
            const auto written =
                text(a["mode"], fmt::format("slave {} axis {}: `mode`", e.position, ax.axis));
            if (!written) {
                return;
            }
            const std::string& mode_text = *written;
            ax.mode = master::parse_mode_name(mode_text);
            if (!ax.mode) {
                error(line_of(a["mode"]),
                      fmt::format("slave {} axis {}: unknown mode `{}` (use pp, pv, pt, hm, ip, "
                                  "csp, csv, cst or a number)",
                                  e.position, ax.axis, mode_text));
                return;
            }
            if (profile != nullptr && !profile->supports_mode(*ax.mode)) {
                error(line_of(a["mode"]),
                      fmt::format("slave {} axis {}: the {} does not support "
                                  "mode `{}`",
                                  e.position, ax.axis, profile->title, mode_text));
                return;
            }
        }
        e.axes.push_back(ax);
    }

    // `esi: path.xml`, relative to the bus file: read now, so a bad file is a finding of
    // `codrive run --check` and not a surprise at start.
    std::shared_ptr<const ethercat::EsiFile> esi(const YAML::Node& n, const std::string& what) {
        const auto path = text(n, what);
        if (!path) {
            return nullptr;
        }
        std::filesystem::path p(*path);
        if (p.is_relative()) {
            p = std::filesystem::path(file_).parent_path() / p;
        }
        auto loaded = ethercat::load_esi(p.lexically_normal().string());
        if (!loaded) {
            error(line_of(n), fmt::format("{}: {}", what, loaded.error()));
            return nullptr;
        }
        return std::make_shared<const ethercat::EsiFile>(std::move(*loaded));
    }

    std::string file_;
    std::vector<std::string>& errors_;
    std::size_t errors_at_start_ = errors_.size();
};

} // namespace

ethercat::SyncMode slave_sync(const EcatSegmentConfig& segment, const EcatSlaveEntry& slave) {
    return slave.sync.value_or(segment.sync);
}

bool slave_dc(const EcatSegmentConfig& segment, const EcatSlaveEntry& slave) {
    return slave_sync(segment, slave) == ethercat::SyncMode::DcSync0;
}

std::uint32_t slave_sync0_shift_us(const EcatSegmentConfig& segment, const EcatSlaveEntry& slave) {
    return slave.sync0_shift_us.value_or(segment.sync0_shift_us);
}

BusFileSections split_bus_file(const std::string& text, const std::string& file) {
    BusFileSections out;
    // Blank the `ethercat:` block line by line (a comment keeps the line numbers of the CAN
    // part, so the master's loader reports the same lines the user sees).
    std::istringstream in(text);
    std::string line;
    bool inside = false;
    int line_no = 0;
    int ethercat_line = 1;
    while (std::getline(in, line)) {
        ++line_no;
        if (starts_top_level_key(line)) {
            inside = line.rfind("ethercat:", 0) == 0;
            if (inside) {
                ethercat_line = line_no;
            }
            if (line.rfind("bus:", 0) == 0) {
                out.has_can = true;
            }
        }
        out.can_text += inside ? "#" + line : line;
        out.can_text += '\n';
    }
    YAML::Node root;
    try {
        root = YAML::Load(text);
    } catch (const YAML::ParserException& e) {
        out.errors.push_back(
            fmt::format("{}:{}: not valid YAML: {}", file, e.mark.line + 1, e.msg));
        return out;
    }
    if (root.IsMap() && root["ethercat"]) {
        SectionParser p(file, out.errors);
        out.ethercat = p.parse(root["ethercat"], ethercat_line);
    }
    if (!out.has_can && !(root.IsMap() && root["ethercat"])) {
        out.errors.push_back(fmt::format("{}:1: the file has neither a `bus:` (CAN) nor an "
                                         "`ethercat:` section",
                                         file));
    }
    return out;
}

} // namespace codrive::controller
