// SPDX-License-Identifier: Apache-2.0
// Touch probes of an axis: 60B8h function bits, 60B9h status, 60BAh..60BDh latched positions.
#include <codrive/drives/touch_probe.hpp>

#include <fmt/format.h>

#include <memory>

namespace codrive::drives {

namespace {

// AKD2G manual §5.4.36 (60B8h) / §5.4.37 (60B9h); probe 2 uses the same bits shifted by 8.
constexpr std::uint16_t kFunction = 0x60B8;
constexpr std::uint16_t kStatus = 0x60B9;
constexpr std::uint16_t kPositive1 = 0x60BA; // 60BBh negative 1, 60BCh positive 2, 60BDh neg. 2
constexpr unsigned kEnable = 1U << 0;
constexpr unsigned kContinuous = 1U << 1;
constexpr unsigned kSourceShift = 2;
constexpr unsigned kSampleRising = 1U << 4;
constexpr unsigned kSampleFalling = 1U << 5;

unsigned shift(unsigned probe) {
    return probe == 2 ? 8U : 0U;
}

} // namespace

bool ProbeStatus::stored(ProbeEdge edge) const {
    switch (edge) {
    case ProbeEdge::Rising:
        return rising_stored;
    case ProbeEdge::Falling:
        return falling_stored;
    case ProbeEdge::Both:
        break;
    }
    return rising_stored || falling_stored;
}

TouchProbes::TouchProbes(DriveTransport& transport, const Profile& profile, unsigned axis)
    : transport_(transport), profile_(profile), axis_(axis == 0 ? 1 : axis) {
    bind();
}

void TouchProbes::bind() {
    in_status_ = transport_.input(index(kStatus), 0);
    for (std::size_t i = 0; i < in_positions_.size(); ++i) {
        in_positions_[i] = transport_.input(index(static_cast<std::uint16_t>(kPositive1 + i)), 0);
    }
}

std::uint16_t TouchProbes::function_bits(unsigned probe, ProbeEdge edge, ProbeTrigger trigger,
                                         ProbeSource source) {
    unsigned bits = kEnable | (static_cast<unsigned>(source) << kSourceShift);
    if (trigger == ProbeTrigger::Continuous) {
        bits |= kContinuous;
    }
    if (edge != ProbeEdge::Falling) {
        bits |= kSampleRising;
    }
    if (edge != ProbeEdge::Rising) {
        bits |= kSampleFalling;
    }
    return static_cast<std::uint16_t>(bits << shift(probe));
}

ProbeStatus TouchProbes::decode_status(std::uint16_t status, unsigned probe) {
    const unsigned s = (status >> shift(probe)) & 0xFFU;
    return ProbeStatus{(s & 1U) != 0, (s & 2U) != 0, (s & 4U) != 0};
}

std::uint16_t TouchProbes::position_object(unsigned probe, ProbeEdge edge) {
    return static_cast<std::uint16_t>(kPositive1 + (probe - 1) * 2 +
                                      (edge == ProbeEdge::Falling ? 1 : 0));
}

std::optional<DriveVoid> TouchProbes::check(unsigned probe) const {
    if (probe != 1 && probe != 2) {
        return drive_fail(DriveErrc::InvalidArgument,
                          fmt::format("{} axis {}: touch probe {} does not exist (1 or 2)",
                                      transport_.name(), axis_, probe));
    }
    if (!profile_.has_object(kFunction)) {
        return drive_fail(DriveErrc::NotSupported,
                          fmt::format("{} axis {}: the {} has no touch probe (no object 60B8h)",
                                      transport_.name(), axis_, profile_.title));
    }
    return std::nullopt;
}

void TouchProbes::arm(unsigned probe, ProbeEdge edge, ProbeTrigger trigger, Done done,
                      ProbeSource source) {
    if (auto bad = check(probe)) {
        done(std::move(*bad));
        return;
    }
    const std::uint16_t mine = function_bits(probe, edge, trigger, source);
    const auto mask = static_cast<std::uint16_t>(0xFFU << shift(probe));
    const std::uint16_t at = index(kFunction);
    DriveTransport* t = &transport_;
    transport_.read_as<std::uint16_t>(
        at, 0, [t, at, mine, mask, done = std::move(done)](DriveResult<std::uint16_t> r) mutable {
            if (!r) {
                done(tl::unexpected(r.error()));
                return;
            }
            const auto others = static_cast<std::uint16_t>(*r & ~mask);
            // Disabled first, so the enable below is an edge that re-arms and clears old latches.
            t->write_as<std::uint16_t>(at, 0, others,
                                       [t, at, value = static_cast<std::uint16_t>(others | mine),
                                        done = std::move(done)](DriveVoid w) mutable {
                                           if (!w) {
                                               done(std::move(w));
                                               return;
                                           }
                                           t->write_as<std::uint16_t>(at, 0, value,
                                                                      std::move(done));
                                       });
        });
}

void TouchProbes::disarm(unsigned probe, Done done) {
    if (auto bad = check(probe)) {
        done(std::move(*bad));
        return;
    }
    const auto mask = static_cast<std::uint16_t>(0xFFU << shift(probe));
    const std::uint16_t at = index(kFunction);
    DriveTransport* t = &transport_;
    transport_.read_as<std::uint16_t>(
        at, 0, [t, at, mask, done = std::move(done)](DriveResult<std::uint16_t> r) mutable {
            if (!r) {
                done(tl::unexpected(r.error()));
                return;
            }
            t->write_as<std::uint16_t>(at, 0, static_cast<std::uint16_t>(*r & ~mask),
                                       std::move(done));
        });
}

void TouchProbes::read_status(unsigned probe, std::function<void(DriveResult<ProbeStatus>)> done) {
    if (auto bad = check(probe)) {
        done(tl::unexpected(bad->error()));
        return;
    }
    transport_.read_as<std::uint16_t>(
        index(kStatus), 0, [probe, done = std::move(done)](DriveResult<std::uint16_t> r) {
            if (!r) {
                done(tl::unexpected(r.error()));
                return;
            }
            done(decode_status(*r, probe));
        });
}

void TouchProbes::read_position(unsigned probe, ProbeEdge edge,
                                std::function<void(DriveResult<std::int32_t>)> done) {
    if (auto bad = check(probe)) {
        done(tl::unexpected(bad->error()));
        return;
    }
    if (edge == ProbeEdge::Both) {
        done(drive_fail(DriveErrc::InvalidArgument,
                        fmt::format("{} axis {}: touch probe {}: read the Rising or the Falling "
                                    "position (each edge has its own object)",
                                    transport_.name(), axis_, probe)));
        return;
    }
    transport_.read_as<std::int32_t>(index(position_object(probe, edge)), 0, std::move(done));
}

std::optional<ProbeStatus> TouchProbes::status(unsigned probe) const {
    if (probe != 1 && probe != 2) {
        return std::nullopt;
    }
    const auto v = transport_.get<std::uint16_t>(in_status_);
    if (!v) {
        return std::nullopt;
    }
    return decode_status(*v, probe);
}

std::optional<std::int32_t> TouchProbes::position(unsigned probe, ProbeEdge edge) const {
    if ((probe != 1 && probe != 2) || edge == ProbeEdge::Both) {
        return std::nullopt;
    }
    return transport_.get<std::int32_t>(in_positions_[position_object(probe, edge) - kPositive1]);
}

} // namespace codrive::drives
