// SPDX-License-Identifier: Apache-2.0
// Helpers for the EDS/DCF tests: fixture paths, finding lookup, dictionary comparison.
#pragma once

#include <codrive/core/eds.hpp>

#include <gtest/gtest.h>

#include <fmt/format.h>

#include <optional>
#include <string>
#include <string_view>

namespace codrive::eds_test {

inline std::string data_path(const std::string& relative) {
    return std::string(CODRIVE_SOURCE_DIR) + "/tests/data/eds/" + relative;
}

/// Loads a fixture; a file that cannot be read fails the test.
inline DeviceDescription load(const std::string& relative, std::optional<NodeId> node = {}) {
    auto d = load_eds(data_path(relative), node);
    EXPECT_TRUE(d.has_value()) << relative << ": " << (d ? "" : d.error().message());
    return d ? std::move(*d) : DeviceDescription{};
}

/// All findings, one per line, for failure messages.
inline std::string dump(const DeviceDescription& d) {
    std::string out;
    for (const auto& f : d.findings) {
        out += format_finding(f) + "\n";
    }
    return out;
}

/// The finding of this severity on this line whose message contains `text`, or nullptr.
inline const EdsFinding* find(const DeviceDescription& d, EdsSeverity s, std::size_t line,
                              std::string_view text) {
    for (const auto& f : d.findings) {
        if (f.severity == s && f.line == line && f.message.find(text) != std::string::npos) {
            return &f;
        }
    }
    return nullptr;
}

inline std::string show(const std::optional<Value>& v) {
    return v ? fmt::format("{}:{}", to_string(v->type()), v->to_string()) : "none";
}

/// Expects two dictionaries to hold the same objects and sub-objects. `texts` also compares
/// default_text and parameter_text (false when the first was built in code).
inline void expect_same_dictionary(const ObjectDictionary& a, const ObjectDictionary& b,
                                   bool texts = true) {
    ASSERT_EQ(a.size(), b.size());
    for (const auto& [index, oa] : a.objects()) {
        const Object* ob = b.find(index);
        ASSERT_NE(ob, nullptr) << fmt::format("object 0x{:04X} missing", index);
        const std::string at = fmt::format("0x{:04X}", index);
        EXPECT_EQ(oa.name, ob->name) << at;
        EXPECT_EQ(oa.code, ob->code) << at;
        EXPECT_EQ(oa.obj_flags, ob->obj_flags) << at;
        ASSERT_EQ(oa.subs.size(), ob->subs.size()) << at;
        for (const auto& [si, sa] : oa.subs) {
            const SubObject* sb = ob->find(si);
            const std::string where = fmt::format("0x{:04X}:{:02X}", index, si);
            ASSERT_NE(sb, nullptr) << where;
            EXPECT_EQ(sa.subindex, sb->subindex) << where;
            EXPECT_EQ(sa.name, sb->name) << where;
            EXPECT_EQ(sa.type, sb->type) << where;
            EXPECT_EQ(sa.access, sb->access) << where;
            EXPECT_EQ(sa.pdo_mappable, sb->pdo_mappable) << where;
            EXPECT_EQ(sa.obj_flags, sb->obj_flags) << where;
            EXPECT_TRUE(sa.value == sb->value)
                << where << ": " << show(sa.value) << " vs " << show(sb->value);
            EXPECT_TRUE(sa.default_value == sb->default_value)
                << where << ": " << show(sa.default_value) << " vs " << show(sb->default_value);
            EXPECT_TRUE(sa.low_limit == sb->low_limit)
                << where << ": " << show(sa.low_limit) << " vs " << show(sb->low_limit);
            EXPECT_TRUE(sa.high_limit == sb->high_limit)
                << where << ": " << show(sa.high_limit) << " vs " << show(sb->high_limit);
            if (texts) {
                EXPECT_EQ(sa.default_text, sb->default_text) << where;
                EXPECT_EQ(sa.parameter_text, sb->parameter_text) << where;
            }
        }
    }
}

/// A minimal valid EDS head (FileInfo, DeviceInfo, lists naming `indexes`) for inline tests.
inline std::string eds_head(std::initializer_list<std::uint16_t> indexes) {
    std::string out = "[FileInfo]\nFileName=t.eds\nEDSVersion=4.0\n[DeviceInfo]\nVendorName=t\n"
                      "[OptionalObjects]\n";
    out += fmt::format("SupportedObjects={}\n", indexes.size());
    std::size_t i = 1;
    for (auto idx : indexes) {
        out += fmt::format("{}=0x{:04X}\n", i++, idx);
    }
    return out;
}

} // namespace codrive::eds_test
