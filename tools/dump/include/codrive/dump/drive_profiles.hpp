// SPDX-License-Identifier: Apache-2.0
// The drive profiles of drives/ (AKD2G, DS-BVS, FIO) as decoder profiles.
#pragma once

#include <codrive/dump/profile.hpp>

namespace codrive::dump {

/// Registers every vendor profile of codrive::drives (not the generic one: it has no vendor
/// texts). Matching by identity uses drives::match_identity.
void register_drive_profiles(ProfileRegistry& registry);

} // namespace codrive::dump
