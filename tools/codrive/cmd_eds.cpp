// SPDX-License-Identifier: Apache-2.0
// `codrive eds lint|show|export`: check an EDS/DCF file, print its object dictionary, or write a
// built-in profile as one.
#include "command_registry.hpp"
#include "device_export.hpp"

#include <codrive/core/eds.hpp>

#include <fmt/format.h>

#include <algorithm>
#include <cstdio>
#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace codrive::cli {
namespace {

struct EdsArgs {
    std::string file;
    std::string index; // "1018", "0x1018", "1018:2"
    int node_id = 0;
    bool no_info = false;
};

std::optional<NodeId> node_arg(int n) {
    return n > 0 ? std::optional<NodeId>(static_cast<NodeId>(n)) : std::nullopt;
}

int run_lint(const EdsArgs& a) {
    auto desc = load_eds(a.file, node_arg(a.node_id));
    if (!desc) {
        fmt::print(stderr, "codrive eds lint: cannot read {}: {}\n", a.file,
                   desc.error().message());
        return kExitFailure;
    }
    for (const auto& f : desc->findings) {
        if (a.no_info && f.severity == EdsSeverity::Info) {
            continue;
        }
        fmt::print("{}\n", format_finding(f));
    }
    fmt::print(stderr, "{}: {} objects, {} errors, {} warnings, {} notes\n", a.file,
               desc->od.size(), desc->count(EdsSeverity::Error), desc->count(EdsSeverity::Warning),
               desc->count(EdsSeverity::Info));
    return desc->has_errors() ? kExitFailure : kExitOk;
}

std::string pdo_text(const SubObject& s) {
    const bool t = s.mappable(PdoDir::Tpdo);
    const bool r = s.mappable(PdoDir::Rpdo);
    return t && r ? "T+R" : (t ? "T" : (r ? "R" : "-"));
}

std::string value_text(const SubObject& s) {
    // A number without DefaultValue (or with an empty one) and without ParameterValue has no
    // default (CiA 306 §4.6.3: DefaultValue is optional): print that, not the zero the model
    // holds. python-canopen reads such entries as "no default" too; `eds show` printed
    // 0x00000000 for CANopenDemo's 1003h:01..10h and lely's 1016h:00.
    if (!s.default_value && s.parameter_text.empty() && s.type != DataType::VisibleString &&
        s.type != DataType::UnicodeString && s.type != DataType::OctetString &&
        s.type != DataType::Domain) {
        return "(no default)";
    }
    std::string v = eds_value_text(s.value);
    if (v.size() > 48) {
        v = v.substr(0, 45) + "...";
    }
    const std::string& text = s.parameter_text.empty() ? s.default_text : s.parameter_text;
    if (text.find('$') != std::string::npos) {
        v += fmt::format(" ({})", text);
    }
    if (!s.parameter_text.empty() && s.default_value && !(*s.default_value == s.value)) {
        v += fmt::format(" [default {}]", eds_value_text(*s.default_value));
    }
    return v;
}

struct Row {
    std::string where, name, type, access, pdo, value;
};

bool parse_selector(const std::string& text, std::optional<std::uint16_t>& index,
                    std::optional<std::uint8_t>& sub) {
    if (text.empty()) {
        return true;
    }
    std::string idx = text;
    std::string si;
    if (auto colon = text.find(':'); colon != std::string::npos) {
        idx = text.substr(0, colon);
        si = text.substr(colon + 1);
    }
    // Indexes are hex in CANopen, with or without 0x; sub-indexes too.
    auto hex = [](std::string s) -> std::optional<std::uint32_t> {
        if (s.size() > 2 && s[0] == '0' && (s[1] == 'x' || s[1] == 'X')) {
            s = s.substr(2);
        }
        auto v = parse_uint("0x" + s);
        return v && *v <= 0xFFFF ? std::optional<std::uint32_t>(static_cast<std::uint32_t>(*v))
                                 : std::nullopt;
    };
    auto i = hex(idx);
    if (!i) {
        return false;
    }
    index = static_cast<std::uint16_t>(*i);
    if (!si.empty()) {
        auto s = hex(si);
        if (!s || *s > 0xFF) {
            return false;
        }
        sub = static_cast<std::uint8_t>(*s);
    }
    return true;
}

int run_show(const EdsArgs& a) {
    std::optional<std::uint16_t> only_index;
    std::optional<std::uint8_t> only_sub;
    if (!parse_selector(a.index, only_index, only_sub)) {
        fmt::print(stderr, "codrive eds show: '{}' is not an index (like 1018, 0x6040 or 1018:2)\n",
                   a.index);
        return kExitUsage;
    }
    auto desc = load_eds(a.file, node_arg(a.node_id));
    if (!desc) {
        fmt::print(stderr, "codrive eds show: cannot read {}: {}\n", a.file,
                   desc.error().message());
        return kExitFailure;
    }
    std::vector<Row> rows;
    rows.push_back({"INDEX", "NAME", "TYPE", "ACCESS", "PDO", "DEFAULT/VALUE"});
    for (const auto& [index, obj] : desc->od.objects()) {
        if (only_index && index != *only_index) {
            continue;
        }
        const bool complex = obj.code == ObjectCode::Array || obj.code == ObjectCode::Record ||
                             obj.code == ObjectCode::Defstruct;
        if (complex) {
            rows.push_back({fmt::format("{:04X}", index), obj.name,
                            std::string(to_string(obj.code)), "", "", ""});
        }
        for (const auto& [si, sub] : obj.subs) {
            if (only_sub && si != *only_sub) {
                continue;
            }
            rows.push_back({fmt::format("{:04X}:{:02X}", index, si),
                            complex ? "  " + sub.name : obj.name, std::string(to_string(sub.type)),
                            std::string(to_string(sub.access)), pdo_text(sub), value_text(sub)});
        }
    }
    if (rows.size() == 1) {
        fmt::print(stderr, "codrive eds show: {} has no object {}\n", a.file, a.index);
        return kExitFailure;
    }
    std::size_t w[5] = {0, 0, 0, 0, 0};
    for (const auto& r : rows) {
        w[0] = std::max(w[0], r.where.size());
        w[1] = std::max(w[1], std::min<std::size_t>(r.name.size(), 48));
        w[2] = std::max(w[2], r.type.size());
        w[3] = std::max(w[3], r.access.size());
        w[4] = std::max(w[4], r.pdo.size());
    }
    for (const auto& r : rows) {
        std::string line =
            fmt::format("{:<{}}  {:<{}}  {:<{}}  {:<{}}  {:<{}}  {}", r.where, w[0], r.name, w[1],
                        r.type, w[2], r.access, w[3], r.pdo, w[4], r.value);
        while (!line.empty() && line.back() == ' ') {
            line.pop_back();
        }
        fmt::print("{}\n", line);
    }
    if (desc->has_errors()) {
        fmt::print(stderr, "{}: {} errors; run `codrive eds lint {}`\n", a.file,
                   desc->count(EdsSeverity::Error), a.file);
    }
    return kExitOk;
}

void install_eds(CLI::App& app, int& exit_code) {
    auto args = std::make_shared<EdsArgs>();
    CLI::App* eds =
        app.add_subcommand("eds", "Check, print and export EDS/DCF device descriptions");
    eds->require_subcommand(1);

    CLI::App* lint = eds->add_subcommand(
        "lint", "Print the findings in an EDS/DCF file as FILE:LINE: severity: message; exit 1 "
                "if any is an error");
    lint->add_option("file", args->file, "EDS or DCF file")->required();
    lint->add_option("--node-id", args->node_id, "node-ID for $NODEID (default: DCF NodeID)")
        ->check(CLI::Range(1, 127));
    lint->add_flag("--no-info", args->no_info, "do not print info findings");
    lint->callback([args, &exit_code] { exit_code = run_lint(*args); });

    CLI::App* show = eds->add_subcommand("show", "Print the object dictionary of an EDS/DCF file");
    show->add_option("file", args->file, "EDS or DCF file")->required();
    show->add_option("index", args->index, "only this object, hex (1018, 0x6040, 1018:2)");
    show->add_option("--node-id", args->node_id, "node-ID for $NODEID (default: DCF NodeID)")
        ->check(CLI::Range(1, 127));
    show->callback([args, &exit_code] { exit_code = run_show(*args); });

    install_export(*eds, false, exit_code);
}

CODRIVE_REGISTER_COMMAND(install_eds);

} // namespace
} // namespace codrive::cli
