// SPDX-License-Identifier: Apache-2.0
// Frame construction, validation and candump-style text.
#include <codrive/core/frame.hpp>

#include <algorithm>
#include <array>
#include <cstring>
#include <fmt/format.h>

namespace codrive {
namespace {
constexpr std::array<std::uint8_t, 16> kFdLengths{0, 1, 2, 3, 4, 5, 6, 7, 8, 12, 16, 20, 24, 32,
                                                  48, 64};
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

std::size_t fd_dlc_to_len(std::uint8_t dlc) { return kFdLengths[dlc & 0x0F]; }

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

} // namespace codrive
