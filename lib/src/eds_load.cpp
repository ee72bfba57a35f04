// SPDX-License-Identifier: Apache-2.0
// Entry points of the EDS/DCF reader: parse text, load a file, findings, node-ID assignment.
#include "eds_internal.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cerrno>
#include <fstream>
#include <sstream>

namespace codrive {

std::string_view to_string(EdsSeverity s) {
    switch (s) {
    case EdsSeverity::Info:
        return "info";
    case EdsSeverity::Warning:
        return "warning";
    case EdsSeverity::Error:
        return "error";
    }
    return "error";
}

std::string format_finding(const EdsFinding& f) {
    return fmt::format("{}:{}: {}: {}", f.file, f.line, to_string(f.severity), f.message);
}

std::size_t DeviceDescription::count(EdsSeverity s) const {
    return static_cast<std::size_t>(std::count_if(
        findings.begin(), findings.end(), [s](const EdsFinding& f) { return f.severity == s; }));
}

DeviceDescription parse_eds(std::string_view text, std::string filename,
                            std::optional<NodeId> node_id) {
    DeviceDescription desc;
    eds::Findings findings(std::move(filename), desc.findings);
    eds::IniFile ini = eds::tokenize(text, findings);
    eds::parse_header_sections(ini, desc, findings);
    desc.node_id = node_id ? node_id : desc.commissioning.node_id;
    if (node_id && !valid_node_id(*node_id)) {
        findings.error(0, fmt::format("node-ID {} is not valid (1..127); $NODEID counts as 0",
                                      static_cast<unsigned>(*node_id)));
        desc.node_id.reset();
    }
    eds::parse_objects(ini, desc, findings);
    // Findings in file order; those about the file as a whole (line 0) first.
    std::stable_sort(desc.findings.begin(), desc.findings.end(),
                     [](const EdsFinding& a, const EdsFinding& b) { return a.line < b.line; });
    return desc;
}

Result<DeviceDescription> load_eds(const std::string& path, std::optional<NodeId> node_id) {
    std::ifstream in(path, std::ios::binary);
    if (!in) {
        return fail_errno(errno != 0 ? errno : ENOENT);
    }
    std::ostringstream buf;
    buf << in.rdbuf();
    if (in.bad()) {
        return fail_errno(errno != 0 ? errno : EIO);
    }
    return parse_eds(buf.str(), path, node_id);
}

void assign_node_id(DeviceDescription& desc, NodeId node) {
    desc.node_id = node;
    for (const auto& [index, obj] : desc.od.objects()) {
        for (const auto& [si, cref] : obj.subs) {
            SubObject* sub = desc.od.find(index, si);
            if (eds::uses_node_id(sub->default_text)) {
                auto v = eds::parse_value(sub->type, sub->default_text, node);
                if (v.value) {
                    sub->default_value = std::move(v.value);
                    if (sub->parameter_text.empty()) {
                        sub->value = *sub->default_value;
                    }
                }
            }
            if (eds::uses_node_id(sub->parameter_text)) {
                auto v = eds::parse_value(sub->type, sub->parameter_text, node);
                if (v.value) {
                    sub->value = std::move(*v.value);
                }
            }
        }
    }
}

} // namespace codrive
