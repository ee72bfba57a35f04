// SPDX-License-Identifier: Apache-2.0
// EMCY message codec and its sentence (CiA 301 §7.2.7.3.1).
#include <codrive/core/endian.hpp>
#include <codrive/emcy/error_codes.hpp>
#include <codrive/emcy/error_register.hpp>
#include <codrive/emcy/message.hpp>
#include <codrive/emcy/text_provider.hpp>

#include <fmt/format.h>

namespace codrive::emcy {

Result<EmcyMessage> parse_emcy(const Frame& frame, NodeId node) {
    if (frame.rtr() || frame.extended() || frame.error() || frame.len < 3) {
        return fail(CoreErrc::InvalidFrame);
    }
    EmcyMessage m;
    m.node = node;
    m.error_code = get_le<std::uint16_t>(frame.data.data());
    m.error_register = frame.data[2];
    m.length = std::min<std::uint8_t>(frame.len, 8);
    for (std::size_t i = 0; i < m.manufacturer.size(); ++i) {
        m.manufacturer[i] = 3 + i < m.length ? frame.data[3 + i] : std::uint8_t{0};
    }
    return m;
}

Result<EmcyMessage> parse_emcy(const Frame& frame) {
    // 080h itself is SYNC; EMCY of node n is 080h + n.
    if (frame.id <= cob::kEmcy || frame.id > cob::kEmcy + kMaxNodeId) {
        return fail(CoreErrc::InvalidFrame);
    }
    return parse_emcy(frame, static_cast<NodeId>(frame.id - cob::kEmcy));
}

Frame make_emcy_frame(const EmcyMessage& message, std::uint32_t cob_id) {
    Frame f;
    f.id = cob_id != 0 ? cob_id : cob::emcy(message.node);
    f.len = 8;
    put_le<std::uint16_t>(f.data.data(), message.error_code);
    f.data[2] = message.error_register;
    for (std::size_t i = 0; i < message.manufacturer.size(); ++i) {
        f.data[3 + i] = message.manufacturer[i];
    }
    return f;
}

std::string describe(const EmcyMessage& m, const IEmcyTextProvider* vendor) {
    std::string text = error_code_text(m.error_code);
    if (vendor != nullptr) {
        if (auto v = vendor->vendor_text(m); v && !v->empty()) {
            text += ": ";
            text += *v;
        }
    }
    const auto& b = m.manufacturer;
    std::string out = fmt::format(
        "node {}: EMCY 0x{:04X} {} (error register 0x{:02X}: {}) [manufacturer {:02X} {:02X} "
        "{:02X} {:02X} {:02X}]",
        m.node, m.error_code, text, m.error_register, describe_error_register(m.error_register),
        b[0], b[1], b[2], b[3], b[4]);
    if (m.length < 8) {
        out += fmt::format(" (short frame: {} bytes)", m.length);
    }
    return out;
}

} // namespace codrive::emcy
