// SPDX-License-Identifier: Apache-2.0
// DriveTransport over CANopen: object access through an SDO client, cyclic data through the PDO
// master's process image; plus the PDO configurations a profile's layouts call for.
#pragma once

#include <codrive/drives/profile.hpp>
#include <codrive/drives/transport.hpp>
#include <codrive/pdo/process_image.hpp>
#include <codrive/pdo/quirks.hpp>
#include <codrive/pdo/types.hpp>
#include <codrive/sdo/client.hpp>

#include <span>
#include <vector>

namespace codrive::drives {

/// The PDO quirks of a drive profile (for PdoConfigurator and validation): DS-BVS read-only
/// COB-IDs, AKD2G volatile maps, pre-operational-only mapping, entry limits.
[[nodiscard]] pdo::PdoQuirks pdo_quirks(const Profile& p);

/// The PDO configurations for running each axis in `modes[axis - 1]`: the profile's layout of
/// that mode goes into RPDO/TPDO `first_pdo + axis` (1-based), synchronous (RPDO type
/// `rpdo_type`, TPDO type `tpdo_type`; 1 = every SYNC). The remaining PDOs 1..4 are disabled so
/// nothing stale (AKD2G) or half-configured stays active. Errors: NotSupported if the profile
/// has no layout for a mode, InvalidArgument for more axes than the profile has.
[[nodiscard]] DriveResult<std::vector<pdo::PdoConfig>>
mode_pdo_configs(const Profile& p, std::span<const cia402::Mode> modes, std::uint8_t rpdo_type = 1,
                 std::uint8_t tpdo_type = 1);

/// CANopen implementation of DriveTransport for one node.
class CanopenTransport final : public DriveTransport {
public:
    /// `image` may be nullptr: then nothing is cyclic and axes poll over SDO.
    explicit CanopenTransport(sdo::SdoClient& sdo, pdo::ProcessImage* image = nullptr);

    /// Uses another process image (after the PDOs were reconfigured). Axes must bind() again.
    void set_image(pdo::ProcessImage* image);

    [[nodiscard]] std::string name() const override;
    void read(std::uint16_t index, std::uint8_t subindex, ReadDone done) override;
    void write(std::uint16_t index, std::uint8_t subindex, Bytes data, WriteDone done) override;
    [[nodiscard]] CyclicHandle output(std::uint16_t index, std::uint8_t subindex) const override;
    [[nodiscard]] CyclicHandle input(std::uint16_t index, std::uint8_t subindex) const override;
    void set_raw(CyclicHandle h, std::uint64_t raw) override;
    [[nodiscard]] std::optional<std::uint64_t> get_raw(CyclicHandle h) const override;
    /// The TPDO's reception counter (PdoMaster).
    [[nodiscard]] std::optional<std::uint64_t> input_count(CyclicHandle h) const override;

private:
    CyclicHandle resolve(std::uint16_t index, std::uint8_t subindex, PdoDir dir) const;

    sdo::SdoClient& sdo_;
    pdo::ProcessImage* image_;
    /// Resolved slots; handles index into it. Grows only at setup (resolve is not cyclic).
    mutable std::vector<pdo::Slot> slots_;
    mutable std::vector<PdoDir> dirs_;
};

} // namespace codrive::drives
