// SPDX-License-Identifier: Apache-2.0
// Reads an ESI XML file (ETG.2000) with pugixml into EsiFile, every finding a `file:line:`
// sentence.
#include <codrive/ethercat/esi.hpp>

#include <fmt/format.h>
#include <pugixml.hpp>

#include <algorithm>
#include <charconv>
#include <cstring>
#include <fstream>
#include <map>
#include <sstream>

namespace codrive::ethercat {
namespace {

// A finding in the file: the first one ends the read (the file is the vendor's, not ours to
// guess at).
struct EsiError {
    std::string sentence;
};

class Reader {
public:
    Reader(std::string_view text, const std::string& file) : text_(text), file_(file) {
        for (std::size_t i = 0; i < text_.size(); ++i) {
            if (text_[i] == '\n') {
                newlines_.push_back(i);
            }
        }
    }

    EsiFile read(const pugi::xml_document& doc) {
        EsiFile out;
        out.file = file_;
        const pugi::xml_node root = doc.child("EtherCATInfo");
        if (!root) {
            fail(doc.first_child(), "the root element is not <EtherCATInfo> (not an ESI file, "
                                    "ETG.2000 §5.1)");
        }
        const pugi::xml_node vendor = root.child("Vendor");
        if (!vendor || !vendor.child("Id")) {
            fail(vendor ? vendor : root, "<Vendor> needs <Id>, the vendor ID (ETG.2000 §5.2)");
        }
        out.vendor_id = number32(vendor.child("Id"), "Vendor/Id");
        out.vendor_name = vendor.child_value("Name");
        const pugi::xml_node devices = root.child("Descriptions").child("Devices");
        for (const pugi::xml_node d : devices.children("Device")) {
            out.devices.push_back(device(d));
        }
        if (out.devices.empty()) {
            fail(devices ? devices : root,
                 "the file describes no device (no Descriptions/Devices/Device)");
        }
        return out;
    }

    [[noreturn]] void fail_at(std::ptrdiff_t offset, const std::string& what) {
        throw EsiError{fmt::format("{}:{}: {}", file_, line_at(offset), what)};
    }

    [[noreturn]] void fail(const pugi::xml_node& n, const std::string& what) {
        fail_at(n ? n.offset_debug() : 0, what);
    }

private:
    int line_at(std::ptrdiff_t offset) const {
        const auto end = static_cast<std::size_t>(
            std::clamp<std::ptrdiff_t>(offset, 0, static_cast<std::ptrdiff_t>(text_.size())));
        // Line = 1 + newlines before the offset (sorted offsets: a binary search).
        return 1 + static_cast<int>(std::lower_bound(newlines_.begin(), newlines_.end(), end) -
                                    newlines_.begin());
    }

    int line(const pugi::xml_node& n) const { return line_at(n.offset_debug()); }

    // ETG.2000 HexDecValue: "#x" followed by hex digits, or a decimal number.
    std::optional<std::uint64_t> parse_number(std::string_view t) const {
        while (!t.empty() && (t.front() == ' ' || t.front() == '\n' || t.front() == '\t')) {
            t.remove_prefix(1);
        }
        while (!t.empty() && (t.back() == ' ' || t.back() == '\n' || t.back() == '\t')) {
            t.remove_suffix(1);
        }
        int base = 10;
        if (t.size() > 2 && t[0] == '#' && (t[1] == 'x' || t[1] == 'X')) {
            base = 16;
            t.remove_prefix(2);
        }
        std::uint64_t v = 0;
        const auto r = std::from_chars(t.data(), t.data() + t.size(), v, base);
        if (t.empty() || r.ec != std::errc() || r.ptr != t.data() + t.size()) {
            return std::nullopt;
        }
        return v;
    }

    std::uint64_t number(const pugi::xml_node& n, std::string_view text, const char* what,
                         std::uint64_t max) {
        const auto v = parse_number(text);
        if (!v || *v > max) {
            fail(n, fmt::format("{} is `{}`, not a number 0..{} (#xHEX or decimal, ETG.2000 "
                                "HexDecValue)",
                                what, text, max));
        }
        return *v;
    }

    std::uint32_t number32(const pugi::xml_node& n, const char* what) {
        return static_cast<std::uint32_t>(number(n, n.child_value(), what, 0xFFFFFFFFU));
    }

    std::uint32_t attr32(const pugi::xml_node& n, const char* attr, const char* what) {
        return static_cast<std::uint32_t>(number(n, n.attribute(attr).value(), what, 0xFFFFFFFFU));
    }

    template <typename T>
    T child_number(const pugi::xml_node& n, const char* child, const char* what, bool required) {
        const pugi::xml_node c = n.child(child);
        if (!c) {
            if (required) {
                fail(n, fmt::format("{} has no <{}>", what, child));
            }
            return T{};
        }
        return static_cast<T>(number(c, c.child_value(),
                                     fmt::format("{} <{}>", what, child).c_str(),
                                     static_cast<std::uint64_t>(std::numeric_limits<T>::max())));
    }

    EsiDevice device(const pugi::xml_node& d) {
        EsiDevice dev;
        dev.line = line(d);
        const pugi::xml_node type = d.child("Type");
        if (!type || !type.attribute("ProductCode")) {
            fail(type ? type : d, "a <Device> needs <Type ProductCode=\"#x...\"> (ETG.2000 "
                                  "§5.3.1: the product code the slave's SII must match)");
        }
        dev.type = type.child_value();
        dev.name = d.child_value("Name");
        dev.product_code = attr32(type, "ProductCode", "Type@ProductCode");
        if (type.attribute("RevisionNo")) {
            dev.revision = attr32(type, "RevisionNo", "Type@RevisionNo");
        }
        const std::string who = dev.type.empty() ? dev.name : dev.type;
        for (const pugi::xml_node sm : d.children("Sm")) {
            EsiSyncManager s;
            s.kind = sm.child_value();
            s.start_address = static_cast<std::uint16_t>(
                number(sm, sm.attribute("StartAddress").value(), "Sm@StartAddress", 0xFFFF));
            if (sm.attribute("DefaultSize")) {
                s.default_size = static_cast<std::uint16_t>(
                    number(sm, sm.attribute("DefaultSize").value(), "Sm@DefaultSize", 0xFFFF));
            }
            if (sm.attribute("ControlByte")) {
                s.control_byte = static_cast<std::uint8_t>(
                    number(sm, sm.attribute("ControlByte").value(), "Sm@ControlByte", 0xFF));
            }
            s.enable = sm.attribute("Enable").as_bool(false);
            dev.sync_managers.push_back(std::move(s));
        }
        for (const pugi::xml_node p : d.children("RxPdo")) {
            dev.rx_pdos.push_back(pdo(p, true));
        }
        for (const pugi::xml_node p : d.children("TxPdo")) {
            dev.tx_pdos.push_back(pdo(p, false));
        }
        const pugi::xml_node coe = d.child("Mailbox").child("CoE");
        dev.coe = static_cast<bool>(coe);
        dev.sdo_info = coe.attribute("SdoInfo").as_bool(false);
        dev.pdo_assign = coe.attribute("PdoAssign").as_bool(false);
        dev.pdo_config = coe.attribute("PdoConfig").as_bool(false);
        const pugi::xml_node dict = d.child("Profile").child("Dictionary");
        read_data_types(dict.child("DataTypes"));
        for (const pugi::xml_node o : dict.child("Objects").children("Object")) {
            EsiObject obj = object(o);
            // An index names one object of the dictionary (ETG.2000 Dictionary/Objects): a second
            // definition would be shadowed by the first in every lookup (found by fuzz_ecat_esi).
            if (const EsiObject* first = dev.object(obj.index); first != nullptr) {
                fail(o, fmt::format("object {:04X}h is defined twice (first at line {})", obj.index,
                                    first->line));
            }
            dev.objects.push_back(std::move(obj));
        }
        return dev;
    }

    EsiPdo pdo(const pugi::xml_node& p, bool rx) {
        EsiPdo out;
        out.rx = rx;
        out.line = line(p);
        const char* what = rx ? "an <RxPdo>" : "a <TxPdo>";
        out.index = child_number<std::uint16_t>(p, "Index", what, true);
        out.name = p.child_value("Name");
        out.fixed = p.attribute("Fixed").as_bool(false);
        if (p.attribute("Sm")) {
            out.sm = static_cast<std::uint8_t>(
                number(p, p.attribute("Sm").value(), "PDO attribute Sm", 15));
        }
        const std::string pdo_what = fmt::format("an entry of PDO {:04X}h", out.index);
        for (const pugi::xml_node e : p.children("Entry")) {
            EsiPdoEntry pe;
            pe.index = child_number<std::uint16_t>(e, "Index", pdo_what.c_str(), true);
            pe.subindex = child_number<std::uint8_t>(e, "SubIndex", pdo_what.c_str(), false);
            pe.bit_len = child_number<std::uint8_t>(e, "BitLen", pdo_what.c_str(), true);
            pe.name = e.child_value("Name");
            pe.data_type = e.child_value("DataType");
            out.entries.push_back(std::move(pe));
        }
        return out;
    }

    void read_data_types(const pugi::xml_node& types) {
        data_types_.clear();
        for (const pugi::xml_node t : types.children("DataType")) {
            data_types_[t.child_value("Name")] = t;
        }
    }

    // Flags/Access and Flags/PdoMapping (ETG.2000 §5.4.3.4); `fallback` is the object's.
    void flags(EsiEntry& e, const pugi::xml_node& f, const pugi::xml_node& fallback) {
        const pugi::xml_node use = f ? f : fallback;
        const std::string access = use.child_value("Access");
        if (access == "rw") {
            e.access = Access::Rw;
        } else if (access == "wo") {
            e.access = Access::Wo;
        } else if (access == "ro" || access.empty()) {
            e.access = Access::Ro;
        } else {
            fail(use.child("Access"),
                 fmt::format("Flags/Access is `{}`; ETG.2000 allows ro, rw or wo", access));
        }
        const std::string map = use.child_value("PdoMapping");
        e.rx_mappable = map.find_first_of("Rr") != std::string::npos;
        e.tx_mappable = map.find_first_of("Tt") != std::string::npos;
    }

    EsiObject object(const pugi::xml_node& o) {
        EsiObject out;
        out.line = line(o);
        out.index = child_number<std::uint16_t>(o, "Index", "an <Object>", true);
        out.name = o.child_value("Name");
        out.type_name = o.child_value("Type");
        if (out.type_name.empty()) {
            fail(o, fmt::format("object {:04X}h has no <Type>", out.index));
        }
        const std::string what = fmt::format("object {:04X}h", out.index);
        out.bit_size = child_number<std::uint32_t>(o, "BitSize", what.c_str(), false);
        const auto dt = data_types_.find(out.type_name);
        const bool record = dt != data_types_.end() && dt->second.child("SubItem");
        if (!record) {
            EsiEntry e;
            e.name = out.name;
            e.type_name = out.type_name;
            e.type = esi_base_type(out.type_name);
            e.bit_size = out.bit_size;
            e.line = out.line;
            if (o.child("Info").child("DefaultData")) {
                e.default_data = o.child("Info").child_value("DefaultData");
            }
            flags(e, o.child("Flags"), o.child("Flags"));
            out.entries.push_back(std::move(e));
            return out;
        }
        for (const pugi::xml_node s : dt->second.children("SubItem")) {
            add_sub_items(out, s, o);
        }
        // Info/SubItem gives the defaults by name, in the order of the DataType's sub-items
        // (ETG.2000 §5.4.3.3); several sub-items may share a name (1003h "Standard error field").
        std::vector<bool> used(out.entries.size(), false);
        for (const pugi::xml_node si : o.child("Info").children("SubItem")) {
            const std::string name = si.child_value("Name");
            for (std::size_t i = 0; i < out.entries.size(); ++i) {
                if (!used[i] && out.entries[i].name == name) {
                    used[i] = true;
                    if (si.child("Info").child("DefaultData")) {
                        out.entries[i].default_data = si.child("Info").child_value("DefaultData");
                    }
                    break;
                }
            }
        }
        return out;
    }

    // One DataType SubItem: a base-typed entry, or an array type expanded into its elements
    // (ArrayInfo LBound/Elements, ETG.2000 §5.4.3.2).
    void add_sub_items(EsiObject& out, const pugi::xml_node& s, const pugi::xml_node& o) {
        const std::string what = fmt::format("a sub-item of object {:04X}h", out.index);
        const std::string type = s.child_value("Type");
        const auto arr = data_types_.find(type);
        if (arr != data_types_.end() && arr->second.child("ArrayInfo")) {
            const pugi::xml_node ai = arr->second.child("ArrayInfo");
            const auto lbound = child_number<std::uint8_t>(ai, "LBound", what.c_str(), false);
            const auto count = child_number<std::uint8_t>(ai, "Elements", what.c_str(), true);
            const std::string base = arr->second.child_value("BaseType");
            const std::uint32_t bits =
                count == 0
                    ? 0
                    : child_number<std::uint32_t>(arr->second, "BitSize", what.c_str(), false) /
                          count;
            for (unsigned i = 0; i < count; ++i) {
                EsiEntry e;
                e.subindex = static_cast<std::uint8_t>(lbound + i);
                e.name = fmt::format("{} {}", s.child_value("Name"), e.subindex);
                e.type_name = base;
                e.type = esi_base_type(base);
                e.bit_size = bits;
                e.line = line(s);
                flags(e, s.child("Flags"), o.child("Flags"));
                out.entries.push_back(std::move(e));
            }
            return;
        }
        EsiEntry e;
        e.subindex = child_number<std::uint8_t>(s, "SubIdx", what.c_str(), true);
        e.name = s.child_value("Name");
        e.type_name = type;
        e.type = esi_base_type(type);
        e.bit_size = child_number<std::uint32_t>(s, "BitSize", what.c_str(), false);
        e.line = line(s);
        flags(e, s.child("Flags"), o.child("Flags"));
        out.entries.push_back(std::move(e));
    }

    std::string_view text_;
    const std::string& file_;
    std::vector<std::size_t> newlines_;
    std::map<std::string, pugi::xml_node> data_types_;
};

} // namespace

namespace {
// ETG.2000 §5.4.3 (Table 42) base data types and their CiA 301 types; where two names share a
// type, the first is the one written (BOOL, USINT, UINT, UDINT).
constexpr std::pair<std::string_view, DataType> kEsiBaseTypes[] = {
    {"BOOL", DataType::Boolean},     {"BIT", DataType::Boolean},
    {"SINT", DataType::Integer8},    {"INT", DataType::Integer16},
    {"INT24", DataType::Integer24},  {"DINT", DataType::Integer32},
    {"LINT", DataType::Integer64},   {"USINT", DataType::Unsigned8},
    {"BYTE", DataType::Unsigned8},   {"UINT", DataType::Unsigned16},
    {"WORD", DataType::Unsigned16},  {"UINT24", DataType::Unsigned24},
    {"UDINT", DataType::Unsigned32}, {"DWORD", DataType::Unsigned32},
    {"ULINT", DataType::Unsigned64}, {"REAL", DataType::Real32},
    {"LREAL", DataType::Real64},
};
} // namespace

std::string_view esi_base_type_name(DataType type) {
    for (const auto& [n, t] : kEsiBaseTypes) {
        if (t == type) {
            return n;
        }
    }
    return {};
}

std::optional<DataType> esi_base_type(std::string_view name) {
    for (const auto& [n, t] : kEsiBaseTypes) {
        if (n == name) {
            return t;
        }
    }
    if (name.rfind("STRING(", 0) == 0) {
        return DataType::VisibleString;
    }
    if (name.rfind("ARRAY [", 0) == 0 && name.size() > 8 &&
        name.substr(name.size() - 8) == " OF BYTE") {
        return DataType::OctetString;
    }
    return std::nullopt;
}

const EsiEntry* EsiObject::entry(std::uint8_t subindex) const {
    for (const auto& e : entries) {
        if (e.subindex == subindex) {
            return &e;
        }
    }
    return nullptr;
}

const EsiObject* EsiDevice::object(std::uint16_t index) const {
    for (const auto& o : objects) {
        if (o.index == index) {
            return &o;
        }
    }
    return nullptr;
}

const EsiEntry* EsiDevice::entry(std::uint16_t index, std::uint8_t subindex) const {
    const EsiObject* o = object(index);
    return o != nullptr ? o->entry(subindex) : nullptr;
}

std::string EsiDevice::describe() const {
    return fmt::format("product 0x{:08X} revision 0x{:08X} ({})", product_code, revision,
                       name.empty() ? type : name);
}

const EsiDevice* EsiFile::match(std::uint32_t vendor, std::uint32_t product,
                                std::uint32_t revision) const {
    if (vendor != vendor_id) {
        return nullptr;
    }
    for (const auto& d : devices) {
        if (d.product_code == product && d.revision == revision) {
            return &d;
        }
    }
    // A drive's firmware moves its revision on while the vendor's file keeps the one it was
    // written for: the same product with another revision still describes it (as EtherCAT
    // configuration tools match by default), the exact revision first.
    for (const auto& d : devices) {
        if (d.product_code == product) {
            return &d;
        }
    }
    return nullptr;
}

std::string EsiFile::mismatch(std::uint32_t vendor, std::uint32_t product,
                              std::uint32_t revision) const {
    std::string has;
    for (const auto& d : devices) {
        has += has.empty() ? d.describe() : "; " + d.describe();
    }
    return fmt::format("the slave is vendor 0x{:08X} product 0x{:08X} revision 0x{:08X}, but {} "
                       "describes vendor 0x{:08X} with {}",
                       vendor, product, revision, file, vendor_id, has);
}

tl::expected<EsiFile, std::string> parse_esi(std::string_view text, const std::string& file) {
    pugi::xml_document doc;
    const pugi::xml_parse_result r = doc.load_buffer(text.data(), text.size());
    Reader reader(text, file);
    try {
        if (!r) {
            reader.fail_at(r.offset, fmt::format("not well-formed XML: {}", r.description()));
        }
        return reader.read(doc);
    } catch (const EsiError& e) {
        return tl::unexpected(e.sentence);
    }
}

tl::expected<EsiFile, std::string> load_esi(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    if (!in) {
        return tl::unexpected(
            fmt::format("{}: cannot read the ESI file: {}", path, std::strerror(errno)));
    }
    std::ostringstream s;
    s << in.rdbuf();
    return parse_esi(s.str(), path);
}

} // namespace codrive::ethercat
