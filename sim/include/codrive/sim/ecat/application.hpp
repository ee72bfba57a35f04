// SPDX-License-Identifier: Apache-2.0
// The device behind a simulated EtherCAT slave controller: object dictionary, model, emergencies.
#pragma once

#include <codrive/core/object_dictionary.hpp>
#include <codrive/core/time.hpp>
#include <codrive/emcy/message.hpp>
#include <codrive/ethercat/al_state.hpp>

#include <vector>

namespace codrive::sim::ecat {

/// What the ESC model needs from the device application (the "PDI side" of a real slave).
class EcatApplication {
public:
    virtual ~EcatApplication() = default;
    /// The object dictionary served over CoE; 1C12h/1C13h and 16xxh/1Axxh define process data.
    virtual ObjectDictionary& od() = 0;
    /// Advances the device model to `now` (called before each frame so inputs are fresh).
    virtual void step(TimePoint now) = 0;
    /// The ESM changed state (after the ESC accepted the transition).
    virtual void on_state_change(ethercat::AlState from, ethercat::AlState to) = 0;
    /// Process outputs were just written into the object dictionary (in OP).
    virtual void on_outputs(TimePoint now) = 0;
    /// Emergencies raised since the last call; the ESC sends them as CoE emergency messages.
    virtual std::vector<emcy::EmcyMessage> take_emergencies() = 0;
    /// True once when the device restarted on its own (FIO after 1011h, §7.12.4.16): the ESC
    /// falls back to INIT as after a power cycle (ETG.1000.6 §6.4.1).
    virtual bool take_restart() { return false; }
    /// The AL status code the device's firmware writes for an ETG.1000.6 Table 11 `code` the
    /// ESC model found (refused transition, SM watchdog). A drive whose manual lists only some
    /// codes maps the others onto them (AKD2G §3.1: 0x0011, 0x0017, nothing else).
    [[nodiscard]] virtual std::uint16_t al_status_code(std::uint16_t code) const { return code; }
    /// Test hook: raise a device fault with this EMCY error code (no-op if unsupported).
    virtual void inject_fault(std::uint16_t /*error_code*/) {}
};

} // namespace codrive::sim::ecat
