// SPDX-License-Identifier: Apache-2.0
// Guard for tests that need real vcan interfaces: fail loudly unless skipping was requested.
#pragma once

#include <string>

namespace codrive::testing {

/// True if `ifname` exists and a CAN raw socket can bind to it.
bool vcan_available(const std::string& ifname = "vcan0");

/// Call at the top of every vcan test: if vcan is missing the test FAILS with an explanation,
/// unless CODRIVE_SKIP_VCAN=1 is set, in which case it is skipped (and reported as skipped).
#define CODRIVE_REQUIRE_VCAN(ifname)                                                               \
    do {                                                                                           \
        if (!::codrive::testing::vcan_available(ifname)) {                                         \
            if (::codrive::testing::vcan_skip_requested()) {                                       \
                GTEST_SKIP() << (ifname) << " not available and CODRIVE_SKIP_VCAN=1";              \
            }                                                                                      \
            FAIL() << (ifname)                                                                     \
                   << " is not available: run this suite through vcan-scripts/run-in-vcan.sh "     \
                      "(or set CODRIVE_SKIP_VCAN=1 to skip explicitly)";                           \
        }                                                                                          \
    } while (false)

bool vcan_skip_requested();

} // namespace codrive::testing
