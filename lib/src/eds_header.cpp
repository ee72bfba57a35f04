// SPDX-License-Identifier: Apache-2.0
// EDS/DCF header sections: [FileInfo], [DeviceInfo], [DummyUsage], [Comments], commissioning.
#include "eds_internal.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cctype>
#include <limits>

namespace codrive::eds {

std::optional<std::uint64_t> read_uint(std::string_view text, std::uint64_t max, std::size_t line,
                                       const std::string& what, Findings& findings) {
    IntegerText it = parse_integer(text, std::nullopt);
    for (auto& note : it.notes) {
        findings.warning(line, fmt::format("{}: {}", what, note));
    }
    if (!it.value) {
        findings.error(line, fmt::format("{} '{}' {}", what, text.substr(0, 40), it.error));
        return std::nullopt;
    }
    if (it.uses_node_id) {
        findings.error(line, fmt::format("{} '{}' uses $NODEID, which is only allowed in values",
                                         what, text.substr(0, 40)));
        return std::nullopt;
    }
    if (it.value->negative || it.value->magnitude > max) {
        findings.error(
            line, fmt::format("{} '{}' is out of range (0..{})", what, text.substr(0, 40), max));
        return std::nullopt;
    }
    return it.value->magnitude;
}

std::optional<std::uint64_t> get_uint(Section& s, std::string_view key, std::uint64_t max,
                                      Findings& findings) {
    Entry* e = s.find(key);
    if (e == nullptr || e->value.empty()) {
        return std::nullopt;
    }
    return read_uint(number_text(s, *e, findings), max, e->line,
                     fmt::format("[{}] {}", s.name, key), findings);
}

std::optional<bool> get_bool(Section& s, std::string_view key, Findings& findings) {
    Entry* e = s.find(key);
    if (e == nullptr || e->value.empty()) {
        return std::nullopt;
    }
    const std::string_view text = number_text(s, *e, findings);
    if (iequals(text, "true") || iequals(text, "false")) {
        findings.warning(e->line, fmt::format("[{}] {}={} should be 1 or 0", s.name, key, text));
        return iequals(text, "true");
    }
    auto v = read_uint(text, 0xFFFFFFFF, e->line, fmt::format("[{}] {}", s.name, key), findings);
    if (!v) {
        return std::nullopt;
    }
    if (*v > 1) {
        findings.warning(e->line,
                         fmt::format("[{}] {}={} should be 1 or 0; read as 1", s.name, key, text));
    }
    return *v != 0;
}

void report_unused(const Section& s, Findings& findings) {
    for (const auto& e : s.entries) {
        if (!e.used) {
            findings.info(e.line, fmt::format("[{}] key '{}' is not used by codrive; ignored",
                                              s.name, e.key.substr(0, 40)));
        }
    }
}

namespace {

std::string get_text(Section& s, std::string_view key) {
    Entry* e = s.find(key);
    return e == nullptr ? std::string() : e->value;
}

void parse_file_info(Section& s, FileInfo& fi) {
    fi.file_name = get_text(s, "FileName");
    fi.file_version = get_text(s, "FileVersion");
    fi.file_revision = get_text(s, "FileRevision");
    fi.eds_version = get_text(s, "EDSVersion");
    fi.description = get_text(s, "Description");
    fi.creation_time = get_text(s, "CreationTime");
    fi.creation_date = get_text(s, "CreationDate");
    fi.created_by = get_text(s, "CreatedBy");
    fi.modification_time = get_text(s, "ModificationTime");
    fi.modification_date = get_text(s, "ModificationDate");
    fi.modified_by = get_text(s, "ModifiedBy");
    fi.last_eds = get_text(s, "LastEDS");
}

template <typename T>
void set_uint(Section& s, std::string_view key, T& field, Findings& f) {
    if (auto v = get_uint(s, key, std::numeric_limits<T>::max(), f)) {
        field = static_cast<T>(*v);
    }
}

void set_bool(Section& s, std::string_view key, bool& field, Findings& f) {
    if (auto v = get_bool(s, key, f)) {
        field = *v;
    }
}

void parse_device_info(Section& s, DeviceInfo& di, Findings& f) {
    di.vendor_name = get_text(s, "VendorName");
    set_uint(s, "VendorNumber", di.vendor_number, f);
    di.product_name = get_text(s, "ProductName");
    set_uint(s, "ProductNumber", di.product_number, f);
    set_uint(s, "RevisionNumber", di.revision_number, f);
    di.order_code = get_text(s, "OrderCode");
    set_bool(s, "SimpleBootUpMaster", di.simple_boot_up_master, f);
    set_bool(s, "SimpleBootUpSlave", di.simple_boot_up_slave, f);
    if (auto g = get_uint(s, "Granularity", 64, f)) {
        di.granularity = static_cast<std::uint8_t>(*g);
    }
    set_uint(s, "DynamicChannelsSupported", di.dynamic_channels_supported, f);
    set_uint(s, "CompactPDO", di.compact_pdo, f);
    set_bool(s, "GroupMessaging", di.group_messaging, f);
    set_uint(s, "NrOfRXPDO", di.nr_of_rx_pdo, f);
    set_uint(s, "NrOfTXPDO", di.nr_of_tx_pdo, f);
    set_bool(s, "LSS_Supported", di.lss_supported, f);
    constexpr std::string_view kBaud = "baudrate_";
    for (auto& e : s.entries) {
        if (e.key.size() <= kBaud.size() || !iequals(e.key.substr(0, kBaud.size()), kBaud)) {
            continue;
        }
        e.used = true;
        const std::string what = fmt::format("[{}] {}", s.name, e.key);
        auto rate = read_uint(e.key.substr(kBaud.size()), 1'000'000, e.line, what + " bit rate", f);
        auto on = read_uint(e.value, 0xFFFFFFFF, e.line, what, f);
        if (rate && on && *on != 0) {
            di.baud_rates.push_back(static_cast<unsigned>(*rate));
        }
    }
    std::sort(di.baud_rates.begin(), di.baud_rates.end());
    di.baud_rates.erase(std::unique(di.baud_rates.begin(), di.baud_rates.end()),
                        di.baud_rates.end());
}

void parse_dummy_usage(Section& s, DummyUsage& du, Findings& f) {
    constexpr std::string_view kDummy = "dummy";
    for (auto& e : s.entries) {
        if (e.key.size() != kDummy.size() + 4 || !iequals(e.key.substr(0, kDummy.size()), kDummy)) {
            continue;
        }
        e.used = true;
        const std::string what = fmt::format("[{}] {}", s.name, e.key);
        auto index = read_uint("0x" + e.key.substr(kDummy.size()), 0xFFFF, e.line, what, f);
        auto on = read_uint(e.value, 1, e.line, what, f);
        if (index && on) {
            du.entries[static_cast<std::uint16_t>(*index)] = *on != 0;
        }
    }
}

void parse_comments(Section& s, std::vector<std::string>& comments, Findings& f) {
    const auto lines = get_uint(s, "Lines", 0xFFFF, f).value_or(0);
    std::uint64_t missing = 0;
    std::uint64_t first_missing = 0;
    for (std::uint64_t i = 1; i <= lines; ++i) {
        Entry* e = s.find(fmt::format("Line{}", i));
        if (e == nullptr) {
            first_missing = missing++ == 0 ? i : first_missing;
            continue;
        }
        comments.push_back(e->value);
    }
    if (missing != 0) {
        f.warning(s.line, fmt::format("[{}] Lines={} but {} of the lines are missing (first: "
                                      "Line{}); the others are kept",
                                      s.name, lines, missing, first_missing));
    }
}

void parse_commissioning(Section& s, DeviceCommissioning& dc, Findings& f) {
    if (Entry* e = s.find("NodeID"); e != nullptr && !e->value.empty()) {
        auto v = read_uint(e->value, 0xFF, e->line, fmt::format("[{}] NodeID", s.name), f);
        if (v && !valid_node_id(static_cast<unsigned>(*v))) {
            f.error(e->line, fmt::format("[{}] NodeID {} is not a node-ID (1..127)", s.name, *v));
        } else if (v) {
            dc.node_id = static_cast<NodeId>(*v);
        }
    }
    if (Entry* e = s.find("NodeName")) {
        dc.node_name = e->value;
    }
    if (auto v = get_uint(s, "Baudrate", 1'000'000, f)) {
        dc.baudrate = static_cast<unsigned>(*v);
    }
    if (auto v = get_uint(s, "NetNumber", 0xFFFFFFFF, f)) {
        dc.net_number = static_cast<std::uint32_t>(*v);
    }
    if (Entry* e = s.find("NetworkName")) {
        dc.network_name = e->value;
    }
    if (auto v = get_bool(s, "CANopenManager", f)) {
        dc.canopen_manager = *v;
    }
    if (auto v = get_uint(s, "LSS_SerialNumber", 0xFFFFFFFF, f)) {
        dc.lss_serial_number = static_cast<std::uint32_t>(*v);
    }
}

} // namespace

void parse_header_sections(IniFile& ini, DeviceDescription& desc, Findings& f) {
    if (Section* s = ini.find("fileinfo")) {
        parse_file_info(*s, desc.file_info);
        report_unused(*s, f);
    } else {
        f.warning(0, "no [FileInfo] section (CiA 306 requires one in an EDS)");
    }
    if (Section* s = ini.find("deviceinfo")) {
        parse_device_info(*s, desc.device_info, f);
        report_unused(*s, f);
    } else {
        f.warning(0, "no [DeviceInfo] section (CiA 306 requires one); using defaults");
    }
    if (Section* s = ini.find("dummyusage")) {
        parse_dummy_usage(*s, desc.dummy_usage, f);
        report_unused(*s, f);
    }
    if (Section* s = ini.find("comments")) {
        parse_comments(*s, desc.comments, f);
        report_unused(*s, f);
    }
    Section* dc = ini.find("devicecomissioning");
    if (Section* alt = ini.find("devicecommissioning")) {
        f.warning(alt->line, "[DeviceCommissioning] is spelt [DeviceComissioning] in CiA 306; "
                             "read anyway");
        if (dc == nullptr) {
            dc = alt;
        }
    }
    if (dc != nullptr) {
        parse_commissioning(*dc, desc.commissioning, f);
        report_unused(*dc, f);
    }
}

} // namespace codrive::eds
