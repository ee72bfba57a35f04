// SPDX-License-Identifier: Apache-2.0
// Which axis a fault belongs to: the drive's per-axis fault lists (AKD2G 5004h/5104h).
#include <codrive/drives/axis.hpp>

#include <fmt/format.h>

#include <memory>

namespace codrive::drives {

namespace {

/// Reads sub-indexes 1..slots of one fault list, stopping at the first empty entry.
struct FaultListReader : std::enable_shared_from_this<FaultListReader> {
    DriveTransport* transport = nullptr;
    const Profile* profile = nullptr;
    std::uint16_t index = 0;
    std::uint8_t slots = 0;
    std::uint8_t next = 1;
    std::vector<AxisFault> faults;
    std::function<void(DriveResult<std::vector<AxisFault>>)> done;

    void run() {
        if (next > slots) {
            done(std::move(faults));
            return;
        }
        auto self = shared_from_this();
        transport->read_as<std::uint16_t>(index, next++, [self](DriveResult<std::uint16_t> r) {
            if (!r) {
                self->done(tl::unexpected(r.error()));
                return;
            }
            if (*r == 0) {
                self->done(std::move(self->faults)); // the active faults come first
                return;
            }
            const FaultRow* row = self->profile->axis_list_fault(*r);
            AxisFault f;
            f.code = row != nullptr ? row->code : *r;
            f.text = row != nullptr ? self->profile->fault_text(row->code)
                                    : fmt::format("fault list entry 0x{:04X}", *r);
            self->faults.push_back(std::move(f));
            self->run();
        });
    }
};

} // namespace

void Axis::note_error_code(std::uint16_t code) {
    const FaultRow* row = profile_->fault(code);
    if (code == 0 || profile_->axis_fault_list == 0 || (row != nullptr && row->is_warning())) {
        // No list to ask, a reset (0000h), or a warning (the lists hold faults): as it comes.
        last_error_code_ = code;
        if (code == 0) {
            reported_fault_ = 0;
        }
        return;
    }
    // Taken at once, so a message written before the list answers still names the fault;
    // taken back if the list says the fault belongs to another axis.
    const std::uint16_t before = last_error_code_;
    last_error_code_ = code;
    attribute_fault(code, before);
}

void Axis::read_faults(std::function<void(DriveResult<std::vector<AxisFault>>)> done) {
    if (profile_->axis_fault_list == 0) {
        done(drive_fail(
            DriveErrc::NotSupported,
            fmt::format("{}: the {} keeps no per-axis fault list", name_, profile_->title)));
        return;
    }
    auto reader = std::make_shared<FaultListReader>();
    reader->transport = &transport_;
    reader->profile = profile_;
    reader->index = index(profile_->axis_fault_list);
    reader->slots = profile_->axis_fault_slots;
    reader->done = std::move(done);
    reader->run();
}

void Axis::attribute_fault(std::uint16_t hint, std::uint16_t before) {
    std::weak_ptr<bool> alive = alive_;
    read_faults([this, alive, hint, before](DriveResult<std::vector<AxisFault>> r) {
        if (alive.expired()) {
            return;
        }
        if (!r) {
            return; // cannot tell which axis: the device's code stays
        }
        if (r->empty()) {
            // The drive lists no fault for this axis: the EMCY was another axis's.
            reported_fault_ = 0;
            if (hint != 0 && last_error_code_ == hint) {
                last_error_code_ = before;
            }
            return;
        }
        const AxisFault* f = &r->front();
        for (const AxisFault& x : *r) {
            if (x.code == hint) {
                f = &x;
            }
        }
        const bool news = f->code != reported_fault_;
        last_error_code_ = f->code;
        reported_fault_ = f->code;
        if (news && fault_handler_) {
            fault_handler_(*f);
        }
    });
}

} // namespace codrive::drives
