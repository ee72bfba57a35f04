// SPDX-License-Identifier: Apache-2.0
// CANopen DriveTransport: SDO for objects, the PDO process image for cyclic data.
#include <codrive/drives/canopen_transport.hpp>

#include <algorithm>

#include <fmt/format.h>

namespace codrive::drives {

pdo::PdoQuirks pdo_quirks(const Profile& p) {
    if (&p == &akd2g_profile() || &p == &ds_bvs_profile()) {
        // The pdo module's presets, with the facts the drive profile holds taken from it.
        pdo::PdoQuirks q = &p == &akd2g_profile() ? pdo::quirks::akd2g() : pdo::quirks::ds_bvs();
        q.maps_volatile = p.quirks.pdo_maps_volatile;
        q.mapping_only_pre_operational = p.quirks.pdo_mapping_preop_only;
        return q;
    }
    pdo::PdoQuirks q = pdo::quirks::standard();
    q.device = std::string(p.title);
    q.cob_id_read_only = p.quirks.pdo_cob_ids_read_only;
    q.maps_volatile = p.quirks.pdo_maps_volatile;
    q.mapping_only_pre_operational = p.quirks.pdo_mapping_preop_only;
    q.max_entries = p.quirks.max_pdo_entries;
    return q;
}

DriveResult<std::vector<pdo::PdoConfig>> mode_pdo_configs(const Profile& p,
                                                          std::span<const cia402::Mode> modes,
                                                          std::uint8_t rpdo_type,
                                                          std::uint8_t tpdo_type) {
    if (modes.empty() || modes.size() > p.max_axes) {
        return drive_fail(
            DriveErrc::InvalidArgument,
            fmt::format("{} has {} axis/axes, {} modes given", p.title, p.max_axes, modes.size()));
    }
    std::vector<pdo::PdoConfig> out;
    std::vector<unsigned> used;
    for (std::size_t i = 0; i < modes.size(); ++i) {
        const auto axis = static_cast<unsigned>(i + 1);
        const ModeLayout* l = p.layout(modes[i]);
        if (l == nullptr) {
            return drive_fail(DriveErrc::NotSupported,
                              fmt::format("{} has no PDO layout for mode {}", p.title,
                                          cia402::mode_name(static_cast<std::int8_t>(modes[i]))));
        }
        const unsigned number = l->first_pdo + axis;
        const auto entries = [&](std::span<const PdoEntry> es) {
            std::vector<pdo::MappingEntry> m;
            for (const PdoEntry& e : es) {
                m.push_back({p.axis_index(e.index, axis), e.subindex, e.bits});
            }
            return m;
        };
        out.push_back(pdo::rpdo(number, entries(l->rx), rpdo_type));
        out.push_back(pdo::tpdo(number, entries(l->tx), tpdo_type));
        used.push_back(number);
    }
    for (unsigned n = 1; n <= 4; ++n) {
        if (std::find(used.begin(), used.end(), n) != used.end()) {
            continue;
        }
        for (PdoDir dir : {PdoDir::Rpdo, PdoDir::Tpdo}) {
            pdo::PdoConfig off = dir == PdoDir::Rpdo ? pdo::rpdo(n, {}) : pdo::tpdo(n, {});
            off.enabled = false;
            out.push_back(std::move(off));
        }
    }
    return out;
}

CanopenTransport::CanopenTransport(sdo::SdoClient& sdo, pdo::ProcessImage* image)
    : sdo_(sdo), image_(image) {}

void CanopenTransport::set_image(pdo::ProcessImage* image) {
    image_ = image;
    slots_.clear();
    dirs_.clear();
}

std::string CanopenTransport::name() const {
    return fmt::format("node {}", sdo_.config().node);
}

void CanopenTransport::read(std::uint16_t index, std::uint8_t subindex, ReadDone done) {
    sdo_.upload(index, subindex, [done = std::move(done)](sdo::SdoResult<sdo::Bytes> r) {
        if (!r) {
            done(drive_fail(DriveErrc::Transport, r.error().to_string()));
            return;
        }
        done(std::move(*r));
    });
}

void CanopenTransport::write(std::uint16_t index, std::uint8_t subindex, Bytes data,
                             WriteDone done) {
    sdo_.download(index, subindex, std::move(data),
                  [done = std::move(done)](sdo::SdoResult<void> r) {
                      if (!r) {
                          done(drive_fail(DriveErrc::Transport, r.error().to_string()));
                          return;
                      }
                      done({});
                  });
}

CyclicHandle CanopenTransport::resolve(std::uint16_t index, std::uint8_t subindex,
                                       PdoDir dir) const {
    if (image_ == nullptr) {
        return {};
    }
    auto slot = image_->slot(index, subindex, dir);
    if (!slot) {
        return {};
    }
    slots_.push_back(*slot);
    dirs_.push_back(dir);
    return {static_cast<std::int32_t>(slots_.size() - 1)};
}

CyclicHandle CanopenTransport::output(std::uint16_t index, std::uint8_t subindex) const {
    return resolve(index, subindex, PdoDir::Rpdo);
}

CyclicHandle CanopenTransport::input(std::uint16_t index, std::uint8_t subindex) const {
    return resolve(index, subindex, PdoDir::Tpdo);
}

void CanopenTransport::set_raw(CyclicHandle h, std::uint64_t raw) {
    if (image_ == nullptr || !h.valid() || static_cast<std::size_t>(h.slot) >= slots_.size()) {
        return;
    }
    const auto i = static_cast<std::size_t>(h.slot);
    if (dirs_[i] != PdoDir::Rpdo) {
        return;
    }
    image_->set<std::uint64_t>(slots_[i], raw);
}

std::optional<std::uint64_t> CanopenTransport::get_raw(CyclicHandle h) const {
    if (image_ == nullptr || !h.valid() || static_cast<std::size_t>(h.slot) >= slots_.size()) {
        return std::nullopt;
    }
    const auto i = static_cast<std::size_t>(h.slot);
    // An input counts only after its TPDO arrived once.
    if (dirs_[i] == PdoDir::Tpdo && image_->rx_time(slots_[i]) == TimePoint{}) {
        return std::nullopt;
    }
    return image_->get<std::uint64_t>(slots_[i]);
}

std::optional<std::uint64_t> CanopenTransport::input_count(CyclicHandle h) const {
    if (image_ == nullptr || !h.valid() || static_cast<std::size_t>(h.slot) >= slots_.size()) {
        return std::nullopt;
    }
    const auto i = static_cast<std::size_t>(h.slot);
    if (dirs_[i] != PdoDir::Tpdo) {
        return std::nullopt;
    }
    return image_->count(slots_[i]);
}

} // namespace codrive::drives
