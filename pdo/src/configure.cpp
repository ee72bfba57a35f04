// SPDX-License-Identifier: Apache-2.0
// PDO configuration sequences (CiA 301 §7.5.2.36) and the SDO runner that performs them.
#include <codrive/pdo/configure.hpp>

#include <fmt/format.h>

namespace codrive::pdo {
namespace {

template <typename T>
SdoWrite make_write(std::uint16_t index, std::uint8_t sub, T value, std::string purpose) {
    SdoWrite w;
    w.index = index;
    w.subindex = sub;
    w.data.resize(sizeof(T));
    put_le<T>(w.data.data(), value);
    w.purpose = std::move(purpose);
    return w;
}

} // namespace

std::string to_string(const SdoWrite& w) {
    std::uint64_t v = get_le_n(w.data.data(), w.data.size());
    return fmt::format("0x{:04X}:{:02X} = 0x{:0{}X} ({})", w.index, w.subindex, v,
                       w.data.size() * 2, w.purpose);
}

std::vector<SdoWrite> configuration_writes(NodeId node, const PdoConfig& pdo, const PdoQuirks& q) {
    std::vector<SdoWrite> out;
    const std::string name = pdo.name();
    const std::uint16_t comm = comm_index(pdo.dir, pdo.number);
    const std::uint16_t map = map_index(pdo.dir, pdo.number);
    const bool write_cob = !q.cob_id_read_only;

    // Step 1: destroy the PDO so that its mapping, inhibit time and SYNC start value may change
    // (CiA 301 §7.5.2.35/37: they are refused with 0x06090030 while the PDO exists). The new
    // CAN-ID goes with it: CiA 301 only forbids changing the id of a *valid* PDO. Where the
    // COB-ID is read-only, mapping count 0 is the switch (DS-BVS manual §6.2.22 a: "write the
    // value 0 to subindex 0x00 (disable PDO)"); it must come first, or a PDO left active by an
    // earlier boot refuses the inhibit time.
    const SdoWrite disable_mapping =
        make_write<std::uint8_t>(map, 0, 0, "disable " + name + " mapping");
    if (write_cob) {
        out.push_back(make_write<std::uint32_t>(
            comm, comm_sub::kCobId, pdo.cob_id_value(node, true), "invalidate " + name));
    } else {
        out.push_back(disable_mapping);
    }
    if (!pdo.enabled) {
        if (write_cob) {
            out.push_back(disable_mapping);
        }
        return out;
    }
    out.push_back(make_write<std::uint8_t>(comm, comm_sub::kTransmissionType,
                                           pdo.comm.transmission_type,
                                           name + " transmission type"));
    if (pdo.dir == PdoDir::Tpdo) {
        if (q.has_inhibit_and_timer) {
            out.push_back(make_write<std::uint16_t>(comm, comm_sub::kInhibitTime,
                                                    pdo.comm.inhibit_time, name + " inhibit time"));
            out.push_back(make_write<std::uint16_t>(comm, comm_sub::kEventTimer,
                                                    pdo.comm.event_timer, name + " event timer"));
        }
        if (q.has_sync_start && pdo.comm.sync_start != 0) {
            out.push_back(make_write<std::uint8_t>(comm, comm_sub::kSyncStart, pdo.comm.sync_start,
                                                   name + " SYNC start value"));
        }
    } else if (q.rpdo_has_event_timer) {
        // Written also when 0 (off): a timer left by an earlier configuration would stay.
        out.push_back(make_write<std::uint16_t>(comm, comm_sub::kEventTimer, pdo.comm.event_timer,
                                                name + " event timer"));
    }
    // Steps 2–4 of §7.5.2.36: disable the mapping, write the entries, enable with the count.
    if (write_cob) {
        out.push_back(disable_mapping);
    }
    for (std::size_t i = 0; i < pdo.mapping.size(); ++i) {
        out.push_back(make_write<std::uint32_t>(map, static_cast<std::uint8_t>(i + 1),
                                                pdo.mapping[i].raw(),
                                                fmt::format("{} mapping entry {}", name, i + 1)));
    }
    out.push_back(make_write<std::uint8_t>(map, 0, static_cast<std::uint8_t>(pdo.mapping.size()),
                                           name + " mapping count"));
    // Step 5: create the PDO again.
    if (write_cob) {
        out.push_back(make_write<std::uint32_t>(comm, comm_sub::kCobId,
                                                pdo.cob_id_value(node, false), "validate " + name));
    }
    return out;
}

PdoConfigurator::PdoConfigurator(sdo::SdoClient& client, DeviceModel device)
    : client_(client), device_(std::move(device)), alive_(std::make_shared<bool>(true)) {}

PdoConfigurator::~PdoConfigurator() {
    *alive_ = false;
}

bool PdoConfigurator::configure(std::vector<PdoConfig> pdos, Done done) {
    if (running_) {
        return false;
    }
    const NodeId node = client_.config().node;
    if (auto ok = validate_all(node, pdos, device_); !ok) {
        done(tl::unexpected(ok.error()));
        return true;
    }
    writes_.clear();
    owners_.clear();
    for (const auto& p : pdos) {
        for (auto& w : configuration_writes(node, p, device_.quirks)) {
            writes_.push_back(std::move(w));
            owners_.push_back(p.name());
        }
    }
    pos_ = 0;
    running_ = true;
    done_ = std::move(done);
    next();
    return true;
}

void PdoConfigurator::next() {
    if (pos_ >= writes_.size()) {
        running_ = false;
        auto done = std::move(done_);
        done(ConfigureReport{writes_.size()});
        return;
    }
    const SdoWrite& w = writes_[pos_];
    std::weak_ptr<bool> alive = alive_;
    client_.download(w.index, w.subindex, w.data, [this, alive](sdo::SdoResult<void> r) {
        if (alive.expired() || !*alive.lock()) {
            return;
        }
        if (!r) {
            running_ = false;
            const SdoWrite& failed = writes_[pos_];
            auto done = std::move(done_);
            done(pdo_fail(PdoErrc::SdoFailed,
                          fmt::format("node {}: configuring {} failed at {}: {}",
                                      client_.config().node, owners_[pos_], to_string(failed),
                                      r.error().to_string())));
            return;
        }
        ++pos_;
        next();
    });
}

} // namespace codrive::pdo
