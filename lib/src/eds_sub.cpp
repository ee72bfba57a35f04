// SPDX-License-Identifier: Apache-2.0
// EDS/DCF keys of one value: ObjectType, DataType, AccessType, defaults, limits, PDOMapping.
#include "eds_internal.hpp"

#include <fmt/format.h>

#include <array>
#include <cctype>
#include <string>
#include <vector>

namespace codrive::eds {

std::optional<ObjectCode> object_code(Section& s, Findings& f) {
    Entry* e = s.find("ObjectType");
    if (e == nullptr || e->value.empty()) {
        return ObjectCode::Var; // CiA 306: VAR when absent
    }
    const std::string_view text = number_text(s, *e, f);
    static constexpr std::array<std::pair<std::string_view, ObjectCode>, 7> kNames = {
        {{"NULL", ObjectCode::Null},
         {"DOMAIN", ObjectCode::Domain},
         {"DEFTYPE", ObjectCode::Deftype},
         {"DEFSTRUCT", ObjectCode::Defstruct},
         {"VAR", ObjectCode::Var},
         {"ARRAY", ObjectCode::Array},
         {"RECORD", ObjectCode::Record}}};
    for (auto [name, code] : kNames) {
        if (iequals(text, name)) {
            f.warning(e->line, fmt::format("[{}] ObjectType={} should be the number 0x{:X}", s.name,
                                           text, static_cast<unsigned>(code)));
            return code;
        }
    }
    auto v = read_uint(text, 0xFF, e->line, fmt::format("[{}] ObjectType", s.name), f);
    if (!v) {
        return std::nullopt;
    }
    for (auto [name, code] : kNames) {
        if (*v == static_cast<unsigned>(code)) {
            return code;
        }
    }
    f.error(e->line, fmt::format("[{}] ObjectType 0x{:X} is not a CiA 301 object code (0x0, 0x2, "
                                 "0x5..0x9); object skipped",
                                 s.name, *v));
    return std::nullopt;
}

namespace {

std::optional<DataType> data_type(Section& s, std::optional<DataType> fallback, Findings& f) {
    Entry* e = s.find("DataType");
    if (e == nullptr || e->value.empty()) {
        if (!fallback) {
            f.error(s.line, fmt::format("[{}] has no DataType; skipped", s.name));
        }
        return fallback;
    }
    const std::string_view text = number_text(s, *e, f);
    if (!text.empty() && std::isalpha(static_cast<unsigned char>(text[0])) != 0) {
        // Some tools write the type's name; CiA 306 wants its index.
        if (auto named = data_type_from_name(text)) {
            f.warning(e->line, fmt::format("[{}] DataType={} should be the index 0x{:04X}", s.name,
                                           text, static_cast<unsigned>(*named)));
            return named;
        }
    }
    auto v = read_uint(text, 0xFFFF, e->line, fmt::format("[{}] DataType", s.name), f);
    if (!v) {
        return std::nullopt;
    }
    auto t = data_type_from_index(static_cast<std::uint16_t>(*v));
    if (!t) {
        f.error(e->line, fmt::format("[{}] DataType 0x{:04X} is not a basic CiA 301 data type "
                                     "codrive supports; skipped",
                                     s.name, *v));
    }
    return t;
}

Access access_type(Section& s, Findings& f) {
    Entry* e = s.find("AccessType");
    if (e == nullptr || e->value.empty()) {
        f.error(e == nullptr ? s.line : e->line,
                fmt::format("[{}] has no AccessType; assuming ro", s.name));
        return Access::Ro;
    }
    const std::string_view text = number_text(s, *e, f);
    auto a = access_from_string(text);
    if (!a) {
        f.error(e->line, fmt::format("[{}] AccessType '{}' is not one of ro, wo, rw, rwr, rww, "
                                     "const; assuming ro",
                                     s.name, text.substr(0, 40)));
        return Access::Ro;
    }
    if (text != to_string(*a)) {
        f.warning(e->line, fmt::format("[{}] AccessType '{}' should be written '{}'", s.name, text,
                                       to_string(*a)));
    }
    return *a;
}

} // namespace

// Reads a value key (DefaultValue, ParameterValue, LowLimit, HighLimit) for sub.type.
std::optional<Value> value_key(Section& s, Entry& e, DataType type, Findings& f,
                               std::optional<NodeId> node) {
    const bool text_type = type == DataType::VisibleString || type == DataType::UnicodeString;
    ValueText vt =
        parse_value(type, text_type ? std::string_view(e.value) : number_text(s, e, f), node);
    for (auto& note : vt.notes) {
        f.warning(e.line, fmt::format("[{}] {}: {}", s.name, e.key, note));
    }
    if (!vt.value) {
        f.error(e.line, fmt::format("[{}] {} {}", s.name, e.key, vt.error));
    }
    return std::move(vt.value);
}

// The value text kept for display and for $NODEID re-evaluation: a number's trailing `; comment`
// (maxon, Elmo) is dropped as number_text() does; VISIBLE_STRING / UNICODE_STRING text is kept
// whole, because ';' is an ordinary character of a string value.
std::string stored_text(const Section& s, Entry& e, DataType type, Findings& f) {
    if (type == DataType::VisibleString || type == DataType::UnicodeString) {
        return e.value;
    }
    return std::string(number_text(s, e, f));
}

namespace {

// -1, 0, 1 comparing two numeric values of the same type; nullopt when not comparable.
std::optional<int> compare(const Value& a, const Value& b) {
    if (is_real(a.type())) {
        auto x = a.as_double();
        auto y = b.as_double();
        if (!x || !y || *x != *x || *y != *y) {
            return std::nullopt;
        }
        return *x < *y ? -1 : (*x > *y ? 1 : 0);
    }
    if (is_signed_integer(a.type())) {
        auto x = a.as_int();
        auto y = b.as_int();
        if (!x || !y) {
            return std::nullopt;
        }
        return *x < *y ? -1 : (*x > *y ? 1 : 0);
    }
    auto x = a.as_uint();
    auto y = b.as_uint();
    if (!x || !y) {
        return std::nullopt;
    }
    return *x < *y ? -1 : (*x > *y ? 1 : 0);
}

void check_limits(Section& s, const SubObject& sub, const Value& v, const char* what,
                  std::size_t line, Findings& f) {
    if (sub.low_limit) {
        auto c = compare(v, *sub.low_limit);
        if (c && *c < 0) {
            f.warning(line, fmt::format("[{}] {} {} is below LowLimit {}", s.name, what,
                                        v.to_string(), sub.low_limit->to_string()));
        }
    }
    if (sub.high_limit) {
        auto c = compare(v, *sub.high_limit);
        if (c && *c > 0) {
            f.warning(line, fmt::format("[{}] {} {} is above HighLimit {}", s.name, what,
                                        v.to_string(), sub.high_limit->to_string()));
        }
    }
}

// "1..5, 9" for a sorted list of node-IDs.
std::string node_ranges(const std::vector<unsigned>& ids) {
    std::string out;
    for (std::size_t i = 0; i < ids.size();) {
        std::size_t j = i;
        while (j + 1 < ids.size() && ids[j + 1] == ids[j] + 1) {
            ++j;
        }
        out += fmt::format("{}{}", out.empty() ? "" : ", ", ids[i]);
        if (j > i) {
            out += fmt::format("..{}", ids[j]);
        }
        i = j + 1;
    }
    return out;
}

// A value or limit written with $NODEID (CiA 306 §4.5.2) depends on the node-ID the device gets.
// Without one, evaluating $NODEID as 0 gives false alarms (`$NODEID+0x80` against LowLimit=0x81),
// so the limits are checked for every node-ID 1..127 (CiA 301 §7.3.2.2.1) and a finding names the
// node-IDs that break them.
void check_limits_each_node(Section& s, const SubObject& sub, std::string_view text,
                            const char* what, std::size_t line, Findings& f) {
    struct Limit {
        const char* key;
        const std::optional<Value>* parsed;
        int bad_sign;
        const char* word;
        std::vector<unsigned> failing{};
        std::string text{};
    };
    std::array<Limit, 2> limits{Limit{"LowLimit", &sub.low_limit, -1, "below"},
                                Limit{"HighLimit", &sub.high_limit, 1, "above"}};
    for (auto& l : limits) {
        if (Entry* e = s.find(l.key); e != nullptr && l.parsed->has_value()) {
            l.text = std::string(number_text(s, *e, f));
        }
    }
    for (unsigned n = 1; n <= 127; ++n) {
        const auto node = static_cast<NodeId>(n);
        auto v = parse_value(sub.type, text, node).value;
        if (!v) {
            continue;
        }
        for (auto& l : limits) {
            if (l.text.empty()) {
                continue;
            }
            std::optional<Value> limit =
                uses_node_id(l.text) ? parse_value(sub.type, l.text, node).value : *l.parsed;
            auto c = limit ? compare(*v, *limit) : std::nullopt;
            if (c && *c == l.bad_sign) {
                l.failing.push_back(n);
            }
        }
    }
    for (const auto& l : limits) {
        if (!l.failing.empty()) {
            f.warning(line, fmt::format("[{}] {} {} is {} {} {} for node-ID {} (checked for every "
                                        "node-ID 1..127)",
                                        s.name, what, text, l.word, l.key, l.text,
                                        node_ranges(l.failing)));
        }
    }
}

// Limit check of a DefaultValue/ParameterValue: for the given node-ID, or for every node-ID when
// none is given and the value or a limit uses $NODEID.
void check_value(Section& s, const SubObject& sub, const Value& v, std::string_view text,
                 const char* what, std::size_t line, Findings& f, std::optional<NodeId> node) {
    const auto limit_uses_node_id = [&](const char* key) {
        const Entry* e = s.find(key);
        return e != nullptr && uses_node_id(e->value);
    };
    if (!node &&
        (uses_node_id(text) || limit_uses_node_id("LowLimit") || limit_uses_node_id("HighLimit"))) {
        check_limits_each_node(s, sub, text, what, line, f);
    } else {
        check_limits(s, sub, v, what, line, f);
    }
}

} // namespace

// Parses the keys describing one value (a VAR object section, a sub-object section, or the
// template of a CompactSubObj array). Returns false when the entry cannot be represented.
bool parse_sub(Section& s, SubObject& sub, bool read_name, std::optional<DataType> fallback,
               Findings& f, std::optional<NodeId> node) {
    if (read_name) {
        if (Entry* e = s.find("ParameterName")) {
            sub.name = e->value;
        } else {
            f.warning(s.line, fmt::format("[{}] has no ParameterName", s.name));
        }
    }
    auto type = data_type(s, fallback, f);
    if (!type) {
        return false;
    }
    sub.type = *type;
    sub.access = access_type(s, f);
    sub.pdo_mappable = get_bool(s, "PDOMapping", f).value_or(false);
    sub.obj_flags = static_cast<std::uint32_t>(get_uint(s, "ObjFlags", 0xFFFFFFFF, f).value_or(0));
    for (auto [key, slot] :
         {std::pair{"LowLimit", &sub.low_limit}, std::pair{"HighLimit", &sub.high_limit}}) {
        Entry* e = s.find(key);
        if (e == nullptr || e->value.empty()) {
            continue;
        }
        if (is_variable_size(sub.type)) {
            f.warning(e->line, fmt::format("[{}] {} has no meaning for {}; ignored", s.name, key,
                                           to_string(sub.type)));
            continue;
        }
        *slot = value_key(s, *e, sub.type, f, node);
    }
    if (sub.low_limit && sub.high_limit) {
        auto c = compare(*sub.low_limit, *sub.high_limit);
        if (c && *c > 0) {
            f.warning(s.find("LowLimit")->line,
                      fmt::format("[{}] LowLimit {} is above HighLimit {}", s.name,
                                  sub.low_limit->to_string(), sub.high_limit->to_string()));
        }
    }
    if (Entry* e = s.find("DefaultValue")) {
        sub.default_text = stored_text(s, *e, sub.type, f);
        if (!e->value.empty()) {
            sub.default_value = value_key(s, *e, sub.type, f, node);
        } else if (is_variable_size(sub.type)) {
            sub.default_value = Value(sub.type, {}); // an empty string is a value
        }
        if (sub.default_value) {
            check_value(s, sub, *sub.default_value, sub.default_text, "DefaultValue", e->line, f,
                        node);
        }
    }
    std::optional<Value> parameter;
    if (Entry* e = s.find("ParameterValue"); e != nullptr && !e->value.empty()) {
        sub.parameter_text = stored_text(s, *e, sub.type, f);
        parameter = value_key(s, *e, sub.type, f, node);
        if (parameter) {
            check_value(s, sub, *parameter, sub.parameter_text, "ParameterValue", e->line, f, node);
        }
    }
    sub.value =
        parameter ? *parameter : (sub.default_value ? *sub.default_value : Value::zero(sub.type));
    // Keys of CiA 306 DCFs and tools that carry nothing codrive models.
    for (auto key : {"Denotation", "StorageLocation"}) {
        (void)s.find(key);
    }
    return true;
}

} // namespace codrive::eds
