// SPDX-License-Identifier: Apache-2.0
// Parameter persistence (1010h store, 1011h restore) and drive identification over any
// DriveTransport: the same calls work over CANopen SDO and EtherCAT CoE.
#pragma once

#include <codrive/drives/profile.hpp>
#include <codrive/drives/transport.hpp>

#include <functional>
#include <string>
#include <string_view>

namespace codrive::drives {

/// Stores the parameters of category `what` ("all", "comm", …; see Profile::store_categories())
/// in the drive's non-volatile memory: writes "save" (65766173h) to 1010h at the category's
/// sub-index (CiA 301 §7.5.2.13). Saved values come back after reset node and power-on.
/// Errors (through `done`): InvalidArgument if the drive has no such category (the sentence
/// lists the ones it has); Transport with the drive's abort if it refuses.
void store_parameters(DriveTransport& t, const Profile& p, std::string_view what,
                      DriveTransport::WriteDone done);

/// Restores the factory defaults of category `what`: writes "load" (64616F6Ch) to 1011h at the
/// category's sub-index (CiA 301 §7.5.2.14). The defaults take effect after the next reset
/// node or power-on (the FIO restarts on its own, §7.12.4.16). Errors as store_parameters();
/// the DS-BVS refuses outside pre-operational with power disabled (abort 08000022h, §6.2.7):
/// the message says so.
void restore_default_parameters(DriveTransport& t, const Profile& p, std::string_view what,
                                DriveTransport::WriteDone done);

/// "all, comm, app" — the category names of a profile, for messages and help texts.
[[nodiscard]] std::string store_category_names(const Profile& p);

/// Reads 1000h, 1008h and 1018h:1/:2 and picks the profile (match_identity(); the generic one
/// for any device no vendor profile claims). Errors: Transport if 1000h cannot be read.
void identify_profile(DriveTransport& t, std::function<void(DriveResult<const Profile*>)> done);

} // namespace codrive::drives
