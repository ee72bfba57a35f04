// SPDX-License-Identifier: Apache-2.0
// EDS/DCF device descriptions (CiA 306): parse into an ObjectDictionary with findings, write back.
#pragma once

#include <codrive/core/cob_id.hpp>
#include <codrive/core/error.hpp>
#include <codrive/core/object_dictionary.hpp>

#include <cstddef>
#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace codrive {

/// How bad a finding is. Errors mean the file breaks CiA 306 in a way codrive could not repair
/// (the affected key, sub-object or object is skipped); warnings mean it was accepted the way
/// common tools accept it; infos are notes (ignored keys and sections).
enum class EdsSeverity : std::uint8_t { Info, Warning, Error };
[[nodiscard]] std::string_view to_string(EdsSeverity s); ///< "info", "warning", "error"

/// One problem found in a file, with the 1-based line it was found on (0: the file as a whole).
struct EdsFinding {
    std::string file;
    std::size_t line = 0;
    EdsSeverity severity = EdsSeverity::Error;
    std::string message;

    friend bool operator==(const EdsFinding&, const EdsFinding&) = default;
};
/// "FILE:LINE: severity: message" (the format of compilers, so editors can jump to it).
[[nodiscard]] std::string format_finding(const EdsFinding& f);

/// [FileInfo], kept as written.
struct FileInfo {
    std::string file_name;
    std::string file_version;
    std::string file_revision;
    std::string eds_version;
    std::string description;
    std::string creation_time;
    std::string creation_date;
    std::string created_by;
    std::string modification_time;
    std::string modification_date;
    std::string modified_by;
    std::string last_eds;

    friend bool operator==(const FileInfo&, const FileInfo&) = default;
};

/// [DeviceInfo].
struct DeviceInfo {
    std::string vendor_name;
    std::uint32_t vendor_number = 0;
    std::string product_name;
    std::uint32_t product_number = 0;
    std::uint32_t revision_number = 0;
    std::string order_code;
    std::vector<unsigned> baud_rates; ///< supported bit rates in kbit/s (BaudRate_N=1), ascending
    bool simple_boot_up_master = false;
    bool simple_boot_up_slave = false;
    std::uint8_t granularity = 8; ///< PDO mapping granularity in bits (0: no mapping)
    std::uint8_t dynamic_channels_supported = 0;
    std::uint8_t compact_pdo = 0;
    bool group_messaging = false;
    std::uint16_t nr_of_rx_pdo = 0;
    std::uint16_t nr_of_tx_pdo = 0;
    bool lss_supported = false;

    friend bool operator==(const DeviceInfo&, const DeviceInfo&) = default;
};

/// [DummyUsage]: which data types may be mapped as dummy entries into RPDOs.
struct DummyUsage {
    std::map<std::uint16_t, bool> entries; ///< data type index → DummyXXXX value

    [[nodiscard]] bool supported(DataType t) const {
        auto it = entries.find(static_cast<std::uint16_t>(t));
        return it != entries.end() && it->second;
    }
    friend bool operator==(const DummyUsage&, const DummyUsage&) = default;
};

/// DCF [DeviceComissioning] (CiA 306; the spec spells it with one "m").
struct DeviceCommissioning {
    std::optional<NodeId> node_id;
    std::optional<std::string> node_name;
    std::optional<unsigned> baudrate; ///< kbit/s
    std::optional<std::uint32_t> net_number;
    std::optional<std::string> network_name;
    std::optional<bool> canopen_manager;
    std::optional<std::uint32_t> lss_serial_number;

    [[nodiscard]] bool empty() const {
        return !node_id && !node_name && !baudrate && !net_number && !network_name &&
               !canopen_manager && !lss_serial_number;
    }
    friend bool operator==(const DeviceCommissioning&, const DeviceCommissioning&) = default;
};

/// A parsed EDS or DCF file.
struct DeviceDescription {
    FileInfo file_info;
    DeviceInfo device_info;
    DeviceCommissioning commissioning;
    DummyUsage dummy_usage;
    std::vector<std::string> comments; ///< [Comments] Line1..LineN
    ObjectDictionary od;
    /// The node-ID `$NODEID` was evaluated with (argument, else DCF NodeID), if any. Without
    /// one, `$NODEID` counts as 0, so default values hold the base of the expression.
    std::optional<NodeId> node_id;
    std::vector<EdsFinding> findings;

    [[nodiscard]] std::size_t count(EdsSeverity s) const;
    [[nodiscard]] bool has_errors() const { return count(EdsSeverity::Error) != 0; }
};

/// Parses EDS/DCF text. Never fails and never throws: whatever cannot be read becomes a finding
/// (file = `filename`, with its line) and the rest is loaded. `node_id` overrides the DCF NodeID
/// for evaluating `$NODEID` expressions.
[[nodiscard]] DeviceDescription parse_eds(std::string_view text, std::string filename,
                                          std::optional<NodeId> node_id = {});

/// Reads and parses a file. Errors: the std::errc of a file that cannot be opened or read
/// (e.g. no_such_file_or_directory). Problems in the file's content are findings, not errors.
[[nodiscard]] Result<DeviceDescription> load_eds(const std::string& path,
                                                 std::optional<NodeId> node_id = {});

/// Writes a description as an EDS (or a DCF, if it has commissioning data or ParameterValues).
/// Parsing the result gives the same objects, sub-objects, names, types, access, mappability,
/// defaults, limits, flags, FileInfo, DeviceInfo, DummyUsage and commissioning. Compact
/// (CompactSubObj) arrays are written expanded.
[[nodiscard]] std::string write_eds(const DeviceDescription& desc);

/// Writes write_eds(desc) to a file. Errors: the std::errc of a failed open or write.
[[nodiscard]] VoidResult save_eds(const DeviceDescription& desc, const std::string& path);

/// Re-evaluates every DefaultValue and ParameterValue that uses `$NODEID` for `node`, and sets
/// the affected current values (e.g. to use one EDS for several nodes).
void assign_node_id(DeviceDescription& desc, NodeId node);

/// Text for a value the way CiA 306 files write it (hex unsigned, decimal signed and reals,
/// strings verbatim or quoted when they would not survive a round trip, hex octets).
[[nodiscard]] std::string eds_value_text(const Value& v);

} // namespace codrive
