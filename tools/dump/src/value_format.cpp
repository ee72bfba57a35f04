// SPDX-License-Identifier: Apache-2.0
// Typed value text for the decoder.
#include <codrive/dump/value_format.hpp>

#include <codrive/core/endian.hpp>
#include <codrive/core/value.hpp>
#include <codrive/drives/cia402.hpp>
#include <codrive/dump/text_append.hpp>

#include <array>
#include <cstring>
#include <iterator>
#include <string>

namespace codrive::dump {
namespace {

constexpr char kHexDigits[] = "0123456789ABCDEF";

void format_string(fmt::memory_buffer& out, std::span<const std::uint8_t> data) {
    constexpr std::size_t kMax = 64;
    out.push_back('"');
    std::size_t n = 0;
    for (std::uint8_t c : data) {
        if (c == 0 && n + 1 == data.size()) {
            break; // a terminating NUL is common and carries no meaning
        }
        if (n++ == kMax) {
            out.push_back('"');
            text::put(out, "…");
            return;
        }
        if (c == '"' || c == '\\') {
            out.push_back('\\');
            out.push_back(static_cast<char>(c));
        } else if (c >= 0x20 && c < 0x7F) {
            out.push_back(static_cast<char>(c));
        } else {
            const char esc[4] = {'\\', 'x', kHexDigits[c >> 4], kHexDigits[c & 0xF]};
            out.append(esc, esc + 4);
        }
    }
    out.push_back('"');
}

bool printable(std::span<const std::uint8_t> data) {
    if (data.size() < 2) {
        return false;
    }
    for (std::size_t i = 0; i < data.size(); ++i) {
        const auto c = data[i];
        if (c == 0 && i + 1 == data.size()) {
            continue;
        }
        if (c < 0x20 || c >= 0x7F) {
            return false;
        }
    }
    return true;
}

void format_unsigned_hex(fmt::memory_buffer& out, std::uint64_t v, std::size_t bytes) {
    std::array<char, 18> buf{};
    buf[0] = '0';
    buf[1] = 'x';
    const std::size_t digits = bytes * 2;
    for (std::size_t i = 0; i < digits; ++i) {
        buf[2 + digits - 1 - i] = kHexDigits[(v >> (4 * i)) & 0xF];
    }
    out.append(buf.data(), buf.data() + 2 + digits);
}

std::string_view command_text(std::uint16_t cw) {
    using namespace drives::cia402;
    const auto c = decode_command(cw);
    return c ? to_string(*c) : std::string_view("no command");
}

} // namespace

void format_hex_bytes(fmt::memory_buffer& out, std::span<const std::uint8_t> data,
                      std::size_t max) {
    for (std::size_t i = 0; i < data.size(); ++i) {
        if (i == max) {
            text::put(out, " …");
            return;
        }
        if (i != 0) {
            out.push_back(' ');
        }
        out.push_back(kHexDigits[data[i] >> 4]);
        out.push_back(kHexDigits[data[i] & 0xF]);
    }
}

void format_value(fmt::memory_buffer& out, const ObjectInfo& info,
                  std::span<const std::uint8_t> data) {
    auto it = std::back_inserter(out);
    if (info.type_known) {
        const DataType t = info.type;
        const std::size_t size = data_type_size(t);
        if (t == DataType::VisibleString || t == DataType::UnicodeString) {
            format_string(out, data);
            return;
        }
        if (t == DataType::OctetString || t == DataType::Domain) {
            if (data.empty()) {
                text::put(out, "(empty)");
            } else {
                format_hex_bytes(out, data);
            }
            return;
        }
        if (size != 0 && size == data.size() && size <= 8) {
            const std::uint64_t raw = get_le_n(data.data(), size);
            if (t == DataType::Real32) {
                fmt::format_to(it, "{}", get_le<float>(data.data()));
            } else if (t == DataType::Real64) {
                fmt::format_to(it, "{}", get_le<double>(data.data()));
            } else if (t == DataType::Boolean) {
                text::put(out, raw != 0 ? "true" : "false");
            } else if (is_signed_integer(t)) {
                fmt::format_to(it, "{}", sign_extend(raw, size));
            } else if (info.hex) {
                format_unsigned_hex(out, raw, size);
            } else {
                fmt::format_to(it, "{}", raw);
            }
            return;
        }
    }
    if (!data.empty() && data.size() <= 8 && !printable(data)) {
        const std::uint64_t raw = get_le_n(data.data(), data.size());
        format_unsigned_hex(out, raw, data.size());
        fmt::format_to(it, " ({})", raw);
        return;
    }
    if (printable(data)) {
        format_string(out, data);
        return;
    }
    if (data.empty()) {
        text::put(out, "(empty)");
        return;
    }
    format_hex_bytes(out, data);
}

void format_cia402_meaning(fmt::memory_buffer& out, std::uint16_t index, std::uint64_t raw) {
    if (index < 0x6000 || index >= 0xA000) {
        return;
    }
    const auto base = static_cast<std::uint16_t>(0x6000U + (index - 0x6000U) % 0x800U);
    using namespace drives::cia402;
    switch (base) {
    case obj::kControlword:
        text::put(out, " (");
        text::put(out, command_text(static_cast<std::uint16_t>(raw)));
        out.push_back(')');
        break;
    case obj::kStatusword: {
        const auto sw16 = static_cast<std::uint16_t>(raw);
        text::put(out, " (");
        text::put(out, to_string(decode_state(sw16)));
        if ((sw16 & sw::kWarning) != 0) {
            text::put(out, ", warning");
        }
        if ((sw16 & sw::kTargetReached) != 0) {
            text::put(out, ", target reached");
        }
        out.push_back(')');
        break;
    }
    case obj::kModesOfOperation:
    case obj::kModesOfOperationDisplay: {
        static const auto names = [] {
            std::array<std::string, 256> n;
            for (int m = -128; m < 128; ++m) {
                n[static_cast<std::size_t>(m + 128)] = mode_name(static_cast<std::int8_t>(m));
            }
            return n;
        }();
        const auto m = static_cast<std::int8_t>(static_cast<std::uint8_t>(raw));
        text::put(out, " (");
        text::put(out, names[static_cast<std::size_t>(m + 128)]);
        out.push_back(')');
        break;
    }
    default:
        break;
    }
}

} // namespace codrive::dump
