// SPDX-License-Identifier: Apache-2.0
// The simulated touch probes: 60B8h arms, input edges latch 60BAh..60BDh, 60B9h reports.
#include <codrive/sim/touch_probe.hpp>

namespace codrive::sim {

namespace {

// AKD2G manual §5.4.36 (60B8h) and §5.4.37 (60B9h); probe 2 uses the same bits shifted by 8.
constexpr std::uint16_t kFunction = 0x60B8;
constexpr std::uint16_t kStatus = 0x60B9;
constexpr std::uint16_t kPositive1 = 0x60BA; // then 60BBh negative 1, 60BCh positive 2, 60BDh
constexpr unsigned kEnable = 1U << 0;
constexpr unsigned kContinuous = 1U << 1;
constexpr unsigned kSourceMask = 3U << 2;
constexpr unsigned kSourceReserved = 3U << 2; // 11b "Reserved"
constexpr unsigned kSampleRising = 1U << 4;
constexpr unsigned kSampleFalling = 1U << 5;
constexpr unsigned kStoredRising = 1U << 1;
constexpr unsigned kStoredFalling = 1U << 2;

unsigned shift(unsigned probe) {
    return probe == 2 ? 8U : 0U;
}

unsigned bits_of(std::uint16_t word, unsigned probe) {
    return (word >> shift(probe)) & 0xFFU;
}

} // namespace

TouchProbe::TouchProbe(ObjectDictionary& od, std::uint16_t index_offset)
    : od_(od), offset_(index_offset) {
    od_.on_write(at(kFunction),
                 [this](std::uint16_t, std::uint8_t,
                        std::span<const std::uint8_t> d) -> tl::expected<void, SdoAbort> {
                     if (d.size() < 2) {
                         return tl::unexpected(SdoAbort::LengthTooLow);
                     }
                     // 60B8h bits 3,2 / 11,10 = 11b are "Reserved" (§5.4.36). The manual does
                     // not say how the drive answers; the simulator refuses the value rather
                     // than accept a trigger it cannot model.
                     const auto v = get_le<std::uint16_t>(d.data());
                     if ((v & kSourceMask) == kSourceReserved ||
                         ((v >> 8) & kSourceMask) == kSourceReserved) {
                         return tl::unexpected(SdoAbort::InvalidValue);
                     }
                     // Each write acts at once, as on the drive: disable-then-enable written
                     // back to back is an enable edge that re-arms the probe.
                     on_function(v);
                     return {};
                 });
    // A status read right after a 60B8h write sees the new function (the write is stored after
    // its hook ran, so the step would otherwise notice it only later).
    od_.on_read(at(kStatus), [this](std::uint16_t, std::uint8_t, SubObject&) {
        if (function() != last_function_) {
            on_function(function());
        }
    });
}

bool TouchProbe::present(const ObjectDictionary& od, std::uint16_t index_offset) {
    for (std::uint16_t i = kFunction; i <= 0x60BD; ++i) {
        if (od.find(static_cast<std::uint16_t>(i + index_offset), 0) == nullptr) {
            return false;
        }
    }
    return true;
}

std::uint16_t TouchProbe::function() const {
    return od_.get<std::uint16_t>(at(kFunction), 0).value_or(0);
}

std::uint16_t TouchProbe::status() const {
    return od_.get<std::uint16_t>(at(kStatus), 0).value_or(0);
}

void TouchProbe::set_status(std::uint16_t s) {
    od_.set<std::uint16_t>(at(kStatus), 0, s);
}

bool TouchProbe::input(unsigned probe) const {
    return probe >= 1 && probe <= 2 && probes_[probe - 1].input;
}

void TouchProbe::reset() {
    od_.set<std::uint16_t>(at(kFunction), 0, 0);
    set_status(0);
    for (std::uint16_t i = kPositive1; i <= 0x60BD; ++i) {
        od_.set<std::int32_t>(at(i), 0, 0);
    }
    last_function_ = 0;
    for (auto& p : probes_) {
        p.armed_rising = p.armed_falling = false;
    }
}

void TouchProbe::on_function(std::uint16_t f) {
    std::uint16_t s = status();
    for (unsigned probe = 1; probe <= 2; ++probe) {
        const unsigned now = bits_of(f, probe);
        const unsigned before = bits_of(last_function_, probe);
        Probe& p = probes_[probe - 1];
        const unsigned sh = shift(probe);
        if ((now & kEnable) == 0) {
            // §5.4.37: "If a touch probe is disabled ... the latched bits ... are always 0."
            s = static_cast<std::uint16_t>(s & ~((kEnable | kStoredRising | kStoredFalling) << sh));
            p.armed_rising = p.armed_falling = false;
            continue;
        }
        s = static_cast<std::uint16_t>(s | (kEnable << sh));
        const bool enabled_now = (before & kEnable) == 0;
        // Enabling a probe, or setting a sampling bit anew, arms that edge and forgets its old
        // latch (CiA 402 / ETG.6010 touch probe sequence, which §4.1.5 says the AKD2G follows).
        if (enabled_now || ((now & kSampleRising) != 0 && (before & kSampleRising) == 0)) {
            p.armed_rising = (now & kSampleRising) != 0;
            s = static_cast<std::uint16_t>(s & ~(kStoredRising << sh));
        }
        if (enabled_now || ((now & kSampleFalling) != 0 && (before & kSampleFalling) == 0)) {
            p.armed_falling = (now & kSampleFalling) != 0;
            s = static_cast<std::uint16_t>(s & ~(kStoredFalling << sh));
        }
        if ((now & kSampleRising) == 0) {
            p.armed_rising = false;
        }
        if ((now & kSampleFalling) == 0) {
            p.armed_falling = false;
        }
    }
    last_function_ = f;
    set_status(s);
}

void TouchProbe::edge(unsigned probe, bool rising, std::int32_t position) {
    const unsigned f = bits_of(last_function_, probe);
    if ((f & kEnable) == 0) {
        return;
    }
    Probe& p = probes_[probe - 1];
    bool& armed = rising ? p.armed_rising : p.armed_falling;
    if (!armed) {
        return;
    }
    if ((f & kContinuous) == 0) {
        armed = false; // "Trigger first event": one latch until re-armed
    }
    const auto index = static_cast<std::uint16_t>(kPositive1 + (probe - 1) * 2 + (rising ? 0 : 1));
    od_.set<std::int32_t>(at(index), 0, position);
    const unsigned bit = (rising ? kStoredRising : kStoredFalling) << shift(probe);
    set_status(static_cast<std::uint16_t>(status() | bit));
}

void TouchProbe::set_input(unsigned probe, bool level, std::int32_t position) {
    if (probe < 1 || probe > 2) {
        return;
    }
    if (function() != last_function_) {
        on_function(function());
    }
    Probe& p = probes_[probe - 1];
    if (p.input == level) {
        return;
    }
    p.input = level;
    edge(probe, level, position);
}

void TouchProbe::set_trigger_position(unsigned probe, std::optional<std::int32_t> position) {
    if (probe >= 1 && probe <= 2) {
        probes_[probe - 1].trigger_at = position;
    }
}

void TouchProbe::step(std::int32_t position) {
    if (function() != last_function_) {
        on_function(function()); // written through a PDO (no write hook) or not yet seen
    }
    for (unsigned probe = 1; probe <= 2; ++probe) {
        const Probe& p = probes_[probe - 1];
        if (!p.trigger_at) {
            continue;
        }
        const bool level = position >= *p.trigger_at;
        if (level != p.input) {
            // The sensor sits at trigger_at: a hardware latch captures the position there, not
            // where the motion happened to be at the end of the step.
            set_input(probe, level, *p.trigger_at);
        }
    }
}

} // namespace codrive::sim
