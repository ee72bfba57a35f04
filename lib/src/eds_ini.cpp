// SPDX-License-Identifier: Apache-2.0
// Tokenizer for the INI syntax of EDS/DCF files: sections, keys, comments.
#include "eds_internal.hpp"

#include <fmt/format.h>

#include <cctype>

namespace codrive::eds {

std::string to_lower(std::string_view s) {
    std::string out(s);
    for (char& c : out) {
        c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    }
    return out;
}

bool iequals(std::string_view a, std::string_view b) {
    if (a.size() != b.size()) {
        return false;
    }
    for (std::size_t i = 0; i < a.size(); ++i) {
        if (std::tolower(static_cast<unsigned char>(a[i])) !=
            std::tolower(static_cast<unsigned char>(b[i]))) {
            return false;
        }
    }
    return true;
}

std::string_view trim(std::string_view s) {
    while (!s.empty() && std::isspace(static_cast<unsigned char>(s.front())) != 0) {
        s.remove_prefix(1);
    }
    while (!s.empty() && std::isspace(static_cast<unsigned char>(s.back())) != 0) {
        s.remove_suffix(1);
    }
    return s;
}

Entry* Section::find(std::string_view key) {
    auto it = keys.find(to_lower(key));
    if (it == keys.end()) {
        return nullptr;
    }
    Entry& e = entries[it->second];
    e.used = true;
    return &e;
}

std::string_view number_text(const Section& s, Entry& e, Findings& findings) {
    const std::size_t semi = e.value.find(';');
    if (semi == std::string::npos) {
        return e.value;
    }
    if (!e.comment_reported) {
        e.comment_reported = true;
        findings.warning(e.line, fmt::format("[{}] {}: trailing comment '{}' ignored (CiA 306 "
                                             "comments take a whole line)",
                                             s.name, e.key, e.value.substr(semi, 40)));
    }
    return trim(std::string_view(e.value).substr(0, semi));
}

Section* IniFile::find(std::string_view lower_name) {
    auto it = by_name.find(std::string(lower_name));
    return it == by_name.end() ? nullptr : &sections[it->second];
}

namespace {

// Printable form of a line for messages: bounded and without control characters.
std::string excerpt(std::string_view s) {
    constexpr std::size_t kMax = 40;
    std::string out;
    for (char c : s.substr(0, kMax)) {
        out += std::iscntrl(static_cast<unsigned char>(c)) != 0 ? '?' : c;
    }
    if (s.size() > kMax) {
        out += "...";
    }
    return out;
}

} // namespace

IniFile tokenize(std::string_view text, Findings& findings) {
    IniFile ini;
    // A UTF-8 byte order mark is written by some Windows editors; it is not part of the text.
    if (text.substr(0, 3) == "\xEF\xBB\xBF") {
        text.remove_prefix(3);
    }
    Section* current = nullptr;
    bool in_bad_section = false; // keys after a malformed header were already reported with it
    std::size_t line_no = 0;
    std::size_t pos = 0;
    while (pos < text.size()) {
        std::size_t end = text.find_first_of("\r\n", pos);
        if (end == std::string_view::npos) {
            end = text.size();
        }
        const std::string_view raw = text.substr(pos, end - pos);
        // \r\n, \n and a lone \r all end a line.
        pos = end;
        if (pos < text.size()) {
            pos += (text[pos] == '\r' && pos + 1 < text.size() && text[pos + 1] == '\n') ? 2 : 1;
        }
        ++line_no;
        const std::string_view line = trim(raw);
        if (line.empty() || line.front() == ';') {
            continue; // CiA 306: comment lines start with ';'
        }
        if (line.front() == '[') {
            if (line.back() != ']') {
                findings.error(line_no, fmt::format("malformed section header '{}' (no closing "
                                                    "']'); its keys are ignored",
                                                    excerpt(line)));
                current = nullptr;
                in_bad_section = true;
                continue;
            }
            const std::string_view name = trim(line.substr(1, line.size() - 2));
            if (name.empty()) {
                findings.error(line_no, "empty section name '[]'; its keys are ignored");
                current = nullptr;
                in_bad_section = true;
                continue;
            }
            in_bad_section = false;
            std::string lower = to_lower(name);
            auto it = ini.by_name.find(lower);
            if (it != ini.by_name.end()) {
                current = &ini.sections[it->second];
                findings.warning(line_no,
                                 fmt::format("duplicate section [{}] (first at line {}); its "
                                             "keys are merged into the first",
                                             excerpt(name), current->line));
                continue;
            }
            ini.by_name.emplace(lower, ini.sections.size());
            ini.sections.push_back(Section{std::string(name), std::move(lower), line_no, {}, {}});
            current = &ini.sections.back();
            continue;
        }
        const std::size_t eq = line.find('=');
        if (eq == std::string_view::npos) {
            findings.error(line_no, fmt::format("line '{}' is neither a [section], a key=value "
                                                "nor a ;comment",
                                                excerpt(line)));
            continue;
        }
        const std::string_view key = trim(line.substr(0, eq));
        const std::string_view value = trim(line.substr(eq + 1));
        if (key.empty()) {
            findings.error(line_no, fmt::format("line '{}' has no key before '='", excerpt(line)));
            continue;
        }
        if (current == nullptr) {
            if (in_bad_section) {
                continue;
            }
            findings.error(line_no, fmt::format("key '{}' is outside any section", excerpt(key)));
            continue;
        }
        std::string lower_key = to_lower(key);
        auto known = current->keys.find(lower_key);
        if (known != current->keys.end()) {
            const Entry* first = &current->entries[known->second];
            if (first->value == value) {
                findings.warning(line_no, fmt::format("[{}] key '{}' repeated (first at line {})",
                                                      current->name, excerpt(key), first->line));
            } else {
                findings.warning(line_no, fmt::format("[{}] duplicate key '{}' (first at line {}); "
                                                      "keeping the first value '{}', ignoring '{}'",
                                                      current->name, excerpt(key), first->line,
                                                      excerpt(first->value), excerpt(value)));
            }
            continue;
        }
        current->keys.emplace(std::move(lower_key), current->entries.size());
        current->entries.push_back(Entry{std::string(key), std::string(value), line_no});
    }
    return ini;
}

} // namespace codrive::eds
