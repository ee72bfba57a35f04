// SPDX-License-Identifier: Apache-2.0
// EDS/DCF section catalog and object lists ([MandatoryObjects], [OptionalObjects], ...).
#include "eds_internal.hpp"
#include "hex_digit.hpp"

#include <fmt/format.h>

#include <array>
#include <cctype>

namespace codrive::eds {

namespace {

std::optional<std::uint32_t> hex_number(std::string_view s, std::size_t max_digits) {
    if (s.empty() || s.size() > max_digits) {
        return std::nullopt;
    }
    std::uint32_t v = 0;
    for (char c : s) {
        const int d = codrive::detail::hex_digit(c);
        if (d < 0) {
            return std::nullopt;
        }
        v = v * 16 + static_cast<std::uint32_t>(d);
    }
    return v;
}

bool ends_with(std::string_view s, std::string_view suffix) {
    return s.size() > suffix.size() && s.substr(s.size() - suffix.size()) == suffix;
}

} // namespace

constexpr std::array<std::string_view, 9> kHeaderSections = {
    "fileinfo",           "deviceinfo",      "dummyusage",          "comments",
    "mandatoryobjects",   "optionalobjects", "manufacturerobjects", "devicecomissioning",
    "devicecommissioning"};

// Sorts every section into the catalog by its name (names are case-insensitive; indexes and
// sub-indexes are hex without 0x: [1018], [1018sub4], [1F81Value], [1F81Name]).
void catalog_sections(IniFile& ini, Catalog& cat, Findings& f) {
    for (auto& s : ini.sections) {
        const std::string& n = s.lower;
        bool known = false;
        for (auto h : kHeaderSections) {
            known = known || n == h;
        }
        if (known) {
            continue;
        }
        if (auto idx = hex_number(n, 4)) {
            cat.objects[static_cast<std::uint16_t>(*idx)] = &s;
            continue;
        }
        const std::size_t sub_pos = n.find("sub");
        if (sub_pos != std::string::npos) {
            auto idx = hex_number(std::string_view(n).substr(0, sub_pos), 4);
            auto si = hex_number(std::string_view(n).substr(sub_pos + 3), 2);
            if (idx && si) {
                auto& slot =
                    cat.subs[static_cast<std::uint16_t>(*idx)][static_cast<std::uint8_t>(*si)];
                if (slot != nullptr) {
                    f.warning(s.line, fmt::format("[{}] defines sub-index {} of 0x{:04X} again "
                                                  "(first in [{}] at line {}); ignored",
                                                  s.name, *si, *idx, slot->name, slot->line));
                } else {
                    slot = &s;
                }
                continue;
            }
        }
        bool handled = false;
        for (auto [suffix, map] : {std::pair{std::string_view("value"), &cat.values},
                                   std::pair{std::string_view("name"), &cat.names},
                                   std::pair{std::string_view("denotation"), &cat.names}}) {
            if (!ends_with(n, suffix)) {
                continue;
            }
            auto idx = hex_number(std::string_view(n).substr(0, n.size() - suffix.size()), 4);
            if (!idx) {
                continue;
            }
            handled = true;
            if (suffix == "denotation") {
                f.info(s.line, fmt::format("[{}] (DCF denotations) is not used by codrive; "
                                           "ignored",
                                           s.name));
            } else {
                (*map)[static_cast<std::uint16_t>(*idx)] = &s;
            }
            break;
        }
        if (!handled) {
            f.info(s.line, fmt::format("section [{}] is not used by codrive; ignored", s.name));
        }
    }
}

namespace {

// Object indexes in the lists are hex with 0x (CiA 306); vendors drop the prefix, and
// since every index in an EDS is hex, that is what they mean.
std::optional<std::uint16_t> list_index(const Section& s, Entry& e, const std::string& what,
                                        Findings& f) {
    const std::string_view v = number_text(s, e, f);
    if (v.size() > 2 && v[0] == '0' && (v[1] == 'x' || v[1] == 'X')) {
        auto n = read_uint(v, 0xFFFF, e.line, what, f);
        return n ? std::optional<std::uint16_t>(static_cast<std::uint16_t>(*n)) : std::nullopt;
    }
    if (auto h = hex_number(v, 4)) {
        f.warning(e.line,
                  fmt::format("{} '{}' has no 0x prefix; read as hex 0x{:04X}", what, v, *h));
        return static_cast<std::uint16_t>(*h);
    }
    f.error(e.line, fmt::format("{} '{}' is not an object index", what, v.substr(0, 40)));
    return std::nullopt;
}

} // namespace

void parse_lists(IniFile& ini, Catalog& cat, Findings& f) {
    for (auto list : {"MandatoryObjects", "OptionalObjects", "ManufacturerObjects"}) {
        Section* s = ini.find(to_lower(list));
        if (s == nullptr) {
            if (std::string_view(list) == "MandatoryObjects") {
                f.warning(0, "no [MandatoryObjects] section (CiA 306 requires one)");
            }
            continue;
        }
        Entry* count_entry = s->find("SupportedObjects");
        const auto count = get_uint(*s, "SupportedObjects", 0xFFFF, f);
        if (count_entry == nullptr) {
            f.warning(s->line, fmt::format("[{}] has no SupportedObjects count", s->name));
        }
        std::size_t listed = 0;
        for (auto& e : s->entries) {
            if (e.used) {
                continue;
            }
            IntegerText key = parse_integer(e.key, std::nullopt);
            if (!key.value || key.uses_node_id || key.value->negative ||
                key.value->magnitude == 0) {
                continue; // reported as an unused key below
            }
            e.used = true;
            ++listed;
            if (count && key.value->magnitude > *count) {
                f.warning(e.line, fmt::format("[{}] entry {} is beyond SupportedObjects={}; "
                                              "loaded anyway",
                                              s->name, e.key, *count));
            }
            auto idx = list_index(*s, e, fmt::format("[{}] {}", s->name, e.key), f);
            if (!idx) {
                continue;
            }
            auto [it, fresh] = cat.listed.emplace(*idx, e.line);
            if (!fresh) {
                f.warning(e.line, fmt::format("[{}] lists object 0x{:04X} again (first at line {})",
                                              s->name, *idx, it->second));
            }
        }
        if (count && *count != listed) {
            f.warning(count_entry->line,
                      fmt::format("[{}] SupportedObjects={} but {} objects are listed", s->name,
                                  *count, listed));
        }
        report_unused(*s, f);
    }
}

} // namespace codrive::eds
