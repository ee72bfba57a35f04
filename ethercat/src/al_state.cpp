// SPDX-License-Identifier: Apache-2.0
// AL state names, allowed transitions and AL status code texts (ETG.1000.6 Tables 9 and 11).
#include <codrive/ethercat/al_state.hpp>

#include <algorithm>
#include <array>
#include <cctype>
#include <fmt/format.h>
#include <utility>

namespace codrive::ethercat {
namespace {

constexpr std::array<std::pair<std::uint16_t, std::string_view>, 47> kAlCodes{{
    {0x0000, "no error"},
    {0x0001, "unspecified error"},
    {0x0002, "no memory"},
    {0x0003, "invalid device setup"},
    {0x0011, "invalid requested state change"},
    {0x0012, "unknown requested state"},
    {0x0013, "bootstrap not supported"},
    {0x0014, "no valid firmware"},
    {0x0015, "invalid mailbox configuration (BOOT)"},
    {0x0016, "invalid mailbox configuration (PRE-OP)"},
    {0x0017, "invalid sync manager configuration"},
    {0x0018, "no valid inputs available"},
    {0x0019, "no valid outputs"},
    {0x001A, "synchronization error"},
    {0x001B, "sync manager watchdog"},
    {0x001C, "invalid sync manager types"},
    {0x001D, "invalid output configuration"},
    {0x001E, "invalid input configuration"},
    {0x001F, "invalid watchdog configuration"},
    {0x0020, "slave needs cold start"},
    {0x0021, "slave needs INIT"},
    {0x0022, "slave needs PRE-OP"},
    {0x0023, "slave needs SAFE-OP"},
    {0x0024, "invalid input mapping"},
    {0x0025, "invalid output mapping"},
    {0x0026, "inconsistent settings"},
    {0x0027, "free-run not supported"},
    {0x0028, "synchronization mode not supported"},
    {0x0029, "free-run needs 3-buffer mode"},
    {0x002A, "background watchdog"},
    {0x002B, "no valid inputs and outputs"},
    {0x002C, "fatal sync error"},
    {0x002D, "no sync error"},
    {0x0030, "invalid DC SYNC configuration"},
    {0x0031, "invalid DC latch configuration"},
    {0x0032, "PLL error"},
    {0x0033, "DC sync IO error"},
    {0x0034, "DC sync timeout error"},
    {0x0035, "DC invalid sync cycle time"},
    {0x0036, "DC SYNC0 cycle time"},
    {0x0037, "DC SYNC1 cycle time"},
    {0x0041, "mailbox AoE error"},
    {0x0042, "mailbox EoE error"},
    {0x0043, "mailbox CoE error"},
    {0x0044, "mailbox FoE error"},
    {0x0050, "EEPROM no access"},
    {0x0051, "EEPROM error"},
}};

} // namespace

std::string to_string(AlState s) {
    switch (s) {
    case AlState::Init:
        return "INIT";
    case AlState::PreOp:
        return "PRE-OP";
    case AlState::Boot:
        return "BOOT";
    case AlState::SafeOp:
        return "SAFE-OP";
    case AlState::Op:
        return "OP";
    case AlState::None:
        return "NONE";
    }
    return fmt::format("state 0x{:X}", static_cast<unsigned>(s));
}

std::optional<AlState> al_state_from_bits(std::uint16_t bits) {
    switch (bits & 0x0F) {
    case 0x01:
        return AlState::Init;
    case 0x02:
        return AlState::PreOp;
    case 0x03:
        return AlState::Boot;
    case 0x04:
        return AlState::SafeOp;
    case 0x08:
        return AlState::Op;
    default:
        return std::nullopt;
    }
}

std::optional<AlState> al_state_from_string(std::string_view text) {
    std::string t;
    for (char c : text) {
        if (c != '-' && c != '_') {
            t.push_back(static_cast<char>(std::tolower(static_cast<unsigned char>(c))));
        }
    }
    if (t == "init") {
        return AlState::Init;
    }
    if (t == "preop") {
        return AlState::PreOp;
    }
    if (t == "safeop") {
        return AlState::SafeOp;
    }
    if (t == "op") {
        return AlState::Op;
    }
    if (t == "boot") {
        return AlState::Boot;
    }
    return std::nullopt;
}

bool transition_allowed(AlState from, AlState to) {
    if (from == to) {
        return true;
    }
    if (from == AlState::Boot) {
        return to == AlState::Init;
    }
    if (to == AlState::Boot) {
        return from == AlState::Init;
    }
    if (to == AlState::Init) {
        return true;
    }
    const auto rank = [](AlState s) {
        switch (s) {
        case AlState::Init:
            return 0;
        case AlState::PreOp:
            return 1;
        case AlState::SafeOp:
            return 2;
        case AlState::Op:
            return 3;
        default:
            return -10;
        }
    };
    const int a = rank(from);
    const int b = rank(to);
    if (a < 0 || b < 0) {
        return false;
    }
    return b < a || b == a + 1;
}

std::optional<std::string_view> al_status_code_text(std::uint16_t code) {
    const auto* it = std::find_if(kAlCodes.begin(), kAlCodes.end(),
                                  [code](const auto& e) { return e.first == code; });
    if (it == kAlCodes.end()) {
        return std::nullopt;
    }
    return it->second;
}

std::string_view al_status_code_describe(std::uint16_t code) {
    if (auto t = al_status_code_text(code)) {
        return *t;
    }
    if (code >= 0x8000) {
        return "vendor-specific AL status code";
    }
    return "unknown AL status code";
}

} // namespace codrive::ethercat
