// SPDX-License-Identifier: Apache-2.0
// Private pieces of the EDS/DCF reader: INI tokenizer, findings sink, number and value text.
#pragma once

#include <codrive/core/eds.hpp>

#include <cstddef>
#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace codrive::eds {

/// Collects findings for one file.
class Findings {
public:
    Findings(std::string file, std::vector<EdsFinding>& out) : file_(std::move(file)), out_(out) {}
    void error(std::size_t line, std::string msg) { add(line, EdsSeverity::Error, std::move(msg)); }
    void warning(std::size_t line, std::string msg) {
        add(line, EdsSeverity::Warning, std::move(msg));
    }
    void info(std::size_t line, std::string msg) { add(line, EdsSeverity::Info, std::move(msg)); }
    void add(std::size_t line, EdsSeverity s, std::string msg) {
        out_.push_back(EdsFinding{file_, line, s, std::move(msg)});
    }

private:
    std::string file_;
    std::vector<EdsFinding>& out_;
};

/// One `key=value` line.
struct Entry {
    std::string key;   ///< as written (trimmed)
    std::string value; ///< trimmed
    std::size_t line = 0;
    bool used = false;
    bool comment_reported = false;
};

/// One `[name]` section; duplicated sections are merged into the first.
struct Section {
    std::string name;  ///< as written (trimmed)
    std::string lower; ///< lower-case name, for lookups
    std::size_t line = 0;
    std::vector<Entry> entries;
    std::map<std::string, std::size_t> keys; ///< lower-case key → index in entries

    /// Case-insensitive key lookup; marks the entry used.
    [[nodiscard]] Entry* find(std::string_view key);
};

/// The whole file as sections, in order of first appearance.
struct IniFile {
    std::vector<Section> sections;
    std::map<std::string, std::size_t> by_name; ///< lower-case name → index in sections

    [[nodiscard]] Section* find(std::string_view lower_name);
};

/// Splits text into sections and entries. Reports malformed lines, keys outside sections,
/// duplicate sections (merged) and duplicate keys (the first one wins, as with the Windows INI
/// functions EDS files were designed for).
[[nodiscard]] IniFile tokenize(std::string_view text, Findings& findings);

[[nodiscard]] std::string to_lower(std::string_view s);
[[nodiscard]] bool iequals(std::string_view a, std::string_view b);
[[nodiscard]] std::string_view trim(std::string_view s);

/// A signed integer as sign and magnitude (UNSIGNED64 values need all 64 bits).
struct Integer {
    bool negative = false;
    std::uint64_t magnitude = 0;
};

/// Result of reading an integer expression such as `0x180`, `-5`, `017`, `$NODEID+0x180`.
struct IntegerText {
    std::optional<Integer> value; ///< nullopt: not an integer expression (see error)
    std::string error;
    std::vector<std::string> notes; ///< warnings (octal reading, leading zeros)
    bool uses_node_id = false;
    bool plain_hex = false; ///< one unsigned hex literal (a bit pattern for signed types)
    std::size_t hex_digits = 0;
};

/// Reads an integer expression: terms joined by + or -, each a number or `$NODEID`. Numbers are
/// decimal, hex with 0x, or octal with a leading 0 (CiA 306, as strtoul(…, 0) reads
/// them). `$NODEID` evaluates to `node` (0 when unknown).
[[nodiscard]] IntegerText parse_integer(std::string_view text, std::optional<NodeId> node);

/// Result of reading a DefaultValue/ParameterValue/limit for a data type.
struct ValueText {
    std::optional<Value> value;
    std::string error;
    std::vector<std::string> notes;
    bool uses_node_id = false;
};

/// Reads value text for a data type. Integers as parse_integer (range-checked against the type;
/// hex for a signed type is a bit pattern), BOOLEAN also true/false, reals as decimal or as a
/// hex bit pattern (lely writes 0x40490FDB for pi), VISIBLE/UNICODE_STRING verbatim or
/// "quoted" with C escapes, OCTET_STRING and DOMAIN as hex bytes, TIME_OF_DAY/TIME_DIFFERENCE
/// as "days ms" or one raw number.
[[nodiscard]] ValueText parse_value(DataType type, std::string_view text,
                                    std::optional<NodeId> node);

/// True if value text refers to $NODEID (any letter case).
[[nodiscard]] bool uses_node_id(std::string_view text);

/// The value of a number-like key without a trailing `; comment`. CiA 306 only knows whole-line
/// comments, but vendor files put them after numbers; text keys keep their ';'. Warns once.
[[nodiscard]] std::string_view number_text(const Section& s, Entry& e, Findings& findings);

/// Reads an unsigned key (any number syntax of parse_integer, no $NODEID) up to `max`. Reports
/// bad text and out-of-range values as errors naming the section and key. nullopt if absent,
/// empty or bad.
[[nodiscard]] std::optional<std::uint64_t> get_uint(Section& s, std::string_view key,
                                                    std::uint64_t max, Findings& findings);
/// Reads a 0/1 key (also true/false, any non-zero number with a warning).
[[nodiscard]] std::optional<bool> get_bool(Section& s, std::string_view key, Findings& findings);
/// Reads an unsigned value text; nullopt with an error finding at `line` naming `what`.
[[nodiscard]] std::optional<std::uint64_t> read_uint(std::string_view text, std::uint64_t max,
                                                     std::size_t line, const std::string& what,
                                                     Findings& findings);
/// Reports keys of a section that nothing read, as infos.
void report_unused(const Section& s, Findings& findings);

/// The sections of a file sorted by what they describe.
struct Catalog {
    std::map<std::uint16_t, Section*> objects;
    std::map<std::uint16_t, std::map<std::uint8_t, Section*>> subs;
    std::map<std::uint16_t, Section*> values;    ///< [xxxxValue]
    std::map<std::uint16_t, Section*> names;     ///< [xxxxName]
    std::map<std::uint16_t, std::size_t> listed; ///< index → line in an object list
};

/// Sorts every section into the catalog by its name; reports sections codrive does not use.
void catalog_sections(IniFile& ini, Catalog& cat, Findings& findings);
/// Reads [MandatoryObjects], [OptionalObjects] and [ManufacturerObjects] into cat.listed.
void parse_lists(IniFile& ini, Catalog& cat, Findings& findings);

/// ObjectType of an object section (VAR when absent); nullopt (with an error) if invalid.
[[nodiscard]] std::optional<ObjectCode> object_code(Section& s, Findings& findings);
/// The value text kept for display, for writing and for $NODEID re-evaluation: a number's
/// trailing `; comment` dropped (as number_text()), string text whole.
[[nodiscard]] std::string stored_text(const Section& s, Entry& e, DataType type, Findings& f);
/// Reads a value key (DefaultValue, ParameterValue, LowLimit, HighLimit, [xxxxValue] entries)
/// for `type`; nullopt with an error finding if it cannot be read.
[[nodiscard]] std::optional<Value> value_key(Section& s, Entry& e, DataType type,
                                             Findings& findings, std::optional<NodeId> node);
/// Parses the keys describing one value (a VAR object section, a sub-object section, or the
/// template of a CompactSubObj array). False (with an error) when it cannot be represented.
bool parse_sub(Section& s, SubObject& sub, bool read_name, std::optional<DataType> fallback,
               Findings& findings, std::optional<NodeId> node);

/// Parses the DeviceInfo/FileInfo/DummyUsage/Comments/DeviceComissioning sections.
void parse_header_sections(IniFile& ini, DeviceDescription& desc, Findings& findings);

/// Parses the object lists and object sections into desc.od.
void parse_objects(IniFile& ini, DeviceDescription& desc, Findings& findings);

} // namespace codrive::eds
