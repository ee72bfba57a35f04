// SPDX-License-Identifier: Apache-2.0
// Frame construction, validation and candump-style text.
#include <codrive/core/frame.hpp>

#include "hex_digit.hpp"

#include <algorithm>
#include <array>
#include <cstring>
#include <fmt/format.h>

namespace codrive {
namespace {
constexpr std::array<std::uint8_t, 16> kFdLengths{0, 1,  2,  3,  4,  5,  6,  7,
                                                  8, 12, 16, 20, 24, 32, 48, 64};
} // namespace

Frame Frame::make(std::uint32_t id, std::span<const std::uint8_t> bytes) {
    Frame f;
    f.id = id;
    f.len = static_cast<std::uint8_t>(std::min(bytes.size(), kMaxClassicLen));
    std::copy_n(bytes.begin(), f.len, f.data.begin());
    return f;
}

Frame Frame::make(std::uint32_t id, std::initializer_list<std::uint8_t> bytes) {
    return make(id, std::span<const std::uint8_t>(bytes.begin(), bytes.size()));
}

Frame Frame::make_rtr(std::uint32_t id, std::uint8_t len) {
    Frame f;
    f.id = id;
    f.len = std::min<std::uint8_t>(len, 8);
    f.flags = kRtr;
    return f;
}

bool Frame::valid() const {
    const std::uint32_t mask = extended() ? kExtMask : kStdMask;
    if ((id & ~mask) != 0 && !error()) {
        return false;
    }
    if (fd()) {
        if (rtr() || len > kMaxFdLen) {
            return false;
        }
        return std::find(kFdLengths.begin(), kFdLengths.end(), len) != kFdLengths.end();
    }
    return len <= kMaxClassicLen;
}

bool operator==(const Frame& a, const Frame& b) {
    if (a.id != b.id || a.len != b.len || a.flags != b.flags) {
        return false;
    }
    if (a.rtr()) {
        return true;
    }
    return std::memcmp(a.data.data(), b.data.data(), a.len) == 0;
}

std::uint8_t fd_len_to_dlc(std::size_t len) {
    for (std::size_t i = 0; i < kFdLengths.size(); ++i) {
        if (kFdLengths[i] >= len) {
            return static_cast<std::uint8_t>(i);
        }
    }
    return 15;
}

std::size_t fd_dlc_to_len(std::uint8_t dlc) {
    return kFdLengths[dlc & 0x0F];
}

std::string to_string(const Frame& f) {
    std::string out = f.extended() || f.error() ? fmt::format("{:08X}", f.id & Frame::kExtMask)
                                                : fmt::format("{:03X}", f.id);
    if (f.fd()) {
        out += fmt::format("##{:X}", (f.flags & Frame::kBrs) != 0 ? 1 : 0);
    } else {
        out += '#';
    }
    if (f.rtr()) {
        out += 'R';
        if (f.len > 0) {
            out += fmt::format("{}", f.len);
        }
        return out;
    }
    for (std::size_t i = 0; i < f.len; ++i) {
        out += fmt::format("{:02X}", f.data[i]);
    }
    return out;
}

bool parse_frame(std::string_view text, Frame& out) {
    const std::size_t hash = text.find('#');
    if (hash == std::string_view::npos || hash == 0 || (hash != 3 && hash != 8)) {
        return false;
    }
    Frame f;
    std::uint32_t id = 0;
    for (std::size_t i = 0; i < hash; ++i) {
        const int d = detail::hex_digit(text[i]);
        if (d < 0) {
            return false;
        }
        id = (id << 4) | static_cast<std::uint32_t>(d);
    }
    f.id = id;
    if (hash == 8) {
        f.flags |= Frame::kExtended;
    }
    std::string_view rest = text.substr(hash + 1);
    std::size_t max_len = Frame::kMaxClassicLen;
    if (!rest.empty() && rest[0] == '#') {
        // CAN FD: "##<flags nibble><data>"
        if (rest.size() < 2 || detail::hex_digit(rest[1]) < 0) {
            return false;
        }
        f.flags |= Frame::kFd;
        if ((detail::hex_digit(rest[1]) & 0x1) != 0) {
            f.flags |= Frame::kBrs;
        }
        rest.remove_prefix(2);
        max_len = Frame::kMaxFdLen;
    } else if (!rest.empty() && (rest[0] == 'R' || rest[0] == 'r')) {
        f.flags |= Frame::kRtr;
        if (rest.size() == 2 && rest[1] >= '0' && rest[1] <= '8') {
            f.len = static_cast<std::uint8_t>(rest[1] - '0');
        } else if (rest.size() != 1) {
            return false;
        }
        if (!f.valid()) {
            return false;
        }
        out = f;
        return true;
    }
    std::size_t len = 0;
    for (std::size_t i = 0; i < rest.size();) {
        if (rest[i] == '.') {
            ++i;
            continue;
        }
        if (i + 1 >= rest.size()) {
            return false;
        }
        const int hi = detail::hex_digit(rest[i]);
        const int lo = detail::hex_digit(rest[i + 1]);
        if (hi < 0 || lo < 0 || len >= max_len) {
            return false;
        }
        f.data[len++] = static_cast<std::uint8_t>(hi * 16 + lo);
        i += 2;
    }
    f.len = static_cast<std::uint8_t>(len);
    if (!f.valid()) {
        return false;
    }
    out = f;
    return true;
}

} // namespace codrive
