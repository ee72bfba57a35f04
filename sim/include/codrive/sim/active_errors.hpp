// SPDX-License-Identifier: Apache-2.0
// The errors a simulated drive has active, kept once for the CAN and the EtherCAT simulator:
// error register 1001h, the error histories, and the emergency each change causes.
#pragma once

#include <codrive/core/object_dictionary.hpp>
#include <codrive/emcy/message.hpp>
#include <codrive/sim/drive_core.hpp>
#include <codrive/sim/profile.hpp>

#include <optional>
#include <vector>

namespace codrive::sim {

/// Active faults and warnings, one entry per axis and error code. Every new entry sets 1001h,
/// is recorded in the drive's histories (1003h, DS-BVS 4080h) and yields its emergency; the
/// last entry going yields EMCY 0000h "error reset or no error" (CiA 301 §7.2.7.1; AKD2G §2.5).
/// An emergency never names the axis: no manual says it does (the AKD2G lists faults per axis in
/// 5004h/5104h AXIS#.FAULT#, §5.3.84); the axis shows its fault in its statusword.
class ActiveErrors {
public:
    ActiveErrors(ObjectDictionary& od, const SimProfile& profile) : od_(od), profile_(profile) {}

    /// A fault or warning of `axis` (−1: the device, e.g. a communication error). A code already
    /// active on that axis is recorded and announced again (the drive saw it again).
    emcy::EmcyMessage raise(const FaultCode& code, int axis, bool warning);
    /// Removes the axis's faults (`warnings_only` false) or warnings; with `code` only that one.
    /// EMCY 0000h when nothing is left active.
    std::optional<emcy::EmcyMessage> clear(int axis, bool warnings_only, std::uint16_t code = 0);
    /// An axis event of DriveCore: raise for FaultRaised/WarningRaised, clear for the others.
    std::optional<emcy::EmcyMessage> on_axis_event(const AxisEvent& e);
    /// Power-on or reset node: nothing active, 1001h 0 (the histories stay, as on a drive).
    void reset();
    [[nodiscard]] bool empty() const { return errors_.empty(); }

private:
    struct Entry {
        std::uint16_t code = 0;
        std::uint8_t reg = 0;
        int axis = -1;
        bool warning = false;
    };
    std::uint8_t update_register();

    ObjectDictionary& od_;
    const SimProfile& profile_;
    std::vector<Entry> errors_;
};

} // namespace codrive::sim
