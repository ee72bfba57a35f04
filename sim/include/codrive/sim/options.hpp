// SPDX-License-Identifier: Apache-2.0
// Command-line specs of codrive-sim: "--node 1:akd2g[:2]" and "--fault 1.2:sto@2s".
#pragma once

#include <codrive/core/cob_id.hpp>
#include <codrive/core/error.hpp>
#include <codrive/core/time.hpp>
#include <codrive/sim/profile.hpp>

#include <string>
#include <string_view>

namespace codrive::sim {

/// One simulated node: id, profile, axis count (0 = the profile's default).
struct NodeSpec {
    NodeId node = 0;
    const SimProfile* profile = nullptr;
    unsigned axes = 0;
};

/// A scheduled fault: `kind` on `axis` (0-based) of `node`, `after` the start.
struct FaultSpec {
    NodeId node = 0;
    unsigned axis = 0;
    FaultKind kind = FaultKind::Sto;
    Duration after{0};
};

/// Parses "ID:PROFILE" or "ID:PROFILE:AXES" ("1:akd2g", "2:ds-bvs", "3:akd2g:1"). On error
/// `error` holds a sentence naming the text and the cause.
[[nodiscard]] bool parse_node_spec(std::string_view text, NodeSpec& out, std::string& error);

/// Parses "NODE[.AXIS]:KIND[@TIME]" with TIME as "2s", "500ms", "1.5s" or plain milliseconds
/// ("1:sto@2s", "2.2:overcurrent@500ms", "1:reset"). AXIS is 1-based on the command line.
[[nodiscard]] bool parse_fault_spec(std::string_view text, FaultSpec& out, std::string& error);

/// Parses "2s", "500ms", "1.5s", "250us", "100" (ms). False if malformed.
[[nodiscard]] bool parse_duration(std::string_view text, Duration& out);

} // namespace codrive::sim
