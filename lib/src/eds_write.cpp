// SPDX-License-Identifier: Apache-2.0
// EDS/DCF writer (CiA 306): a DeviceDescription back to text that parses to the same model.
#include "eds_internal.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <cctype>
#include <cerrno>
#include <fstream>
#include <vector>

namespace codrive {
namespace {

// A single-line value: line breaks and other control characters would end or corrupt the key.
std::string one_line(std::string_view s) {
    std::string out;
    for (char c : s) {
        out += std::iscntrl(static_cast<unsigned char>(c)) != 0 && c != '\t' ? ' ' : c;
    }
    return std::string(eds::trim(out));
}

bool writable_text(std::string_view s) {
    for (char c : s) {
        if (c == '\n' || c == '\r') {
            return false;
        }
    }
    return s == eds::trim(s);
}

class Writer {
public:
    void section(std::string_view name) {
        if (!out_.empty()) {
            out_ += '\n';
        }
        out_ += fmt::format("[{}]\n", name);
    }
    void key(std::string_view k, std::string_view v) { out_ += fmt::format("{}={}\n", k, v); }
    void hex32(std::string_view k, std::uint32_t v) { key(k, fmt::format("0x{:08X}", v)); }
    void num(std::string_view k, std::uint64_t v) { key(k, fmt::format("{}", v)); }
    void flag(std::string_view k, bool v) { key(k, v ? "1" : "0"); }
    std::string take() { return std::move(out_); }

private:
    std::string out_;
};

void write_file_info(Writer& w, const FileInfo& fi) {
    w.section("FileInfo");
    w.key("FileName", one_line(fi.file_name));
    w.key("FileVersion", one_line(fi.file_version));
    w.key("FileRevision", one_line(fi.file_revision));
    w.key("LastEDS", one_line(fi.last_eds));
    w.key("EDSVersion", one_line(fi.eds_version));
    w.key("Description", one_line(fi.description));
    w.key("CreationTime", one_line(fi.creation_time));
    w.key("CreationDate", one_line(fi.creation_date));
    w.key("CreatedBy", one_line(fi.created_by));
    w.key("ModificationTime", one_line(fi.modification_time));
    w.key("ModificationDate", one_line(fi.modification_date));
    w.key("ModifiedBy", one_line(fi.modified_by));
}

void write_device_info(Writer& w, const DeviceInfo& di) {
    w.section("DeviceInfo");
    w.key("VendorName", one_line(di.vendor_name));
    w.hex32("VendorNumber", di.vendor_number);
    w.key("ProductName", one_line(di.product_name));
    w.hex32("ProductNumber", di.product_number);
    w.hex32("RevisionNumber", di.revision_number);
    w.key("OrderCode", one_line(di.order_code));
    // The CiA 301 bit rates are always listed; other rates only when supported.
    constexpr std::array<unsigned, 8> kStandard = {10, 20, 50, 125, 250, 500, 800, 1000};
    std::vector<unsigned> rates(kStandard.begin(), kStandard.end());
    for (unsigned r : di.baud_rates) {
        if (std::find(rates.begin(), rates.end(), r) == rates.end()) {
            rates.push_back(r);
        }
    }
    std::sort(rates.begin(), rates.end());
    for (unsigned r : rates) {
        const bool on =
            std::find(di.baud_rates.begin(), di.baud_rates.end(), r) != di.baud_rates.end();
        w.flag(fmt::format("BaudRate_{}", r), on);
    }
    w.flag("SimpleBootUpMaster", di.simple_boot_up_master);
    w.flag("SimpleBootUpSlave", di.simple_boot_up_slave);
    w.num("Granularity", di.granularity);
    w.num("DynamicChannelsSupported", di.dynamic_channels_supported);
    w.num("CompactPDO", di.compact_pdo);
    w.flag("GroupMessaging", di.group_messaging);
    w.num("NrOfRXPDO", di.nr_of_rx_pdo);
    w.num("NrOfTXPDO", di.nr_of_tx_pdo);
    w.flag("LSS_Supported", di.lss_supported);
}

void write_commissioning(Writer& w, const DeviceCommissioning& dc) {
    w.section("DeviceComissioning"); // sic, as CiA 306 spells it
    if (dc.node_id) {
        w.key("NodeID", fmt::format("0x{:02X}", *dc.node_id));
    }
    if (dc.node_name) {
        w.key("NodeName", one_line(*dc.node_name));
    }
    if (dc.baudrate) {
        w.num("Baudrate", *dc.baudrate);
    }
    if (dc.net_number) {
        w.num("NetNumber", *dc.net_number);
    }
    if (dc.network_name) {
        w.key("NetworkName", one_line(*dc.network_name));
    }
    if (dc.canopen_manager) {
        w.flag("CANopenManager", *dc.canopen_manager);
    }
    if (dc.lss_serial_number) {
        w.hex32("LSS_SerialNumber", *dc.lss_serial_number);
    }
}

enum class List { Mandatory, Optional, Manufacturer };

// CiA 301: 1000h, 1001h and 1018h are mandatory; 2000h..5FFFh are manufacturer-specific.
List list_of(std::uint16_t index) {
    if (index == 0x1000 || index == 0x1001 || index == 0x1018) {
        return List::Mandatory;
    }
    if (index >= 0x2000 && index <= 0x5FFF) {
        return List::Manufacturer;
    }
    return List::Optional;
}

void write_lists(Writer& w, const ObjectDictionary& od) {
    for (auto [list, name] : {std::pair{List::Mandatory, "MandatoryObjects"},
                              std::pair{List::Optional, "OptionalObjects"},
                              std::pair{List::Manufacturer, "ManufacturerObjects"}}) {
        std::vector<std::uint16_t> indexes;
        for (const auto& [index, obj] : od.objects()) {
            if (list_of(index) == list) {
                indexes.push_back(index);
            }
        }
        w.section(name);
        w.num("SupportedObjects", indexes.size());
        for (std::size_t i = 0; i < indexes.size(); ++i) {
            w.key(fmt::format("{}", i + 1), fmt::format("0x{:04X}", indexes[i]));
        }
    }
}

std::string default_text(const SubObject& sub) {
    if (!sub.default_text.empty() && writable_text(sub.default_text)) {
        return sub.default_text;
    }
    return sub.default_value ? eds_value_text(*sub.default_value) : std::string();
}

void write_value_keys(Writer& w, const SubObject& sub) {
    w.key("DataType", fmt::format("0x{:04X}", static_cast<unsigned>(sub.type)));
    w.key("AccessType", to_string(sub.access));
    if (sub.default_value || !sub.default_text.empty()) {
        w.key("DefaultValue", default_text(sub));
    }
    w.flag("PDOMapping", sub.pdo_mappable);
    if (sub.low_limit) {
        w.key("LowLimit", eds_value_text(*sub.low_limit));
    }
    if (sub.high_limit) {
        w.key("HighLimit", eds_value_text(*sub.high_limit));
    }
    if (sub.obj_flags != 0) {
        w.key("ObjFlags", fmt::format("0x{:X}", sub.obj_flags));
    }
    if (!sub.parameter_text.empty()) {
        w.key("ParameterValue",
              writable_text(sub.parameter_text) ? sub.parameter_text : eds_value_text(sub.value));
    }
}

void write_object(Writer& w, const Object& obj) {
    w.section(fmt::format("{:04X}", obj.index));
    w.key("ParameterName", one_line(obj.name));
    w.key("ObjectType", fmt::format("0x{:X}", static_cast<unsigned>(obj.code)));
    const bool complex = obj.code == ObjectCode::Array || obj.code == ObjectCode::Record ||
                         obj.code == ObjectCode::Defstruct;
    if (!complex) {
        if (const SubObject* sub = obj.find(0)) {
            write_value_keys(w, *sub);
        }
        return;
    }
    w.key("SubNumber", fmt::format("0x{:X}", obj.subs.size()));
    if (obj.obj_flags != 0) {
        w.key("ObjFlags", fmt::format("0x{:X}", obj.obj_flags));
    }
    for (const auto& [si, sub] : obj.subs) {
        w.section(fmt::format("{:04X}sub{:X}", obj.index, si));
        w.key("ParameterName", one_line(sub.name));
        w.key("ObjectType", "0x7");
        write_value_keys(w, sub);
    }
}

} // namespace

std::string write_eds(const DeviceDescription& desc) {
    Writer w;
    write_file_info(w, desc.file_info);
    write_device_info(w, desc.device_info);
    if (!desc.dummy_usage.entries.empty()) {
        w.section("DummyUsage");
        for (const auto& [type, on] : desc.dummy_usage.entries) {
            w.flag(fmt::format("Dummy{:04X}", type), on);
        }
    }
    if (!desc.comments.empty()) {
        w.section("Comments");
        w.num("Lines", desc.comments.size());
        for (std::size_t i = 0; i < desc.comments.size(); ++i) {
            w.key(fmt::format("Line{}", i + 1), one_line(desc.comments[i]));
        }
    }
    if (!desc.commissioning.empty()) {
        write_commissioning(w, desc.commissioning);
    }
    write_lists(w, desc.od);
    for (const auto& [index, obj] : desc.od.objects()) {
        write_object(w, obj);
    }
    return w.take();
}

VoidResult save_eds(const DeviceDescription& desc, const std::string& path) {
    std::ofstream out(path, std::ios::binary | std::ios::trunc);
    if (!out) {
        return fail_errno(errno != 0 ? errno : EACCES);
    }
    const std::string text = write_eds(desc);
    out.write(text.data(), static_cast<std::streamsize>(text.size()));
    out.close();
    if (!out) {
        return fail_errno(errno != 0 ? errno : EIO);
    }
    return {};
}

} // namespace codrive
