// SPDX-License-Identifier: Apache-2.0
// A drive device (node/slave) with one or more axes: AKD2G carries two axes behind one SDO
// server, one EMCY producer and one set of PDOs; each axis has its own state machine.
#pragma once

#include <codrive/drives/axis.hpp>
#include <codrive/emcy/consumer.hpp>

#include <memory>
#include <vector>

namespace codrive::drives {

class DriveDevice final : public ITimed {
public:
    /// Creates `axes` axes (clamped to 1..profile.max_axes) on one transport. `base` supplies
    /// the timeout and poll period; its axis number and name are set per axis.
    DriveDevice(DriveTransport& transport, const Profile& profile, unsigned axes,
                AxisConfig base = {});

    [[nodiscard]] std::size_t axis_count() const { return axes_.size(); }
    /// Axis n (1-based); the caller keeps n within 1..axis_count().
    [[nodiscard]] Axis& axis(unsigned n) { return *axes_.at(n - 1); }
    [[nodiscard]] const Profile& profile() const { return profile_; }

    /// Plugs the profile's EMCY text table into the consumer for this node.
    void attach_emcy_text(emcy::EmcyConsumer& consumer, NodeId node) const;
    /// An EMCY of this device: the code goes to every axis (EMCY codes carry no axis — AKD2G
    /// [AMB-8]); on a drive with per-axis fault lists (AKD2G 5004h/5104h, §5.3.84) each axis
    /// keeps it only if its list holds a fault (Axis::note_error_code); a reset (0000h) clears
    /// it.
    void on_emcy(const emcy::EmcyEvent& event);

    /// Runs every axis's cycle / tick.
    void on_cycle(TimePoint now);
    [[nodiscard]] TimePoint next_deadline() const override;
    void on_tick(TimePoint now) override;
    /// Re-resolves every axis's process-image handles.
    void bind();

private:
    const Profile& profile_;
    std::vector<std::unique_ptr<Axis>> axes_;
};

} // namespace codrive::drives
