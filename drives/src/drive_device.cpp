// SPDX-License-Identifier: Apache-2.0
// Multi-axis drive devices: axes sharing one transport, EMCY routing.
#include <codrive/drives/drive_device.hpp>

#include <algorithm>

namespace codrive::drives {

DriveDevice::DriveDevice(DriveTransport& transport, const Profile& profile, unsigned axes,
                         AxisConfig base)
    : profile_(profile) {
    axes = std::clamp(axes, 1U, static_cast<unsigned>(profile.max_axes));
    for (unsigned n = 1; n <= axes; ++n) {
        AxisConfig cfg = base;
        cfg.axis = n;
        cfg.profile = &profile;
        cfg.name.clear();
        axes_.push_back(std::make_unique<Axis>(transport, cfg));
    }
}

void DriveDevice::attach_emcy_text(emcy::EmcyConsumer& consumer, NodeId node) const {
    consumer.set_text_provider(node, emcy_text_provider(profile_));
}

void DriveDevice::on_emcy(const emcy::EmcyEvent& event) {
    const std::uint16_t code = event.reset ? 0 : event.message.error_code;
    for (auto& a : axes_) {
        a->note_error_code(code);
    }
}

void DriveDevice::on_cycle(TimePoint now) {
    for (auto& a : axes_) {
        a->on_cycle(now);
    }
}

TimePoint DriveDevice::next_deadline() const {
    TimePoint t = kNever;
    for (const auto& a : axes_) {
        t = std::min(t, a->next_deadline());
    }
    return t;
}

void DriveDevice::on_tick(TimePoint now) {
    for (auto& a : axes_) {
        if (a->next_deadline() <= now) {
            a->on_tick(now);
        }
    }
}

void DriveDevice::bind() {
    for (auto& a : axes_) {
        a->bind();
    }
}

} // namespace codrive::drives
