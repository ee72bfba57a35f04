// SPDX-License-Identifier: Apache-2.0
// Slot resolution for the process image (setup time only).
#include <codrive/pdo/process_image.hpp>

#include <fmt/format.h>

namespace codrive::pdo {
namespace {

PdoResult<Slot> find_slot(NodeId node, const std::vector<detail::PdoChannel>& pdos,
                          std::uint16_t index, std::uint8_t subindex, const PdoDir* dir) {
    for (std::size_t i = 0; i < pdos.size(); ++i) {
        const auto& p = pdos[i];
        if (dir != nullptr && p.dir != *dir) {
            continue;
        }
        unsigned offset = 0;
        for (const auto& e : p.config.mapping) {
            if (!e.is_dummy() && !e.is_zero_padding() && e.index == index &&
                e.subindex == subindex) {
                return Slot{static_cast<std::uint16_t>(i), static_cast<std::uint8_t>(offset),
                            e.bits};
            }
            offset += e.bits;
        }
    }
    return pdo_fail(
        PdoErrc::UnknownObject,
        fmt::format("node {}: 0x{:04X}:{:02X} is not mapped in any {}", node, index, subindex,
                    dir == nullptr ? std::string("PDO") : std::string(to_string(*dir))));
}

} // namespace

PdoResult<Slot> ProcessImage::slot(std::uint16_t index, std::uint8_t subindex) const {
    return find_slot(node_, pdos_, index, subindex, nullptr);
}

PdoResult<Slot> ProcessImage::slot(std::uint16_t index, std::uint8_t subindex, PdoDir dir) const {
    return find_slot(node_, pdos_, index, subindex, &dir);
}

} // namespace codrive::pdo
