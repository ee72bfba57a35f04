// SPDX-License-Identifier: Apache-2.0
// Remote PDO configuration over SDO with the CiA 301 §7.5.2.36 procedure and device quirks.
#pragma once

#include <codrive/pdo/error.hpp>
#include <codrive/pdo/types.hpp>
#include <codrive/pdo/validate.hpp>
#include <codrive/sdo/client.hpp>

#include <functional>
#include <memory>
#include <span>
#include <string>
#include <vector>

namespace codrive::pdo {

/// One SDO download of a configuration sequence.
struct SdoWrite {
    std::uint16_t index = 0;
    std::uint8_t subindex = 0;
    std::vector<std::uint8_t> data; ///< little-endian, exactly the object size
    std::string purpose;            ///< "invalidate TPDO1", "TPDO1 mapping entry 2"

    friend bool operator==(const SdoWrite& a, const SdoWrite& b) {
        return a.index == b.index && a.subindex == b.subindex && a.data == b.data;
    }
};
/// "0x1A00:01 = 0x60410010 (TPDO1 mapping entry 1)".
[[nodiscard]] std::string to_string(const SdoWrite& w);

/// The writes that configure one PDO, in order (CiA 301 §7.5.2.36):
///  1. COB-ID with bit 31 set (the PDO is destroyed, so its mapping may change);
///  2. transmission type; TPDO inhibit time and event timer (where the device has them), SYNC
///     start value (if set and supported), RPDO event timer (where supported, also when 0);
///  3. mapping count 0; 4. the entries; 5. the mapping count;
///  6. the COB-ID with bit 31 clear (if the PDO is enabled).
/// With cob_id_read_only the COB-ID writes are left out and mapping count 0 (the only way such
/// a device switches a PDO off) comes first, so that a PDO left active by an earlier boot-up
/// accepts its inhibit time again. A disabled PDO gets only the invalid COB-ID (where writable)
/// and mapping count 0. Every value is written whatever the device holds, so configuring twice
/// ends in the same configuration.
[[nodiscard]] std::vector<SdoWrite> configuration_writes(NodeId node, const PdoConfig& pdo,
                                                         const PdoQuirks& quirks);

/// Result of a successful configuration.
struct ConfigureReport {
    std::size_t writes = 0;
};

/// Runs configuration sequences on one node's SdoClient: validates everything first, then
/// performs the writes one at a time and stops at the first failure. The node must be in NMT
/// pre-operational (CiA 301 allows mapping changes in operational for invalid PDOs, but the
/// drives in scope refuse them with 0x08000022); PDO maps of devices with maps_volatile must be
/// written after every boot-up. Sans-I/O: progress comes from the client's on_frame/on_tick.
class PdoConfigurator {
public:
    using Done = std::function<void(PdoResult<ConfigureReport>)>;

    PdoConfigurator(sdo::SdoClient& client, DeviceModel device);
    ~PdoConfigurator();
    PdoConfigurator(const PdoConfigurator&) = delete;
    PdoConfigurator& operator=(const PdoConfigurator&) = delete;

    /// Validates `pdos` (validate_all), then writes them in order. `done` gets the count of
    /// writes, or: the validation error (nothing is written), or SdoFailed with a sentence like
    /// "node 3: configuring TPDO1 failed at 0x1A00:01 = 0x607A0020 (TPDO1 mapping entry 1):
    /// SDO download ... aborted by server: 0x06040041 ...". Returns false (and does not call
    /// `done`) if a configuration is already running.
    bool configure(std::vector<PdoConfig> pdos, Done done);
    [[nodiscard]] bool busy() const { return running_; }

private:
    void next();
    sdo::SdoClient& client_;
    DeviceModel device_;
    std::vector<SdoWrite> writes_;
    std::vector<std::string> owners_; ///< PDO name per write, for messages
    std::size_t pos_ = 0;
    bool running_ = false;
    Done done_;
    std::shared_ptr<bool> alive_;
};

} // namespace codrive::pdo
