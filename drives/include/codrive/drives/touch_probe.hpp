// SPDX-License-Identifier: Apache-2.0
// Touch probes of an axis (CiA 402 60B8h..60BDh; AKD2G manual §4.1.5): arm on an edge, poll the
// status, read the latched position, disarm.
#pragma once

#include <codrive/drives/error.hpp>
#include <codrive/drives/profile.hpp>
#include <codrive/drives/transport.hpp>

#include <array>
#include <cstdint>
#include <functional>
#include <optional>

namespace codrive::drives {

/// Which edge of the probe input latches the position.
enum class ProbeEdge : std::uint8_t {
    Rising,  ///< 60B8h bit 4 (probe 1) / 12 (probe 2); latched into 60BAh / 60BCh
    Falling, ///< 60B8h bit 5 / 13; latched into 60BBh / 60BDh
    Both,    ///< both sampling bits (arm only)
};

/// 60B8h bit 1 / 9: latch once until armed again, or at every edge.
enum class ProbeTrigger : std::uint8_t { FirstEvent, Continuous };

/// What triggers the probe (60B8h bits 3,2 / 11,10, AKD2G §5.4.36).
enum class ProbeSource : std::uint8_t {
    Input = 0,     ///< the probe's own input (AKD2G: DIN1 for probe 1, DIN2 for probe 2)
    ZeroPulse = 1, ///< the feedback's zero pulse
    Object60D0 = 2 ///< the source 60D0h sub 1 / 2 selects
};

/// One probe's half of 60B9h (AKD2G §5.4.37).
struct ProbeStatus {
    bool enabled = false;        ///< bit 0 / 8
    bool rising_stored = false;  ///< bit 1 / 9: 60BAh / 60BCh holds a position
    bool falling_stored = false; ///< bit 2 / 10: 60BBh / 60BDh holds a position
    /// The stored bit of `edge` (Both: either edge stored).
    [[nodiscard]] bool stored(ProbeEdge edge) const;
};

/// The touch probes 1 and 2 of one axis. Positions are in the units of 6064h (the axis's
/// position units: user units where the factor group defines them; convert to SI with
/// SiScale::from_position). Every call ends in its callback: a value or a readable error.
class TouchProbes {
public:
    using Done = std::function<void(DriveVoid)>;

    /// `axis` is 1-based (AKD2G axis 2 uses 68B8h..68BDh). Resolves the process-image entries
    /// of 60B9h..60BDh (bind()).
    TouchProbes(DriveTransport& transport, const Profile& profile, unsigned axis = 1);

    /// Re-resolves the process-image entries (after the PDO mapping changed); keeps look-ups off
    /// the cyclic path, as Axis::bind() does.
    void bind();

    /// The 60B8h bits of one probe (already shifted for probe 2).
    [[nodiscard]] static std::uint16_t function_bits(unsigned probe, ProbeEdge edge,
                                                     ProbeTrigger trigger,
                                                     ProbeSource source = ProbeSource::Input);
    /// Decodes one probe's half of a 60B9h value.
    [[nodiscard]] static ProbeStatus decode_status(std::uint16_t status, unsigned probe);

    /// Arms probe 1 or 2: reads 60B8h, writes it with the probe disabled, then with the probe
    /// enabled for `edge` and `trigger` (the enable edge clears old latches, CiA 402 / ETG.6010
    /// sequence); the other probe's bits are kept. Errors: InvalidArgument (probe not 1 or 2),
    /// NotSupported (the drive has no 60B8h), Transport.
    void arm(unsigned probe, ProbeEdge edge, ProbeTrigger trigger, Done done,
             ProbeSource source = ProbeSource::Input);
    /// Disables probe 1 or 2 (its stored bits read 0 afterwards, §5.4.37). Errors as arm().
    void disarm(unsigned probe, Done done);
    /// Reads 60B9h for one probe. Errors as arm().
    void read_status(unsigned probe, std::function<void(DriveResult<ProbeStatus>)> done);
    /// Reads the position latched on `edge` (Rising or Falling) of probe 1 or 2. Errors as arm();
    /// InvalidArgument for ProbeEdge::Both.
    void read_position(unsigned probe, ProbeEdge edge,
                       std::function<void(DriveResult<std::int32_t>)> done);

    /// Without SDO: the status from the process image, if 60B9h is mapped into a TPDO/TxPDO and
    /// has been received; nullopt otherwise. Cyclic-safe (no look-up, no allocation).
    [[nodiscard]] std::optional<ProbeStatus> status(unsigned probe) const;
    /// Without SDO: the latched position from the process image, if its object is mapped.
    [[nodiscard]] std::optional<std::int32_t> position(unsigned probe, ProbeEdge edge) const;

    /// The index of a touch-probe object for this axis (60B8h → 68B8h on AKD2G axis 2).
    [[nodiscard]] std::uint16_t index(std::uint16_t base) const {
        return profile_.axis_index(base, axis_);
    }

private:
    /// nullopt if the call may go ahead; otherwise the error to report.
    [[nodiscard]] std::optional<DriveVoid> check(unsigned probe) const;
    [[nodiscard]] static std::uint16_t position_object(unsigned probe, ProbeEdge edge);

    DriveTransport& transport_;
    const Profile& profile_;
    unsigned axis_;
    CyclicHandle in_status_;
    std::array<CyclicHandle, 4> in_positions_{}; ///< 60BAh, 60BBh, 60BCh, 60BDh
};

} // namespace codrive::drives
