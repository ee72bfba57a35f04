// SPDX-License-Identifier: Apache-2.0
// The objects codrive's CANopen and CoE stacks build around a profile's dictionary, for export.
#include <codrive/devices/device_files.hpp>

#include <codrive/core/time.hpp>
#include <codrive/core/virtual_bus.hpp>
#include <codrive/sim/ecat/application.hpp>
#include <codrive/sim/ecat/drive_profiles.hpp>
#include <codrive/sim/profile.hpp>
#include <codrive/sim/sim_device.hpp>

#include <vector>

namespace codrive::devices {

namespace {

// The objects a device description takes from the stack rather than the profile: the CiA 301
// communication area 1000h-1FFFh (error register and history, SYNC/EMCY/guarding, store and
// restore, SDO server, PDO communication and mapping, ETG.1000.6 sync-manager objects), a vendor
// error history (Profile::error_history_index: DS-BVS 4080h, §6.2.44) and 60E3h of every axis,
// which the drive core builds from the profile's homing list (Profile::homing_methods). Everything
// else the simulators add (simulation control records, scratch objects, objects a profile does not
// describe) is the simulator's, not the drive's, and stays out of the files.
bool is_stack_object(const drives::Profile& p, unsigned axes, std::uint16_t index) {
    if (index >= 0x1000 && index <= 0x1FFF) {
        return true;
    }
    if (index == p.error_history_index) {
        return true;
    }
    for (unsigned axis = 1; axis <= axes; ++axis) {
        if (index == p.axis_index(0x60E3, axis)) {
            return true;
        }
    }
    return false;
}

bool is_mapping_object(std::uint16_t index) {
    return (index >= 0x1600 && index <= 0x17FF) || (index >= 0x1A00 && index <= 0x1BFF);
}

// The stack objects `from` has and the profile lacks, then the objects their PDO maps name that
// only the stack builds (AKD2G 3580h/3601h of the fixed maps 1A20h/1620h, manual §5.3.25 and
// §5.3.39), so every mapped entry of a file is an object of the same file.
void take(ObjectDictionary& out, const ObjectDictionary& from, const ObjectDictionary& profile,
          const drives::Profile& p, unsigned axes) {
    for (const auto& [index, obj] : from.objects()) {
        if (profile.find(index) == nullptr && is_stack_object(p, axes, index)) {
            out.insert(obj);
        }
    }
    std::vector<std::uint16_t> mapped;
    for (const auto& [index, obj] : out.objects()) {
        if (!is_mapping_object(index)) {
            continue;
        }
        for (const auto& [si, sub] : obj.subs) {
            const auto entry = sub.value.as_uint().value_or(0);
            if (si != 0 && entry != 0) {
                mapped.push_back(static_cast<std::uint16_t>(entry >> 16));
            }
        }
    }
    for (const std::uint16_t index : mapped) {
        const Object* obj = from.find(index);
        if (obj != nullptr && profile.find(index) == nullptr && out.find(index) == nullptr) {
            out.insert(*obj);
        }
    }
}

} // namespace

ObjectDictionary stack_objects(const drives::Profile& p, unsigned axes, Stack stack) {
    ObjectDictionary profile;
    drives::build_device_dictionary(profile, p, axes);
    ObjectDictionary out;
    if (stack == Stack::CanOpen) {
        const sim::SimProfile* sp = sim::find_profile(p.name);
        if (sp == nullptr) {
            return out; // no simulated drive (the generic profile): nothing beyond the profile
        }
        // The CAN simulator's node at node-ID 1 (the DS-BVS factory node-ID, §6.2.74), with
        // its factory values (SimDevice::describe()). Nothing is sent: it is never started.
        FakeClock clock;
        VirtualNetwork net(clock);
        sim::SimDeviceConfig config;
        config.node = 1;
        config.profile = sp;
        config.axes = axes;
        const sim::SimDevice device(net.endpoint("export"), config);
        take(out, device.describe().od, profile, p, axes);
        return out;
    }
    const auto slave = sim::ecat::make_drive_slave(p.name);
    if (slave == nullptr) {
        return out;
    }
    take(out, slave->app().od(), profile, p, axes);
    return out;
}

} // namespace codrive::devices
