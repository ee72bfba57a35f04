// SPDX-License-Identifier: Apache-2.0
// Command-line specs of codrive-sim.
#include <codrive/sim/options.hpp>

#include <codrive/core/value.hpp>

#include <fmt/format.h>

#include <charconv>

namespace codrive::sim {

bool parse_duration(std::string_view text, Duration& out) {
    double scale = 1e6; // default: milliseconds, in ns
    std::string_view num = text;
    const auto ends = [&](std::string_view suffix) {
        return num.size() > suffix.size() && num.substr(num.size() - suffix.size()) == suffix;
    };
    if (ends("ms")) {
        num.remove_suffix(2);
    } else if (ends("us")) {
        num.remove_suffix(2);
        scale = 1e3;
    } else if (ends("s")) {
        num.remove_suffix(1);
        scale = 1e9;
    }
    if (num.empty()) {
        return false;
    }
    double v = 0;
    auto [ptr, ec] = std::from_chars(num.data(), num.data() + num.size(), v);
    if (ec != std::errc{} || ptr != num.data() + num.size() || v < 0) {
        return false;
    }
    out = Duration{static_cast<Duration::rep>(v * scale)};
    return true;
}

bool parse_node_spec(std::string_view text, NodeSpec& out, std::string& error) {
    const auto colon = text.find(':');
    if (colon == std::string_view::npos) {
        error = fmt::format("node spec '{}' needs ID:PROFILE (e.g. 1:akd2g)", text);
        return false;
    }
    const auto id = parse_uint(text.substr(0, colon));
    if (!id || !valid_node_id(static_cast<unsigned>(*id))) {
        error = fmt::format("node spec '{}': node id must be 1..127", text);
        return false;
    }
    std::string_view rest = text.substr(colon + 1);
    unsigned axes = 0;
    if (const auto c2 = rest.find(':'); c2 != std::string_view::npos) {
        const auto a = parse_uint(rest.substr(c2 + 1));
        if (!a || *a < 1 || *a > 2) {
            error = fmt::format("node spec '{}': axis count must be 1 or 2", text);
            return false;
        }
        axes = static_cast<unsigned>(*a);
        rest = rest.substr(0, c2);
    }
    const SimProfile* p = find_profile(rest);
    if (p == nullptr) {
        error = fmt::format("node spec '{}': unknown profile '{}' (known: akd2g, ds-bvs, fio)",
                            text, rest);
        return false;
    }
    if (axes > p->max_axes()) {
        error =
            fmt::format("node spec '{}': {} has at most {} axis", text, p->name(), p->max_axes());
        return false;
    }
    out = NodeSpec{static_cast<NodeId>(*id), p, axes};
    return true;
}

bool parse_fault_spec(std::string_view text, FaultSpec& out, std::string& error) {
    const auto colon = text.find(':');
    if (colon == std::string_view::npos) {
        error = fmt::format("fault spec '{}' needs NODE[.AXIS]:KIND[@TIME] (e.g. 1:sto@2s)", text);
        return false;
    }
    std::string_view who = text.substr(0, colon);
    std::string_view what = text.substr(colon + 1);
    FaultSpec f;
    if (const auto dot = who.find('.'); dot != std::string_view::npos) {
        const auto axis = parse_uint(who.substr(dot + 1));
        if (!axis || *axis < 1 || *axis > 2) {
            error = fmt::format("fault spec '{}': axis must be 1 or 2", text);
            return false;
        }
        f.axis = static_cast<unsigned>(*axis - 1);
        who = who.substr(0, dot);
    }
    const auto node = parse_uint(who);
    if (!node || !valid_node_id(static_cast<unsigned>(*node))) {
        error = fmt::format("fault spec '{}': node id must be 1..127", text);
        return false;
    }
    f.node = static_cast<NodeId>(*node);
    if (const auto at = what.find('@'); at != std::string_view::npos) {
        if (!parse_duration(what.substr(at + 1), f.after)) {
            error = fmt::format("fault spec '{}': time '{}' is not like 2s or 500ms", text,
                                what.substr(at + 1));
            return false;
        }
        what = what.substr(0, at);
    }
    if (!parse_fault_kind(what, f.kind)) {
        error = fmt::format("fault spec '{}': unknown fault '{}' (sto, overcurrent, "
                            "following-error, heartbeat-loss, reset)",
                            text, what);
        return false;
    }
    out = f;
    return true;
}

} // namespace codrive::sim
