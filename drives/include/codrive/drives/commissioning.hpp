// SPDX-License-Identifier: Apache-2.0
// Commissioning over the bus: a new node-ID (and CAN bit rate) written to the drive's own
// objects and saved, effective at its next restart (DS-BVS 5000h/5002h, manual §6.2.74/§6.2.76).
#pragma once

#include <codrive/drives/profile.hpp>
#include <codrive/drives/transport.hpp>

#include <optional>

namespace codrive::drives {

/// Writes `node_id` (1..127) to the profile's node-ID object and, if given, the code of
/// `bit_rate_kbit` to its bit-rate object, then saves all parameters (1010h:01h "save"). The
/// drive keeps answering at its old node-ID until it restarts: the caller then sends NMT reset
/// node and waits for the boot-up at `node_id` (as `codrive commission` does).
/// Errors: NotSupported if the profile names no node-ID object (or no bit-rate object when a
/// rate is given); InvalidArgument for a node-ID outside 1..127 or a rate the drive does not
/// support (the sentence lists the ones it does); Transport with the drive's abort.
void commission_node(DriveTransport& t, const Profile& p, unsigned node_id,
                     std::optional<unsigned> bit_rate_kbit, DriveTransport::WriteDone done);

/// "20, 50, 125, 250, 500, 1000" — the bit rates (kbit/s) a profile's drive accepts.
[[nodiscard]] std::string bit_rate_names(const Profile& p);

} // namespace codrive::drives
