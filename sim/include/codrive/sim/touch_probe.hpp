// SPDX-License-Identifier: Apache-2.0
// The simulated touch probes of one axis (AKD2G manual §4.1.5, objects 60B8h..60BDh).
#pragma once

#include <codrive/core/object_dictionary.hpp>

#include <array>
#include <cstdint>
#include <optional>

namespace codrive::sim {

/// Two touch probes of one axis, as the AKD2G manual describes them (§4.1.5, object pages
/// §5.4.36-§5.4.41): 60B8h (function) arms them, a rising or falling edge of a probe's input
/// latches the axis's actual position (6064h units) into 60BAh/60BBh (probe 1) or 60BCh/60BDh
/// (probe 2) and sets the "stored" bits of 60B9h. The inputs are driven by the simulator's
/// user: set_input() (an edge now, latching the given position), or set_trigger_position()
/// (a sensor at a fixed place: the input is high while the position is at or beyond it, and
/// the edge latches the place itself, as the drive's hardware latch would).
class TouchProbe {
public:
    /// Installs the write check of 60B8h at `index_offset` (0 for axis 1, 800h for AKD2G axis 2).
    /// The objects themselves come from the drive profile.
    TouchProbe(ObjectDictionary& od, std::uint16_t index_offset);
    TouchProbe(const TouchProbe&) = delete;
    TouchProbe& operator=(const TouchProbe&) = delete;

    /// True if the dictionary has 60B8h..60BDh at `index_offset` (the profile describes them).
    [[nodiscard]] static bool present(const ObjectDictionary& od, std::uint16_t index_offset);

    /// Drives probe `probe`'s (1 or 2) input to `level`; an edge latches `position`.
    void set_input(unsigned probe, bool level, std::int32_t position);
    /// Probe `probe`'s input follows the position: high at or beyond `at` (nullopt: the input
    /// is left where it is and no longer follows the position).
    void set_trigger_position(unsigned probe, std::optional<std::int32_t> at);
    /// Called every simulation step with the actual position (6064h).
    void step(std::int32_t position);
    /// Forgets latched values and the function (power-on / NMT reset node).
    void reset();

    [[nodiscard]] bool input(unsigned probe) const;

private:
    struct Probe {
        bool input = false;
        std::optional<std::int32_t> trigger_at;
        bool armed_rising = false;  ///< first-event mode: still waiting for its rising edge
        bool armed_falling = false; ///< first-event mode: still waiting for its falling edge
    };

    void on_function(std::uint16_t function);
    void edge(unsigned probe, bool rising, std::int32_t position);
    [[nodiscard]] std::uint16_t function() const;
    [[nodiscard]] std::uint16_t status() const;
    void set_status(std::uint16_t s);
    [[nodiscard]] std::uint16_t at(std::uint16_t base) const {
        return static_cast<std::uint16_t>(base + offset_);
    }

    ObjectDictionary& od_;
    std::uint16_t offset_;
    std::uint16_t last_function_ = 0;
    std::array<Probe, 2> probes_{};
};

} // namespace codrive::sim
