// SPDX-License-Identifier: Apache-2.0
// The default PDO assignment an ESI file states for a device, as the master writes it over CoE.
#pragma once

#include <codrive/ethercat/esi.hpp>
#include <codrive/ethercat/master.hpp>

#include <optional>
#include <vector>

namespace codrive::ethercat {

/// The PDOs a device assigns by default, outputs and inputs.
struct EsiDefaultPdos {
    std::vector<PdoMapping> rx; ///< for 1C12h (SM2)
    std::vector<PdoMapping> tx; ///< for 1C13h (SM3)
};

/// ETG.2000 §5.4.4: an RxPdo/TxPdo with an `Sm` attribute is assigned to that sync manager by
/// default; its entries are the default mapping. A `Fixed` PDO, or a device whose CoE element
/// lacks PdoConfig, gets no entries (Master::configure_pdos() then keeps the slave's mapping).
/// None when the device cannot take an assignment (no CoE@PdoAssign): the slave keeps its own.
[[nodiscard]] std::optional<EsiDefaultPdos> esi_default_pdos(const EsiDevice& device);

} // namespace codrive::ethercat
