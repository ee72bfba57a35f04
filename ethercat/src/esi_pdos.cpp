// SPDX-License-Identifier: Apache-2.0
// The default PDO assignment of an ESI device (the PDOs with an Sm attribute, ETG.2000 §5.4.4).
#include <codrive/ethercat/esi_pdos.hpp>

namespace codrive::ethercat {

std::optional<EsiDefaultPdos> esi_default_pdos(const EsiDevice& device) {
    if (!device.pdo_assign) {
        return std::nullopt;
    }
    const auto take = [&](const std::vector<EsiPdo>& pdos, std::vector<PdoMapping>& out) {
        for (const auto& p : pdos) {
            if (!p.sm) {
                continue;
            }
            PdoMapping m;
            m.index = p.index;
            if (!p.fixed && device.pdo_config) {
                for (const auto& e : p.entries) {
                    m.entries.push_back(PdoEntry{e.index, e.subindex, e.bit_len});
                }
            }
            out.push_back(std::move(m));
        }
    };
    EsiDefaultPdos out;
    take(device.rx_pdos, out.rx);
    take(device.tx_pdos, out.tx);
    return out;
}

} // namespace codrive::ethercat
