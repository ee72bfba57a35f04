// SPDX-License-Identifier: Apache-2.0
// The simulated non-volatile memory behind 1010h (store) and 1011h (restore), one for the CAN
// and the EtherCAT simulator; which objects a category holds comes from the drive profile.
#pragma once

#include <codrive/core/object_dictionary.hpp>
#include <codrive/drives/profile.hpp>

#include <cstdint>
#include <functional>
#include <map>
#include <set>

namespace codrive::sim {

/// Factory defaults and saved values of a dictionary. A save copies the current values of a
/// category's objects; a restore puts the factory values back in the saved set; load() (reset
/// node, power-on) writes the saved set into the dictionary.
class ParameterStore {
public:
    using Check = std::function<tl::expected<void, SdoAbort>()>;

    ParameterStore(ObjectDictionary& od, const drives::Profile& p) : od_(od), profile_(p) {}

    /// Adds 1010h and 1011h with the sub-indices the drive has (sub 0 = the highest).
    void add_objects();
    /// The dictionary as it is now becomes the factory defaults and the saved set.
    void snapshot_factory();
    /// Installs the 1010h/1011h hooks: "save"/"load" at a category's sub-index, any other value
    /// refused with 08000020h (CiA 301 §7.5.2.13). `restore_allowed` may refuse a restore in
    /// the device's state (DS-BVS §6.2.7); `restored` runs after a restore (FIO: restart).
    void install_hooks(Check restore_allowed, std::function<void()> restored);

    void save(const drives::StoreCategory& c);
    void restore_defaults(const drives::StoreCategory& c);
    /// Writes the saved values into the dictionary: every object (reset node, power-on) or only
    /// the communication area 1000h..1FFFh (reset communication, CiA 301 §7.3.2.2.2).
    void load(bool communication_only);
    /// Sets the value and default of every sub-object of `od` to the factory value (an EDS).
    void write_factory(ObjectDictionary& od) const;
    /// The saved values that differ from the factory ones (what a restart carries over).
    [[nodiscard]] std::map<std::uint32_t, Value> changes() const;
    /// Takes saved values from changes() of an earlier store (the same memory after a restart).
    void adopt(const std::map<std::uint32_t, Value>& saved);
    /// Marks the current value of one sub-object as saved (command-line settings).
    void keep(std::uint16_t index, std::uint8_t subindex);

private:
    static std::uint32_t key(std::uint16_t index, std::uint8_t sub) {
        return (static_cast<std::uint32_t>(index) << 8) | sub;
    }

    ObjectDictionary& od_;
    const drives::Profile& profile_;
    std::map<std::uint32_t, Value> factory_;
    std::map<std::uint32_t, Value> stored_;
    std::set<std::uint8_t> saved_subs_; ///< 1010h sub-indices saved at least once (FIO reads 1)
};

} // namespace codrive::sim
