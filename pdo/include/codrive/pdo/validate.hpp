// SPDX-License-Identifier: Apache-2.0
// Checks a PDO configuration against the device before anything is written to it.
#pragma once

#include <codrive/core/eds.hpp>
#include <codrive/core/object_dictionary.hpp>
#include <codrive/pdo/error.hpp>
#include <codrive/pdo/quirks.hpp>
#include <codrive/pdo/types.hpp>

#include <span>
#include <string>
#include <vector>

namespace codrive::pdo {

/// What is known about the device: its dictionary (from an EDS, a profile or a simulator) and
/// its [DummyUsage]; either may be absent, then the checks that need it are skipped.
struct DeviceModel {
    const ObjectDictionary* od = nullptr;
    const DummyUsage* dummy_usage = nullptr;
    PdoQuirks quirks;
};

/// A model from a parsed EDS/DCF (which must outlive it): its dictionary and [DummyUsage], and
/// on top of `base` the PDO counts (NrOfRxPDO/NrOfTxPDO, if given) and byte alignment when
/// Granularity is 8.
[[nodiscard]] DeviceModel device_model(const DeviceDescription& eds, PdoQuirks base = PdoQuirks{});

/// Checks one PDO for `node` (the node only appears in messages and default COB-IDs):
///  - number within 1..quirks' count, transmission type not reserved (241..251), RTR types only
///    for TPDOs and only where supported, 254 where supported;
///  - COB-ID: 11-bit unless extended and supported, not restricted (CiA 301 Table 41);
///  - every entry: length > 0; a dummy (0001h..0007h) only in RPDOs, with its type's length and
///    listed in DummyUsage; index 0000h only as AKD2G padding; otherwise the object exists, is
///    mappable in this direction and has the length of its type;
///  - byte alignment where required; at most quirks.max_entries entries; total ≤ 64 bits.
/// Errors: InvalidMapping, LengthExceeded, InvalidCommunication — with the sentence.
[[nodiscard]] PdoResult<void> validate(NodeId node, const PdoConfig& pdo, const DeviceModel& dev);

/// validate() for each PDO, plus: no two enabled PDOs of the node share a COB-ID.
[[nodiscard]] PdoResult<void> validate_all(NodeId node, std::span<const PdoConfig> pdos,
                                           const DeviceModel& dev);

/// Every problem instead of the first (for tools that list them all).
[[nodiscard]] std::vector<std::string> find_problems(NodeId node, std::span<const PdoConfig> pdos,
                                                     const DeviceModel& dev);

} // namespace codrive::pdo
