// SPDX-License-Identifier: Apache-2.0
// EDS/DCF object lists and object sections (CiA 306) into the object dictionary.
#include "eds_internal.hpp"

#include <fmt/format.h>

#include <array>
#include <cctype>

namespace codrive::eds {
namespace {

constexpr std::uint16_t kUnsigned8 = static_cast<std::uint16_t>(DataType::Unsigned8);

void parse_compact(std::uint16_t index, Section& s, Object& obj, std::uint8_t count, Catalog& cat,
                   Findings& f, std::optional<NodeId> node) {
    // CiA 306 §4.5.2: the object section describes every sub-object 1..N; sub 0 is the
    // UNSIGNED8 count; names are the object name followed by the sub-index (as lely and the
    // CANopen tools generate them), unless [xxxxName] gives them.
    SubObject tmpl;
    if (!parse_sub(s, tmpl, false, std::nullopt, f, node)) {
        return;
    }
    SubObject sub0;
    sub0.subindex = 0;
    sub0.name = "NrOfObjects";
    sub0.type = DataType::Unsigned8;
    sub0.access = Access::Ro;
    sub0.default_text = std::to_string(count);
    sub0.default_value = Value::from_uint(DataType::Unsigned8, count).value();
    sub0.value = *sub0.default_value;
    obj.subs[0] = sub0;
    for (unsigned i = 1; i <= count; ++i) {
        SubObject sub = tmpl;
        sub.subindex = static_cast<std::uint8_t>(i);
        sub.name = fmt::format("{}{}", obj.name, i);
        obj.subs[sub.subindex] = std::move(sub);
    }
    auto entries = [&](Section* sec, auto&& apply) {
        if (sec == nullptr) {
            return;
        }
        Entry* nr = sec->find("NrOfEntries");
        const auto declared = get_uint(*sec, "NrOfEntries", 0xFF, f);
        if (nr == nullptr) {
            f.warning(sec->line, fmt::format("[{}] has no NrOfEntries", sec->name));
        }
        std::size_t n = 0;
        for (auto& e : sec->entries) {
            if (e.used) {
                continue;
            }
            IntegerText key = parse_integer(e.key, std::nullopt);
            if (!key.value || key.uses_node_id || key.value->negative) {
                continue;
            }
            e.used = true;
            ++n;
            if (key.value->magnitude == 0 || key.value->magnitude > count) {
                f.warning(e.line, fmt::format("[{}] sub-index {} is outside 1..{} "
                                              "(CompactSubObj); ignored",
                                              sec->name, e.key, count));
                continue;
            }
            apply(obj.subs[static_cast<std::uint8_t>(key.value->magnitude)], e, *sec);
        }
        if (declared && *declared != n) {
            f.warning(nr->line, fmt::format("[{}] NrOfEntries={} but {} entries are given",
                                            sec->name, *declared, n));
        }
        report_unused(*sec, f);
    };
    entries(cat.names.count(index) != 0 ? cat.names[index] : nullptr,
            [](SubObject& sub, Entry& e, Section&) { sub.name = e.value; });
    entries(cat.values.count(index) != 0 ? cat.values[index] : nullptr,
            [&](SubObject& sub, Entry& e, Section& sec) {
                // In an EDS these are the default values of the sub-objects.
                sub.default_text = stored_text(sec, e, sub.type, f);
                sub.default_value = value_key(sec, e, sub.type, f, node);
                sub.value = sub.default_value ? *sub.default_value : Value::zero(sub.type);
            });
}

void parse_object(std::uint16_t index, Section& s, Catalog& cat, ObjectDictionary& od, Findings& f,
                  std::optional<NodeId> node) {
    Object obj;
    obj.index = index;
    if (Entry* e = s.find("ParameterName")) {
        obj.name = e->value;
    } else {
        f.warning(s.line, fmt::format("[{}] has no ParameterName", s.name));
    }
    auto code = object_code(s, f);
    if (!code) {
        return;
    }
    obj.code = *code;
    auto subs_it = cat.subs.find(index);
    const bool has_sub_sections = subs_it != cat.subs.end() && !subs_it->second.empty();
    const bool complex = obj.code == ObjectCode::Array || obj.code == ObjectCode::Record ||
                         obj.code == ObjectCode::Defstruct;
    if (!complex) {
        SubObject sub;
        sub.name = obj.name;
        const auto fallback = obj.code == ObjectCode::Domain
                                  ? std::optional<DataType>(DataType::Domain)
                                  : std::nullopt;
        if (obj.code == ObjectCode::Null && s.find("DataType") == nullptr) {
            od.insert(std::move(obj));
            return;
        }
        if (!parse_sub(s, sub, false, fallback, f, node)) {
            return;
        }
        obj.obj_flags = sub.obj_flags;
        obj.subs[0] = std::move(sub);
        for (auto key : {"SubNumber", "CompactSubObj"}) {
            if (Entry* e = s.find(key); e != nullptr && e->value != "0" && !e->value.empty()) {
                f.warning(e->line, fmt::format("[{}] {} has no meaning for a {} object; ignored",
                                               s.name, key, to_string(obj.code)));
            }
        }
        if (has_sub_sections) {
            f.warning(subs_it->second.begin()->second->line,
                      fmt::format("[{}] is a sub-object of 0x{:04X}, which is a {} (ObjectType); "
                                  "ignored",
                                  subs_it->second.begin()->second->name, index,
                                  to_string(obj.code)));
        }
        report_unused(s, f);
        od.insert(std::move(obj));
        return;
    }
    obj.obj_flags = static_cast<std::uint32_t>(get_uint(s, "ObjFlags", 0xFFFFFFFF, f).value_or(0));
    Entry* sub_number_entry = s.find("SubNumber");
    const auto sub_number = get_uint(s, "SubNumber", 0xFF + 1, f);
    Entry* compact_entry = s.find("CompactSubObj");
    const auto compact = get_uint(s, "CompactSubObj", 0xFE, f);
    if (compact && *compact > 0) {
        if (obj.code != ObjectCode::Array) {
            f.warning(compact_entry->line,
                      fmt::format("[{}] CompactSubObj is defined for ARRAY objects (CiA 306 "
                                  "§4.5.2), this is a {}; accepted",
                                  s.name, to_string(obj.code)));
        }
        parse_compact(index, s, obj, static_cast<std::uint8_t>(*compact), cat, f, node);
        if (sub_number && *sub_number != 0 && *sub_number != *compact + 1) {
            f.warning(sub_number_entry->line,
                      fmt::format("[{}] SubNumber={} does not match CompactSubObj={}", s.name,
                                  *sub_number, *compact));
        }
    } else {
        for (auto* named : {&cat.values, &cat.names}) {
            if (auto it = named->find(index); it != named->end()) {
                f.warning(
                    it->second->line,
                    fmt::format("[{}] is only used with CompactSubObj; ignored", it->second->name));
            }
        }
        if (!has_sub_sections) {
            f.warning(s.line, fmt::format("[{}] is a {} without sub-object sections", s.name,
                                          to_string(obj.code)));
        }
        if (!sub_number) {
            if (sub_number_entry == nullptr) {
                f.warning(s.line, fmt::format("[{}] has no SubNumber", s.name));
            }
        } else {
            const std::size_t found = has_sub_sections ? subs_it->second.size() : 0;
            if (*sub_number != found) {
                f.warning(sub_number_entry->line,
                          fmt::format("[{}] SubNumber={} but {} sub-object sections are given",
                                      s.name, *sub_number, found));
            }
        }
    }
    if (has_sub_sections) {
        if (compact && *compact > 0) {
            f.warning(subs_it->second.begin()->second->line,
                      fmt::format("[{}] has both CompactSubObj and sub-object sections; the "
                                  "sections replace the generated sub-objects",
                                  s.name));
        }
        for (auto& [si, sec] : subs_it->second) {
            SubObject sub;
            sub.subindex = si;
            if (Entry* ot = sec->find("ObjectType"); ot != nullptr && !ot->value.empty() &&
                                                     parse_integer(ot->value, std::nullopt)
                                                             .value.value_or(Integer{false, 7})
                                                             .magnitude != 7) {
                f.warning(ot->line, fmt::format("[{}] ObjectType={}: sub-objects are VAR (0x7); "
                                                "read as VAR",
                                                sec->name, ot->value));
            }
            if (parse_sub(*sec, sub, true, std::nullopt, f, node)) {
                obj.subs[si] = std::move(sub);
            }
            report_unused(*sec, f);
        }
    }
    if (const SubObject* s0 = obj.find(0); s0 == nullptr) {
        if (!obj.subs.empty()) {
            f.warning(s.line,
                      fmt::format("[{}] has no sub-index 0 (highest sub-index supported)", s.name));
        }
    } else if (static_cast<std::uint16_t>(s0->type) != kUnsigned8) {
        f.warning(s.line, fmt::format("[{}] sub-index 0 is {}, CiA 301 makes it UNSIGNED8", s.name,
                                      to_string(s0->type)));
    }
    report_unused(s, f);
    od.insert(std::move(obj));
}

} // namespace

void parse_objects(IniFile& ini, DeviceDescription& desc, Findings& f) {
    Catalog cat;
    catalog_sections(ini, cat, f);
    parse_lists(ini, cat, f);
    for (auto& [index, line] : cat.listed) {
        if (cat.objects.count(index) == 0) {
            f.error(line, fmt::format("object 0x{:04X} is listed but has no [{:04X}] section",
                                      index, index));
        }
    }
    for (auto& [index, sec] : cat.objects) {
        if (cat.listed.count(index) == 0) {
            f.warning(sec->line, fmt::format("object [{}] is not listed in [MandatoryObjects], "
                                             "[OptionalObjects] or [ManufacturerObjects]; loaded "
                                             "anyway",
                                             sec->name));
        }
        if (index == 0) {
            f.error(sec->line,
                    fmt::format("object index 0 in [{}] is not valid; skipped", sec->name));
            continue;
        }
        parse_object(index, *sec, cat, desc.od, f, desc.node_id);
    }
    for (auto& [index, subs] : cat.subs) {
        if (cat.objects.count(index) == 0) {
            for (auto& [si, sec] : subs) {
                f.error(sec->line, fmt::format("[{}] has no object section [{:04X}]; ignored",
                                               sec->name, index));
            }
        }
    }
    for (auto* named : {&cat.values, &cat.names}) {
        for (auto& [index, sec] : *named) {
            if (cat.objects.count(index) == 0) {
                f.error(sec->line, fmt::format("[{}] has no object section [{:04X}]; ignored",
                                               sec->name, index));
            }
        }
    }
}

} // namespace codrive::eds