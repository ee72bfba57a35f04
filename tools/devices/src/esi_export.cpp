// SPDX-License-Identifier: Apache-2.0
// A drive profile's object dictionary as an EtherCAT slave information file (ETG.2000 ESI XML).
#include <codrive/devices/device_files.hpp>
#include <codrive/ethercat/esi.hpp>

#include <fmt/format.h>
#include <pugixml.hpp>

#include <algorithm>
#include <optional>
#include <sstream>
#include <vector>

namespace codrive::devices {

namespace {

std::string hex_text(std::uint32_t v, int digits) {
    return fmt::format("#x{:0{}X}", v, digits);
}

std::size_t bit_size(const SubObject& s) {
    const std::size_t bytes = data_type_size(s.type);
    if (s.type == DataType::Boolean) {
        return 1;
    }
    return 8 * (bytes != 0 ? bytes : s.value.size());
}

// ETG.2000 §5.4.3 (Table 42) type names: the base types from the ESI reader's table (one truth
// for both directions), strings and octet strings sized by the value.
std::string esi_type(const SubObject& s) {
    if (const std::string_view base = ethercat::esi_base_type_name(s.type); !base.empty()) {
        return std::string(base);
    }
    switch (s.type) {
    case DataType::VisibleString:
        return fmt::format("STRING({})", s.value.size());
    case DataType::OctetString:
        return fmt::format("ARRAY [0..{}] OF BYTE", s.value.size() == 0 ? 0 : s.value.size() - 1);
    default:
        return std::string(to_string(s.type));
    }
}

// ETG.2000 Flags/Access is ro, rw or wo; the PDO direction goes to Flags/PdoMapping.
void add_flags(pugi::xml_node parent, const SubObject& s) {
    pugi::xml_node flags = parent.append_child("Flags");
    const char* access = "rw";
    if (s.access == Access::Ro || s.access == Access::Const) {
        access = "ro";
    } else if (s.access == Access::Wo) {
        access = "wo";
    }
    flags.append_child("Access").text().set(access);
    const bool t = s.mappable(PdoDir::Tpdo);
    const bool r = s.mappable(PdoDir::Rpdo);
    if (t || r) {
        flags.append_child("PdoMapping").text().set(t && r ? "RT" : (t ? "T" : "R"));
    }
}

// MinValue and MaxValue are ETG.2000 HexDecValues: "#x" and hex digits, or a signed decimal
// (not the "0x" of a CiA 306 EDS). Written for integer types only: a REAL has no such form.
std::optional<std::string> hex_dec_text(const Value& v) {
    if (is_signed_integer(v.type()) && v.as_int()) {
        return std::to_string(*v.as_int());
    }
    if (is_unsigned_integer(v.type()) && v.as_uint()) {
        return fmt::format("#x{:0{}X}", *v.as_uint(), 2 * v.size());
    }
    return std::nullopt;
}

// DefaultData is the value's little-endian byte image in hex (ETG.2000 §5.4.3.4 hexBinary).
void add_info(pugi::xml_node parent, const SubObject& s) {
    pugi::xml_node info = parent.append_child("Info");
    const auto low = s.low_limit ? hex_dec_text(*s.low_limit) : std::nullopt;
    const auto high = s.high_limit ? hex_dec_text(*s.high_limit) : std::nullopt;
    if (low && high) {
        info.append_child("MinValue").text().set(low->c_str());
        info.append_child("MaxValue").text().set(high->c_str());
    }
    std::string data;
    for (const std::uint8_t b : s.value.bytes()) {
        data += fmt::format("{:02X}", b);
    }
    info.append_child("DefaultData").text().set(data.c_str());
}

bool is_complex(const Object& o) {
    return o.code == ObjectCode::Array || o.code == ObjectCode::Record ||
           o.code == ObjectCode::Defstruct;
}

// One structured type per ARRAY/RECORD: sub-index 0 at bit 0, the entries from bit 16 on (the
// layout ETG.2000 examples use: sub 0 padded to a word).
std::size_t sub_offset(std::uint8_t si, std::size_t offset) {
    return si != 0 && offset < 16 ? 16 : offset;
}

std::size_t record_bits(const Object& obj) {
    std::size_t offset = 0;
    for (const auto& [si, sub] : obj.subs) {
        offset = sub_offset(si, offset) + bit_size(sub);
    }
    return offset;
}

void add_data_types(pugi::xml_node types, const ObjectDictionary& od) {
    std::vector<std::pair<std::string, std::size_t>> base;
    const auto note = [&base](const SubObject& s) {
        const std::string name = esi_type(s);
        for (const auto& b : base) {
            if (b.first == name) {
                return;
            }
        }
        base.emplace_back(name, bit_size(s));
    };
    for (const auto& [index, obj] : od.objects()) {
        for (const auto& [si, sub] : obj.subs) {
            note(sub);
        }
    }
    for (const auto& [name, bits] : base) {
        pugi::xml_node t = types.append_child("DataType");
        t.append_child("Name").text().set(name.c_str());
        t.append_child("BitSize").text().set(static_cast<unsigned>(bits));
    }
    for (const auto& [index, obj] : od.objects()) {
        if (!is_complex(obj)) {
            continue;
        }
        pugi::xml_node t = types.append_child("DataType");
        t.append_child("Name").text().set(fmt::format("DT{:04X}", index).c_str());
        t.append_child("BitSize").text().set(static_cast<unsigned>(record_bits(obj)));
        std::size_t offset = 0;
        for (const auto& [si, sub] : obj.subs) {
            offset = sub_offset(si, offset);
            pugi::xml_node item = t.append_child("SubItem");
            item.append_child("SubIdx").text().set(static_cast<unsigned>(si));
            item.append_child("Name").text().set(sub.name.c_str());
            item.append_child("Type").text().set(esi_type(sub).c_str());
            item.append_child("BitSize").text().set(static_cast<unsigned>(bit_size(sub)));
            item.append_child("BitOffs").text().set(static_cast<unsigned>(offset));
            add_flags(item, sub);
            offset += bit_size(sub);
        }
    }
}

void add_objects(pugi::xml_node objects, const ObjectDictionary& od) {
    for (const auto& [index, obj] : od.objects()) {
        pugi::xml_node o = objects.append_child("Object");
        o.append_child("Index").text().set(hex_text(index, 4).c_str());
        o.append_child("Name").text().set(obj.name.c_str());
        if (!is_complex(obj)) {
            const SubObject& s = obj.subs.begin()->second;
            o.append_child("Type").text().set(esi_type(s).c_str());
            o.append_child("BitSize").text().set(static_cast<unsigned>(bit_size(s)));
            add_info(o, s);
            add_flags(o, s);
            continue;
        }
        o.append_child("Type").text().set(fmt::format("DT{:04X}", index).c_str());
        o.append_child("BitSize").text().set(static_cast<unsigned>(record_bits(obj)));
        pugi::xml_node info = o.append_child("Info");
        for (const auto& [si, sub] : obj.subs) {
            pugi::xml_node item = info.append_child("SubItem");
            item.append_child("Name").text().set(sub.name.c_str());
            add_info(item, sub);
        }
    }
}

struct PdoSpec {
    std::uint16_t index = 0;
    std::vector<std::uint32_t> entries; ///< index << 16 | sub << 8 | bits
    bool assigned = false;
    bool fixed = false;
};

// ETG.2000 RxPdo/TxPdo: every mapping object of the dictionary (first..last) with its default
// entries, the same defaults its Dictionary object states; Sm for the maps the sync manager's
// assignment object (1C12h/1C13h, ETG.1000.6 §5.6.7.4) assigns by default, Fixed for a map
// whose entry count cannot be written.
std::vector<PdoSpec> dictionary_pdos(const ObjectDictionary& od, std::uint16_t first,
                                     std::uint16_t last, std::uint16_t assignment) {
    std::vector<std::uint16_t> assigned;
    const auto count = od.get<std::uint8_t>(assignment, 0).value_or(0);
    for (unsigned i = 1; i <= count; ++i) {
        assigned.push_back(
            od.get<std::uint16_t>(assignment, static_cast<std::uint8_t>(i)).value_or(0));
    }
    std::vector<PdoSpec> out;
    for (const auto& [index, obj] : od.objects()) {
        if (index < first || index > last) {
            continue;
        }
        PdoSpec pdo;
        pdo.index = index;
        pdo.assigned = std::find(assigned.begin(), assigned.end(), index) != assigned.end();
        const SubObject* n = od.find(index, 0);
        pdo.fixed = n == nullptr || !writable(n->access);
        const auto entries = od.get<std::uint8_t>(index, 0).value_or(0);
        for (unsigned i = 1; i <= entries; ++i) {
            pdo.entries.push_back(
                od.get<std::uint32_t>(index, static_cast<std::uint8_t>(i)).value_or(0));
        }
        out.push_back(std::move(pdo));
    }
    return out;
}

void add_pdo(pugi::xml_node device, const char* element, const PdoSpec& pdo, unsigned sm,
             const ObjectDictionary& od) {
    pugi::xml_node x = device.append_child(element);
    x.append_attribute("Fixed").set_value(pdo.fixed ? "1" : "0");
    if (pdo.assigned) {
        x.append_attribute("Sm").set_value(sm);
    }
    x.append_child("Index").text().set(hex_text(pdo.index, 4).c_str());
    x.append_child("Name").text().set(
        fmt::format("{} {:04X}h", sm == 2 ? "RxPDO" : "TxPDO", pdo.index).c_str());
    for (const std::uint32_t e : pdo.entries) {
        const auto index = static_cast<std::uint16_t>(e >> 16);
        const auto sub = static_cast<std::uint8_t>(e >> 8);
        pugi::xml_node entry = x.append_child("Entry");
        entry.append_child("Index").text().set(hex_text(index, 4).c_str());
        entry.append_child("SubIndex").text().set(static_cast<unsigned>(sub));
        entry.append_child("BitLen").text().set(static_cast<unsigned>(e & 0xFF));
        if (const SubObject* s = od.find(index, sub); s != nullptr) {
            entry.append_child("Name").text().set(s->name.c_str());
            entry.append_child("DataType").text().set(esi_type(*s).c_str());
        }
    }
}

void add_sm(pugi::xml_node device, const char* kind, unsigned address, unsigned size,
            unsigned control) {
    pugi::xml_node sm = device.append_child("Sm");
    if (size != 0) {
        sm.append_attribute("DefaultSize").set_value(size);
    }
    sm.append_attribute("StartAddress").set_value(hex_text(address, 4).c_str());
    sm.append_attribute("ControlByte").set_value(hex_text(control, 2).c_str());
    sm.append_attribute("Enable").set_value("1");
    sm.text().set(kind);
}

} // namespace

std::string export_esi(const drives::Profile& p, unsigned axes, std::string_view vendor_name) {
    const DeviceDescription d = profile_description(p, axes, vendor_name, Stack::Coe);
    pugi::xml_document doc;
    pugi::xml_node decl = doc.append_child(pugi::node_declaration);
    decl.append_attribute("version").set_value("1.0");
    decl.append_attribute("encoding").set_value("UTF-8");
    doc.append_child(pugi::node_comment)
        .set_value(fmt::format(" {} generated by `codrive esi export` from codrive's profile "
                               "(devices/regenerate.sh); do not edit ",
                               p.title)
                       .c_str());
    pugi::xml_node info = doc.append_child("EtherCATInfo");
    info.append_attribute("Version").set_value("1.6");
    pugi::xml_node vendor = info.append_child("Vendor");
    vendor.append_child("Id").text().set(hex_text(d.device_info.vendor_number, 8).c_str());
    vendor.append_child("Name").text().set(std::string(vendor_name).c_str());

    pugi::xml_node desc = info.append_child("Descriptions");
    pugi::xml_node group = desc.append_child("Groups").append_child("Group");
    group.append_child("Type").text().set(std::string(p.name).c_str());
    group.append_child("Name").text().set(std::string(p.title).c_str());

    pugi::xml_node device = desc.append_child("Devices").append_child("Device");
    device.append_attribute("Physics").set_value("YY");
    pugi::xml_node type = device.append_child("Type");
    type.append_attribute("ProductCode")
        .set_value(hex_text(d.device_info.product_number, 8).c_str());
    type.append_attribute("RevisionNo")
        .set_value(hex_text(d.device_info.revision_number, 8).c_str());
    type.text().set(std::string(p.name).c_str());
    device.append_child("Name").text().set(std::string(p.title).c_str());
    device.append_child("GroupType").text().set(std::string(p.name).c_str());

    pugi::xml_node profile = device.append_child("Profile");
    profile.append_child("ProfileNo").text().set(402); // CiA 402 / ETG.6010 drive profile
    profile.append_child("AddInfo").text().set(axes);
    pugi::xml_node dict = profile.append_child("Dictionary");
    add_data_types(dict.append_child("DataTypes"), d.od);
    add_objects(dict.append_child("Objects"), d.od);

    for (const char* f : {"Outputs", "Inputs", "MBoxState"}) {
        device.append_child("Fmmu").text().set(f);
    }
    // The sync managers of codrive's simulated slave (sim/src/ecat_drive.cpp): 128-byte
    // mailboxes at 1000h/1080h, process data from 1100h/1180h (ETG.1000.4 Table 59 control bytes).
    add_sm(device, "MBoxOut", 0x1000, 128, 0x26);
    add_sm(device, "MBoxIn", 0x1080, 128, 0x22);
    add_sm(device, "Outputs", 0x1100, 0, 0x64);
    add_sm(device, "Inputs", 0x1180, 0, 0x20);

    for (const PdoSpec& pdo : dictionary_pdos(d.od, 0x1600, 0x17FF, 0x1C12)) {
        add_pdo(device, "RxPdo", pdo, 2, d.od);
    }
    for (const PdoSpec& pdo : dictionary_pdos(d.od, 0x1A00, 0x1BFF, 0x1C13)) {
        add_pdo(device, "TxPdo", pdo, 3, d.od);
    }

    pugi::xml_node mailbox = device.append_child("Mailbox");
    mailbox.append_attribute("DataLinkLayer").set_value("true");
    pugi::xml_node coe = mailbox.append_child("CoE");
    coe.append_attribute("SdoInfo").set_value("true");
    coe.append_attribute("PdoAssign").set_value("true");
    coe.append_attribute("PdoConfig").set_value("true");
    if (p.name == "akd2g") {
        // The AKD2G takes its parameter file and firmware over FoE (manual §2.3.3.4).
        mailbox.append_child("FoE");
    }

    std::ostringstream out;
    doc.save(out, "  ", pugi::format_default, pugi::encoding_utf8);
    return out.str();
}

} // namespace codrive::devices
