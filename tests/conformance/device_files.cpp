// SPDX-License-Identifier: Apache-2.0
// The fourth way a fact is checked: against the drive's device description files in devices/
// (EDS read with codrive's CiA 306 parser, ESI read with pugixml as ETG.2000 describes it).
#include "conformance.hpp"

#include <fmt/format.h>
#include <pugixml.hpp>

#include <cstdlib>
#include <map>
#include <string_view>
#include <utility>

namespace codrive::conformance {

/// The parsed ESI: the document and its Object and DataType elements by index and name.
struct DeviceFiles::Esi {
    pugi::xml_document doc;
    std::map<std::uint16_t, pugi::xml_node> objects;
    std::map<std::string, pugi::xml_node, std::less<>> data_types;
};

namespace {

/// What a file says about one sub-object, in the terms of a Fact.
struct Described {
    std::optional<DataType> type;
    bool readable = true;
    bool writable = false;
    std::optional<std::int64_t> value;
    std::optional<std::int64_t> low;
    std::optional<std::int64_t> high;
};

const char* access_text(bool readable, bool writable) {
    if (!writable) {
        return "ro";
    }
    return readable ? "rw" : "wo";
}

/// The comparisons a fact states: data type, access class, default, and the range where the
/// manual narrows the type's.
void compare(const std::string& what, const Fact& f, const Described& d,
             std::vector<std::string>& out) {
    if (d.type && *d.type != f.type) {
        out.push_back(fmt::format("{}: data type {}, manual {}", what, to_string(*d.type),
                                  to_string(f.type)));
    }
    const bool want_rw = f.access == Acc::Rw;
    if ((d.writable && d.readable) != want_rw || (!want_rw && d.writable)) {
        out.push_back(fmt::format("{}: access {}, manual {}", what,
                                  access_text(d.readable, d.writable), want_rw ? "rw" : "ro"));
    }
    if (f.value && d.value != f.value) {
        out.push_back(fmt::format("{}: default {}, manual {}", what,
                                  d.value ? std::to_string(*d.value) : std::string("none"),
                                  *f.value));
    }
    const auto [type_low, type_high] = type_range(f.type);
    const std::int64_t low = f.low.value_or(type_low);
    const std::int64_t high = f.high.value_or(type_high);
    if (low == type_low && high == type_high) {
        return; // the manual does not narrow the type's range
    }
    if (!d.low && !d.high) {
        out.push_back(fmt::format("{}: no limits, manual {}..{}", what, low, high));
    } else if (d.low.value_or(type_low) != low || d.high.value_or(type_high) != high) {
        out.push_back(fmt::format("{}: limits {}..{}, manual {}..{}", what,
                                  d.low.value_or(type_low), d.high.value_or(type_high), low, high));
    }
}

std::optional<std::int64_t> int_of(const std::optional<Value>& v) {
    return v ? v->as_int() : std::nullopt;
}

void check_eds(const std::string& what, const DeviceDescription& eds, const Fact& f,
               std::vector<std::string>& out) {
    const SubObject* s = eds.od.find(f.index, f.sub);
    if (f.access == Acc::Absent) {
        if (s != nullptr) {
            out.push_back(fmt::format("{}: the file lists it (manual: no such object)", what));
        }
        return;
    }
    if (s == nullptr) {
        out.push_back(eds.od.find(f.index) != nullptr
                          ? fmt::format("{}: the object has no sub-index {:02X}h", what, f.sub)
                          : fmt::format("{}: the file does not list the object", what));
        return;
    }
    compare(what, f,
            Described{s->type, readable(s->access), writable(s->access), int_of(s->default_value),
                      int_of(s->low_limit), int_of(s->high_limit)},
            out);
}

/// ETG.2000 base data type names (the CoE data types of ETG.1000.6 Table 64 by their IEC 61131
/// names) for the CiA 301 integer types a fact can have. Read independently of the exporter
/// (tools/devices) so that a wrong name written there shows here.
std::optional<DataType> esi_base_type(std::string_view name) {
    static const std::map<std::string_view, DataType> kTypes{
        {"BOOL", DataType::Boolean},      {"SINT", DataType::Integer8},
        {"INT", DataType::Integer16},     {"INT24", DataType::Integer24},
        {"DINT", DataType::Integer32},    {"LINT", DataType::Integer64},
        {"USINT", DataType::Unsigned8},   {"BYTE", DataType::Unsigned8},
        {"UINT", DataType::Unsigned16},   {"WORD", DataType::Unsigned16},
        {"UINT24", DataType::Unsigned24}, {"UDINT", DataType::Unsigned32},
        {"DWORD", DataType::Unsigned32},  {"ULINT", DataType::Unsigned64},
        {"REAL", DataType::Real32},       {"LREAL", DataType::Real64},
    };
    const auto it = kTypes.find(name);
    return it == kTypes.end() ? std::nullopt : std::optional<DataType>(it->second);
}

/// An ETG.2000 HexDecValue ("#x" and hex digits, or a decimal with optional sign).
std::optional<std::int64_t> hex_dec_value(std::string_view text) {
    const bool hex = text.starts_with("#x");
    const std::string digits(hex ? text.substr(2) : text);
    if (digits.empty()) {
        return std::nullopt;
    }
    char* end = nullptr;
    const long long v = std::strtoll(digits.c_str(), &end, hex ? 16 : 10);
    if (end == nullptr || *end != '\0' || (hex && (digits[0] == '-' || digits[0] == '+'))) {
        return std::nullopt;
    }
    return v;
}

/// DefaultData (hexBinary: the value's little-endian bytes) of an integer type; nullopt if the
/// text is not whole hex octets of the type's size.
std::optional<std::int64_t> default_data(std::string_view text, DataType type) {
    if (text.size() != 2 * data_type_size(type)) {
        return std::nullopt;
    }
    std::vector<std::uint8_t> bytes;
    for (std::size_t i = 0; i < text.size(); i += 2) {
        const std::string octet(text.substr(i, 2));
        char* end = nullptr;
        const unsigned long b = std::strtoul(octet.c_str(), &end, 16);
        if (*end != '\0' || octet[0] == '-' || octet[0] == '+') {
            return std::nullopt;
        }
        bytes.push_back(static_cast<std::uint8_t>(b));
    }
    return decode(type, bytes);
}

/// Type, BitSize, Flags/Access and Info (DefaultData, MinValue, MaxValue) of one sub-object.
Described describe_esi(const std::string& what, pugi::xml_node typed, pugi::xml_node flags,
                       pugi::xml_node info, std::vector<std::string>& out) {
    Described d;
    const std::string type_name = typed.child_value("Type");
    d.type = esi_base_type(type_name);
    if (!d.type) {
        out.push_back(fmt::format("{}: type `{}` is not an ETG.2000 base type", what, type_name));
    } else if (std::string_view bits = typed.child_value("BitSize");
               bits != std::to_string(data_type_size(*d.type) * 8)) {
        out.push_back(fmt::format("{}: BitSize {}, {} has {}", what, bits, type_name,
                                  data_type_size(*d.type) * 8));
    }
    const std::string_view access = flags.child_value("Access");
    if (access != "ro" && access != "rw" && access != "wo") {
        out.push_back(fmt::format("{}: Flags/Access `{}` is none of ro, rw, wo", what, access));
    }
    d.readable = access != "wo";
    d.writable = access == "rw" || access == "wo";
    if (const pugi::xml_node data = info.child("DefaultData"); data && d.type) {
        d.value = default_data(data.text().get(), *d.type);
        if (!d.value) {
            out.push_back(fmt::format("{}: DefaultData `{}` is not {} hex octets", what,
                                      data.text().get(), data_type_size(*d.type)));
        }
    }
    for (const auto& [element, target] :
         {std::pair{"MinValue", &d.low}, std::pair{"MaxValue", &d.high}}) {
        if (const pugi::xml_node limit = info.child(element); limit) {
            *target = hex_dec_value(limit.text().get());
            if (!*target) {
                out.push_back(fmt::format("{}: {} `{}` is not an ETG.2000 HexDecValue (#x… or "
                                          "decimal)",
                                          what, element, limit.text().get()));
            }
        }
    }
    return d;
}

/// The Object/Info/SubItem for a DataType SubItem: ETG.2000 names it by the SubItem's Name;
/// the n-th DataType SubItem of a name is described by the n-th Info SubItem of that name.
pugi::xml_node info_sub_item(pugi::xml_node object, pugi::xml_node type, pugi::xml_node item) {
    const std::string_view name = item.child_value("Name");
    unsigned ordinal = 0;
    for (pugi::xml_node i : type.children("SubItem")) {
        if (i == item) {
            break;
        }
        ordinal += name == i.child_value("Name") ? 1U : 0U;
    }
    for (pugi::xml_node i : object.child("Info").children("SubItem")) {
        if (name == i.child_value("Name") && ordinal-- == 0) {
            return i;
        }
    }
    return {};
}

void check_esi(const std::string& what, const DeviceFiles::Esi& esi, const Fact& f,
               std::vector<std::string>& out) {
    const auto o = esi.objects.find(f.index);
    pugi::xml_node object = o == esi.objects.end() ? pugi::xml_node{} : o->second;
    const auto t = object ? esi.data_types.find(object.child_value("Type")) : esi.data_types.end();
    const pugi::xml_node type = t == esi.data_types.end() ? pugi::xml_node{} : t->second;
    const bool structured = type && type.child("SubItem");
    pugi::xml_node item;
    if (structured) {
        for (pugi::xml_node i : type.children("SubItem")) {
            if (std::string_view(i.child_value("SubIdx")) == std::to_string(f.sub)) {
                item = i;
            }
        }
    }
    const bool present = object && (structured ? static_cast<bool>(item) : f.sub == 0);
    if (f.access == Acc::Absent) {
        if (present) {
            out.push_back(fmt::format("{}: the file lists it (manual: no such object)", what));
        }
        return;
    }
    if (!present) {
        out.push_back(object ? fmt::format("{}: the object has no sub-index {:02X}h", what, f.sub)
                             : fmt::format("{}: the file does not list the object", what));
        return;
    }
    if (!structured) {
        compare(what, f,
                describe_esi(what, object, object.child("Flags"), object.child("Info"), out), out);
        return;
    }
    const pugi::xml_node info = info_sub_item(object, type, item);
    if (!info) {
        out.push_back(fmt::format("{}: Object/Info has no SubItem named `{}`", what,
                                  item.child_value("Name")));
    }
    // Access is given with the DataType's SubItem; an object's own SubItem Flags are the fallback.
    const pugi::xml_node flags = item.child("Flags") ? item.child("Flags") : info.child("Flags");
    compare(what, f, describe_esi(what, item, flags, info.child("Info"), out), out);
}

std::string display_name(const std::string& path) {
    const std::string_view root = CODRIVE_SOURCE_DIR "/";
    return path.starts_with(root) ? path.substr(root.size()) : path;
}

} // namespace

DeviceFiles::DeviceFiles(std::string eds_path, std::string esi_path)
    : eds_name_(display_name(eds_path)), esi_name_(display_name(esi_path)) {
    if (!eds_path.empty()) {
        auto desc = load_eds(eds_path);
        if (!desc) {
            eds_error_ = desc.error().message();
        } else if (desc->has_errors()) {
            for (const EdsFinding& finding : desc->findings) {
                if (finding.severity == EdsSeverity::Error) {
                    eds_error_ += format_finding(finding) + "; ";
                }
            }
        } else {
            eds_ = std::make_unique<DeviceDescription>(std::move(*desc));
        }
    }
    if (!esi_path.empty()) {
        auto esi = std::make_unique<Esi>();
        const pugi::xml_parse_result r = esi->doc.load_file(esi_path.c_str());
        const pugi::xml_node dict = esi->doc.child("EtherCATInfo")
                                        .child("Descriptions")
                                        .child("Devices")
                                        .child("Device")
                                        .child("Profile")
                                        .child("Dictionary");
        if (!r) {
            esi_error_ = r.description();
        } else if (!dict) {
            esi_error_ = "no EtherCATInfo/Descriptions/Devices/Device/Profile/Dictionary";
        } else {
            for (pugi::xml_node t : dict.child("DataTypes").children("DataType")) {
                esi->data_types.emplace(t.child_value("Name"), t);
            }
            for (pugi::xml_node o : dict.child("Objects").children("Object")) {
                const auto index = hex_dec_value(o.child_value("Index"));
                if (!index || *index < 0 || *index > 0xFFFF) {
                    esi_error_ += fmt::format("Object Index `{}` is not a #x index; ",
                                              o.child_value("Index"));
                    continue;
                }
                esi->objects.emplace(static_cast<std::uint16_t>(*index), o);
            }
            if (esi_error_.empty()) {
                esi_ = std::move(esi);
            }
        }
    }
}

DeviceFiles::~DeviceFiles() = default;

DeviceFiles DeviceFiles::of(std::string_view stem) {
    const std::string base = std::string(CODRIVE_SOURCE_DIR) + "/devices/" + std::string(stem);
    return DeviceFiles(base + ".eds", base + ".xml");
}

bool DeviceFiles::applies(const Fact& f) const {
    return (!eds_name_.empty() && f.bus != Bus::Ecat) || (!esi_name_.empty() && f.bus != Bus::Can);
}

std::vector<std::string> DeviceFiles::check(const std::string& what, const Fact& f) const {
    std::vector<std::string> out;
    if (!eds_name_.empty() && f.bus != Bus::Ecat) {
        const std::string where = what + " " + eds_name_;
        if (eds_) {
            check_eds(where, *eds_, f, out);
        } else {
            out.push_back(fmt::format("{}: cannot be read: {}", where, eds_error_));
        }
    }
    if (!esi_name_.empty() && f.bus != Bus::Can) {
        const std::string where = what + " " + esi_name_;
        if (esi_) {
            check_esi(where, *esi_, f, out);
        } else {
            out.push_back(fmt::format("{}: cannot be read: {}", where, esi_error_));
        }
    }
    return out;
}

} // namespace codrive::conformance
