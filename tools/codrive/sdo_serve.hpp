// SPDX-License-Identifier: Apache-2.0
// `codrive sdo serve`: an SDO server on a CAN interface with a small built-in dictionary.
#pragma once

#include <codrive/core/cob_id.hpp>
#include <codrive/core/object_dictionary.hpp>

#include <string>

namespace codrive::cli {

/// The built-in dictionary: 1000h device type, 1008h device name, 1018h identity (4 subs),
/// 2000h a writable UNSIGNED32, 2001h a writable DOMAIN.
[[nodiscard]] ObjectDictionary make_sdo_serve_dictionary(NodeId node);

/// Serves until SIGINT/SIGTERM. `eds_path` (optional) replaces the built-in dictionary.
/// Prints "ready" on stdout once listening. Returns the process exit code.
int run_sdo_serve(const std::string& iface, NodeId node, const std::string& eds_path);

} // namespace codrive::cli
