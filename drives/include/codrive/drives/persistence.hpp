// SPDX-License-Identifier: Apache-2.0
// Parameter persistence (1010h store, 1011h restore) and drive identification over any
// DriveTransport: the same calls work over CANopen SDO and EtherCAT CoE.
#pragma once

#include <codrive/drives/profile.hpp>
#include <codrive/drives/transport.hpp>

#include <cstdint>
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

/// What a device says about itself, and the profile that follows from it.
struct DeviceIdentity {
    std::uint32_t device_type = 0;  ///< 1000h
    std::uint32_t vendor_id = 0;    ///< 1018h:01, 0 when it could not be read
    std::uint32_t product_code = 0; ///< 1018h:02, 0 when it could not be read
    std::string device_name;        ///< 1008h, empty when it could not be read
    /// match_identity()'s profile; generic_profile() for a CiA 402 drive no vendor profile
    /// claims; canopen_device_profile() when 1000h bits 0..15 are not 402. Never null.
    const Profile* profile = nullptr;
    /// 1000h bits 0..15 = 402 (CiA 301 §7.5.2.1: the device profile number).
    [[nodiscard]] bool is_drive() const { return (device_type & 0xFFFFU) == 402U; }
    /// "Kollmorgen AKD2G", "generic CiA 402 drive", or for other devices "CANopen device,
    /// device type 00000191h (CiA 401 profile)" / "... (no standard profile)".
    [[nodiscard]] std::string label() const;
};

/// Reads 1000h, 1008h and 1018h:1/:2 of any CANopen device or CoE slave and picks its profile.
/// Errors: Transport if 1000h cannot be read (1008h and 1018h are optional, CiA 301 §7.5.2).
void identify_device(DriveTransport& t, std::function<void(DriveResult<DeviceIdentity>)> done);

/// identify_device() for a caller that needs a drive: the profile of a CiA 402 device (vendor
/// or generic). Errors: Transport if 1000h cannot be read; NotSupported, with a sentence naming
/// the device and its 1000h, for a device that is not a CiA 402 drive.
void identify_profile(DriveTransport& t, std::function<void(DriveResult<const Profile*>)> done);

} // namespace codrive::drives
