// SPDX-License-Identifier: Apache-2.0
// A drive profile's object dictionary written as vendor-format device descriptions (EDS, ESI).
#pragma once

#include <codrive/core/eds.hpp>
#include <codrive/drives/profile.hpp>

#include <span>
#include <string>
#include <string_view>

namespace codrive::devices {

/// One file of the repository's `devices/` folder: `<stem>.eds` and `<stem>.xml`, generated
/// from the built-in profile `profile` with `axes` axes.
struct DeviceFile {
    std::string_view stem;    ///< "akd2g", "ds-bvs", "fio"
    std::string_view profile; ///< the profile name (drives::find_profile)
    unsigned axes = 1;
    std::string_view vendor_name; ///< [DeviceInfo] VendorName / ESI Vendor/Name ("" if unknown)
};

/// The files `devices/regenerate.sh` writes and the tests compare (every vendor profile, with
/// the axis count the master assumes for it: drives::Profile::max_axes).
[[nodiscard]] std::span<const DeviceFile> device_files();

/// The stack whose communication objects a description carries besides the profile's.
enum class Stack {
    CanOpen, ///< CiA 301 over CAN: 1005h/1006h, 100Ch/100Dh, 1014h, 1200h, PDOs 1400h-1BFFh
    Coe,     ///< CoE (ETG.1000.6): PDO maps 1600h-1BFFh, sync managers 1C00h-1C33h
};

/// The objects `stack` builds around the profile's dictionary, taken from the one place that
/// builds them (the CANopen node of codrive-sim, sim::SimDevice, at node-ID 1 with its factory
/// values; the CoE slave of codrive-ecat-sim, sim::ecat::make_drive_slave): the CiA 301 area
/// 1000h-1FFFh, 4080h and 60E3h of every axis, where the profile's dictionary lacks them.
/// Empty for a profile without a simulated drive (generic).
[[nodiscard]] ObjectDictionary stack_objects(const drives::Profile& p, unsigned axes, Stack stack);

/// The dictionary the master builds for a profile (drives::build_device_dictionary with `axes`
/// axes) plus stack_objects() as a CiA 306 description: [FileInfo], [DeviceInfo] with the
/// profile's identity, bit rates, PDO granularity and PDO counts, and every object. The stack
/// is CANopen for a drive with a CAN interface (Profile::quirks.canopen), else CoE. Deterministic
/// (no dates, no host names), so a regenerated file can be compared byte for byte.
[[nodiscard]] DeviceDescription profile_description(const drives::Profile& p, unsigned axes,
                                                    std::string_view vendor_name = {});
/// The same with the stack named (export_esi takes the CoE objects).
[[nodiscard]] DeviceDescription profile_description(const drives::Profile& p, unsigned axes,
                                                    std::string_view vendor_name, Stack stack);

/// write_eds(profile_description(p, axes, vendor_name)).
[[nodiscard]] std::string export_eds(const drives::Profile& p, unsigned axes,
                                     std::string_view vendor_name = {});

/// The same dictionary as an EtherCAT slave information file (ETG.2000): one
/// EtherCATInfo/Descriptions/Devices/Device with the identity, the sync managers and FMMUs of
/// codrive's simulated slave, a CoE mailbox, one RxPdo/TxPdo per mapping object of the
/// dictionary with its default entries (Sm where 1C12h/1C13h assign it by default, Fixed where
/// its entry count is read-only) and Profile/Dictionary with DataTypes and one Object per index
/// (the profile's objects plus stack_objects(p, axes, Stack::Coe)).
[[nodiscard]] std::string export_esi(const drives::Profile& p, unsigned axes,
                                     std::string_view vendor_name = {});

/// The devices/ entry for a profile name, or nullptr (e.g. "generic").
[[nodiscard]] const DeviceFile* device_file(std::string_view profile);

} // namespace codrive::devices
