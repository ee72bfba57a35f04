// SPDX-License-Identifier: Apache-2.0
// vcan availability check for the vcan test suite.
#include <codrive/testing/vcan.hpp>

#include <codrive/core/socket_can_bus.hpp>

#include <cstdlib>
#include <string_view>

namespace codrive::testing {

bool vcan_available(const std::string& ifname) {
    auto bus = SocketCanBus::open(ifname);
    return bus.has_value();
}

bool vcan_skip_requested() {
    const char* v = std::getenv("CODRIVE_SKIP_VCAN");
    return v != nullptr && std::string_view(v) == "1";
}

} // namespace codrive::testing
