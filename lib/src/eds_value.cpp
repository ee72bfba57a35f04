// SPDX-License-Identifier: Apache-2.0
// Number and value text of EDS/DCF files: $NODEID expressions, octal, quoted strings, reals.
#include "eds_internal.hpp"
#include "hex_digit.hpp"

#include <fmt/format.h>

#include <cctype>
#include <limits>

namespace codrive::eds {
namespace {

constexpr std::string_view kNodeId = "$NODEID";

bool is_space(char c) {
    return std::isspace(static_cast<unsigned char>(c)) != 0;
}

std::string printable(std::string_view s) {
    std::string out;
    for (char c : s.substr(0, 40)) {
        out += std::iscntrl(static_cast<unsigned char>(c)) != 0 ? '?' : c;
    }
    if (s.size() > 40) {
        out += "...";
    }
    return out;
}

// Adds two sign-magnitude integers; nullopt on overflow of the 64-bit magnitude.
std::optional<Integer> add(Integer a, Integer b) {
    Integer r;
    if (a.negative == b.negative) {
        if (a.magnitude > std::numeric_limits<std::uint64_t>::max() - b.magnitude) {
            return std::nullopt;
        }
        r = {a.negative, a.magnitude + b.magnitude};
    } else if (a.magnitude >= b.magnitude) {
        r = {a.negative, a.magnitude - b.magnitude};
    } else {
        r = {b.negative, b.magnitude - a.magnitude};
    }
    if (r.magnitude == 0) {
        r.negative = false;
    }
    return r;
}

std::uint64_t umax(std::size_t bytes) {
    return bytes >= 8 ? std::numeric_limits<std::uint64_t>::max()
                      : (std::uint64_t{1} << (8 * bytes)) - 1;
}

// Reads one literal at s[i...]; advances i. Leading-zero numbers are octal as in C.
std::optional<std::uint64_t> read_literal(std::string_view s, std::size_t& i, IntegerText& out,
                                          bool& was_hex) {
    const std::size_t start = i;
    unsigned base = 10;
    was_hex = false;
    if (i + 1 < s.size() && s[i] == '0' && (s[i + 1] == 'x' || s[i + 1] == 'X')) {
        base = 16;
        i += 2;
        was_hex = true;
    }
    const std::size_t digits_start = i;
    while (i < s.size() && codrive::detail::hex_digit(s[i]) >= 0 &&
           (base == 16 || codrive::detail::hex_digit(s[i]) < 10)) {
        ++i;
    }
    const std::string_view digits = s.substr(digits_start, i - digits_start);
    if (digits.empty()) {
        out.error = base == 16 ? "has no digits after 0x" : "is not a number";
        return std::nullopt;
    }
    if (base == 10 && digits.size() > 1 && digits[0] == '0') {
        bool octal = true;
        for (char c : digits) {
            octal = octal && c < '8';
        }
        if (octal) {
            base = 8;
        }
        std::uint64_t dec = 0;
        for (char c : digits) {
            dec = dec * 10 + static_cast<std::uint64_t>(c - '0');
            if (dec > 1'000'000'000'000ULL) {
                break; // only for the message; the real value is computed below
            }
        }
        out.notes.push_back(
            octal ? fmt::format("'{}' has a leading zero and is read as octal (CiA 306, like "
                                "strtoul); write 0x... or drop the zero if decimal was meant",
                                printable(s.substr(start, i - start)))
                  : fmt::format("'{}' has a leading zero but is not octal; read as decimal",
                                printable(s.substr(start, i - start))));
    }
    std::uint64_t v = 0;
    for (char c : digits) {
        const auto d = static_cast<std::uint64_t>(codrive::detail::hex_digit(c));
        if (v > (std::numeric_limits<std::uint64_t>::max() - d) / base) {
            out.error = "is too large for 64 bits";
            return std::nullopt;
        }
        v = v * base + d;
    }
    if (was_hex) {
        out.hex_digits = digits.size();
    }
    return v;
}

std::string unescape_quoted(std::string_view s) {
    std::string out;
    for (std::size_t i = 0; i < s.size(); ++i) {
        if (s[i] != '\\' || i + 1 >= s.size()) {
            out += s[i];
            continue;
        }
        const char c = s[++i];
        switch (c) {
        case 'n':
            out += '\n';
            break;
        case 'r':
            out += '\r';
            break;
        case 't':
            out += '\t';
            break;
        case 'x':
            if (i + 2 < s.size() && codrive::detail::hex_digit(s[i + 1]) >= 0 &&
                codrive::detail::hex_digit(s[i + 2]) >= 0) {
                out += static_cast<char>(codrive::detail::hex_digit(s[i + 1]) * 16 +
                                         codrive::detail::hex_digit(s[i + 2]));
                i += 2;
            } else {
                out += "\\x";
            }
            break;
        default:
            out += c; // \\ and \" and anything else: the character itself
            break;
        }
    }
    return out;
}

ValueText integer_value(DataType type, std::string_view text, std::optional<NodeId> node) {
    ValueText out;
    if (type == DataType::Boolean) {
        if (iequals(text, "true")) {
            out.value = Value::from_uint(type, 1).value();
            return out;
        }
        if (iequals(text, "false")) {
            out.value = Value::from_uint(type, 0).value();
            return out;
        }
    }
    IntegerText it = parse_integer(text, node);
    out.notes = std::move(it.notes);
    out.uses_node_id = it.uses_node_id;
    if (!it.value) {
        out.error = fmt::format("'{}' {}", printable(text), it.error);
        return out;
    }
    const std::size_t n = data_type_size(type);
    const Integer v = *it.value;
    Result<Value> r = fail(CoreErrc::OutOfRange);
    if (is_signed_integer(type) && it.plain_hex) {
        // Hex for a signed type is the bit pattern: 0xFFFF for INTEGER16 is -1.
        if (v.magnitude <= umax(n)) {
            r = Value::from_int(type, sign_extend(v.magnitude, n));
        }
    } else if (v.negative) {
        constexpr auto kMinMagnitude =
            static_cast<std::uint64_t>(std::numeric_limits<std::int64_t>::max()) + 1;
        if (v.magnitude <= kMinMagnitude) {
            r = Value::from_int(type, v.magnitude == kMinMagnitude
                                          ? std::numeric_limits<std::int64_t>::min()
                                          : -static_cast<std::int64_t>(v.magnitude));
        }
    } else {
        r = Value::from_uint(type, v.magnitude);
    }
    if (!r) {
        out.error = fmt::format("'{}' is out of range for {}", printable(text), to_string(type));
        return out;
    }
    out.value = std::move(*r);
    return out;
}

ValueText real_value(DataType type, std::string_view text) {
    ValueText out;
    const std::size_t n = data_type_size(type);
    if (text.size() == 2 + 2 * n && text[0] == '0' && (text[1] == 'x' || text[1] == 'X')) {
        bool all_hex = true;
        for (char c : text.substr(2)) {
            all_hex = all_hex && codrive::detail::hex_digit(c) >= 0;
        }
        if (all_hex) {
            // Exactly 2*size hex digits: the IEEE 754 bit pattern (lely's DCFs write pi as
            // 0x40490FDB). Shorter hex text is a number, as strtod reads it.
            std::uint64_t raw = 0;
            for (char c : text.substr(2)) {
                raw = raw * 16 + static_cast<std::uint64_t>(codrive::detail::hex_digit(c));
            }
            Value v = Value::zero(type);
            put_le_n(v.mutable_bytes().data(), raw, n);
            out.value = std::move(v);
            return out;
        }
    }
    if (text.find('$') != std::string_view::npos) {
        out.error = fmt::format("'{}' uses $NODEID, which is not allowed for {}", printable(text),
                                to_string(type));
        return out;
    }
    auto r = Value::parse(type, text);
    if (!r) {
        out.error = fmt::format("'{}' is not a valid {} number", printable(text), to_string(type));
        return out;
    }
    out.value = std::move(*r);
    return out;
}

ValueText time_value(DataType type, std::string_view text, std::optional<NodeId> node) {
    ValueText out;
    const std::size_t sp = text.find_first_of(" \t");
    Value v = Value::zero(type);
    if (sp == std::string_view::npos) {
        IntegerText it = parse_integer(text, node);
        out.notes = std::move(it.notes);
        if (!it.value || it.value->negative || it.value->magnitude > umax(6)) {
            out.error = fmt::format("'{}' is not a valid {} (\"days ms\" or a 48-bit number)",
                                    printable(text), to_string(type));
            return out;
        }
        put_le_n(v.mutable_bytes().data(), it.value->magnitude, 6);
        out.value = std::move(v);
        return out;
    }
    // "days ms", as lely writes it (CiA 301 TIME_OF_DAY: ms in 28 bits, then days since 1984).
    IntegerText days = parse_integer(text.substr(0, sp), node);
    IntegerText ms = parse_integer(trim(text.substr(sp)), node);
    if (!days.value || !ms.value || days.value->negative || ms.value->negative ||
        days.value->magnitude > 0xFFFF || ms.value->magnitude >= (1U << 28)) {
        out.error = fmt::format("'{}' is not a valid {} (\"days ms\" with ms < 2^28)",
                                printable(text), to_string(type));
        return out;
    }
    put_le_n(v.mutable_bytes().data(), ms.value->magnitude, 4);
    put_le_n(v.mutable_bytes().data() + 4, days.value->magnitude, 2);
    out.value = std::move(v);
    return out;
}

bool needs_quotes(std::string_view s) {
    if (s.empty()) {
        return false;
    }
    if (s != trim(s)) {
        return true;
    }
    if (s.size() >= 2 && s.front() == '"' && s.back() == '"') {
        return true;
    }
    for (char c : s) {
        if (std::iscntrl(static_cast<unsigned char>(c)) != 0 && c != '\t') {
            return true;
        }
    }
    return false;
}

std::string quote(std::string_view s) {
    std::string out = "\"";
    for (char c : s) {
        switch (c) {
        case '\\':
            out += "\\\\";
            break;
        case '"':
            out += "\\\"";
            break;
        case '\n':
            out += "\\n";
            break;
        case '\r':
            out += "\\r";
            break;
        case '\t':
            out += "\\t";
            break;
        default:
            if (std::iscntrl(static_cast<unsigned char>(c)) != 0) {
                out += fmt::format("\\x{:02X}", static_cast<unsigned char>(c));
            } else {
                out += c;
            }
        }
    }
    out += '"';
    return out;
}

} // namespace

IntegerText parse_integer(std::string_view text, std::optional<NodeId> node) {
    IntegerText out;
    const std::string_view s = trim(text);
    if (s.empty()) {
        out.error = "is empty";
        return out;
    }
    Integer acc;
    std::size_t i = 0;
    std::size_t terms = 0;
    bool only_hex = false;
    auto skip_space = [&] {
        while (i < s.size() && is_space(s[i])) {
            ++i;
        }
    };
    while (true) {
        skip_space();
        bool negative = false;
        if (terms > 0) {
            if (i >= s.size() || (s[i] != '+' && s[i] != '-')) {
                out.error =
                    fmt::format("has '{}' where + or - was expected", printable(s.substr(i, 1)));
                return out;
            }
            negative = s[i] == '-';
            ++i;
            skip_space();
        }
        if (i < s.size() && (s[i] == '+' || s[i] == '-')) {
            negative = negative != (s[i] == '-');
            ++i;
            skip_space();
        }
        if (i >= s.size()) {
            out.error = "ends with an operator";
            return out;
        }
        std::uint64_t term = 0;
        bool was_hex = false;
        if (s.size() - i >= kNodeId.size() && iequals(s.substr(i, kNodeId.size()), kNodeId)) {
            term = node.value_or(0);
            out.uses_node_id = true;
            i += kNodeId.size();
        } else if (s[i] == '$') {
            out.error = "uses an unknown variable (only $NODEID is defined)";
            return out;
        } else {
            auto lit = read_literal(s, i, out, was_hex);
            if (!lit) {
                return out;
            }
            term = *lit;
        }
        if (i < s.size() && !is_space(s[i]) && s[i] != '+' && s[i] != '-') {
            out.error = fmt::format("has unexpected '{}'", printable(s.substr(i, 1)));
            return out;
        }
        auto sum = add(acc, Integer{negative, term});
        if (!sum) {
            out.error = "is too large for 64 bits";
            return out;
        }
        acc = *sum;
        only_hex = terms == 0 && was_hex && !negative;
        ++terms;
        skip_space();
        if (i >= s.size()) {
            break;
        }
    }
    out.plain_hex = terms == 1 && only_hex;
    out.value = acc;
    return out;
}

ValueText parse_value(DataType type, std::string_view text, std::optional<NodeId> node) {
    if (is_signed_integer(type) || is_unsigned_integer(type)) {
        return integer_value(type, trim(text), node);
    }
    if (is_real(type)) {
        return real_value(type, trim(text));
    }
    ValueText out;
    switch (type) {
    case DataType::VisibleString:
    case DataType::UnicodeString:
        // Quotes are lely's convention for strings with edge white space or escapes.
        if (text.size() >= 2 && text.front() == '"' && text.back() == '"') {
            out.value = Value::from_string(unescape_quoted(text.substr(1, text.size() - 2)), type);
        } else {
            out.value = Value::from_string(text, type);
        }
        return out;
    case DataType::OctetString:
    case DataType::Domain: {
        auto bytes = parse_hex_bytes(text);
        if (!bytes) {
            out.error = fmt::format("'{}' is not hex bytes (like 0A1B2C or 0A 1B 2C) as {} needs",
                                    printable(text), to_string(type));
            return out;
        }
        out.value = Value(type, std::move(*bytes));
        return out;
    }
    case DataType::TimeOfDay:
    case DataType::TimeDifference:
        return time_value(type, trim(text), node);
    default:
        out.error = fmt::format("values of {} are not supported", to_string(type));
        return out;
    }
}

bool uses_node_id(std::string_view text) {
    return to_lower(text).find("$nodeid") != std::string::npos;
}

} // namespace codrive::eds

namespace codrive {

std::string eds_value_text(const Value& v) {
    const DataType type = v.type();
    const std::size_t n = data_type_size(type);
    const auto bytes = v.bytes();
    switch (type) {
    case DataType::VisibleString:
    case DataType::UnicodeString: {
        const std::string s(bytes.begin(), bytes.end());
        return eds::needs_quotes(s) ? eds::quote(s) : s;
    }
    case DataType::OctetString:
    case DataType::Domain: {
        std::string out;
        for (auto b : bytes) {
            out += fmt::format("{:02X}", b);
        }
        return out;
    }
    default:
        break;
    }
    if (n == 0 || bytes.size() < n) {
        return {};
    }
    if (type == DataType::TimeOfDay || type == DataType::TimeDifference) {
        return fmt::format("{} {}", get_le_n(bytes.data() + 4, 2),
                           get_le_n(bytes.data(), 4) & 0x0FFFFFFF);
    }
    if (type == DataType::Real32) {
        return fmt::format("{}", get_le<float>(bytes.data()));
    }
    if (type == DataType::Real64) {
        return fmt::format("{}", get_le<double>(bytes.data()));
    }
    if (type == DataType::Boolean) {
        return bytes[0] != 0 ? "1" : "0";
    }
    if (is_signed_integer(type)) {
        return fmt::format("{}", sign_extend(get_le_n(bytes.data(), n), n));
    }
    return fmt::format("0x{:0{}X}", get_le_n(bytes.data(), n), 2 * n);
}

} // namespace codrive
