// SPDX-License-Identifier: Apache-2.0
// 1010h/1011h categories of a profile, store/restore over a DriveTransport, drive identification.
#include <codrive/drives/persistence.hpp>

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <memory>

namespace codrive::drives {
namespace {

/// CiA 301 §7.5.2.13: a drive without categories saves everything at sub-index 1.
constexpr std::array<StoreCategory, 1> kAllOnly{{{0x01, "all", "all parameters", {}}}};

bool is_pdo_map(std::uint16_t index) {
    return (index >= 0x1600 && index <= 0x17FF) || (index >= 0x1A00 && index <= 0x1BFF);
}

void write_signature(DriveTransport& t, const Profile& p, std::string_view what,
                     std::uint16_t index, std::uint32_t signature, DriveTransport::WriteDone done) {
    const StoreCategory* c = p.store_category(what);
    if (c == nullptr) {
        done(drive_fail(DriveErrc::InvalidArgument,
                        fmt::format("{} ({}): no parameter category '{}' in {:04X}h (it has: {})",
                                    t.name(), p.title, what, index, store_category_names(p))));
        return;
    }
    const bool restore = index == 0x1011;
    const bool preop_only = restore && p.quirks.restore_needs_preop_power_disabled;
    std::string title(p.title);
    t.write_as<std::uint32_t>(
        index, c->subindex, signature, [done = std::move(done), preop_only, title](DriveVoid r) {
            if (!r && preop_only) {
                // DS-BVS §6.2.7: the drive answers 08000022h outside its window.
                done(drive_fail(DriveErrc::Transport,
                                r.error().message + fmt::format(" — the {} restores defaults only "
                                                                "in NMT pre-operational with the "
                                                                "power stage disabled",
                                                                title)));
                return;
            }
            done(std::move(r));
        });
}

} // namespace

std::span<const StoreCategory> Profile::store_categories() const {
    if (persistence.categories.empty()) {
        return kAllOnly;
    }
    return persistence.categories;
}

const StoreCategory* Profile::store_category(std::string_view wanted) const {
    for (const StoreCategory& c : store_categories()) {
        if (c.name == wanted) {
            return &c;
        }
    }
    return nullptr;
}

const StoreCategory* Profile::store_category(std::uint8_t subindex) const {
    for (const StoreCategory& c : store_categories()) {
        if (c.subindex == subindex) {
            return &c;
        }
    }
    return nullptr;
}

bool Profile::saves(const StoreCategory& c, std::uint16_t index) const {
    if (index == 0x1010 || index == 0x1011) {
        return false; // the commands themselves (DS-BVS §6.2.6/§6.2.7: "Backup NO")
    }
    if (quirks.pdo_maps_volatile && is_pdo_map(index)) {
        return false; // AKD2G §5.2.11, DS-BVS §6.2.14-§6.2.17 "Backup NO"
    }
    const auto member = [index](const StoreCategory& k) {
        return std::find(k.objects.begin(), k.objects.end(), index) != k.objects.end();
    };
    if (!c.objects.empty()) {
        return member(c);
    }
    const auto cats = store_categories();
    const bool listed = std::any_of(cats.begin(), cats.end(),
                                    [](const StoreCategory& k) { return !k.objects.empty(); });
    // "all": the union of the other categories where the drive lists them (FIO §7.12.4),
    // otherwise every parameter (AKD2G §5.2.11, DS-BVS §6.2.6).
    return !listed || std::any_of(cats.begin(), cats.end(), member);
}

std::string store_category_names(const Profile& p) {
    std::string out;
    for (const StoreCategory& c : p.store_categories()) {
        out += out.empty() ? "" : ", ";
        out += c.name;
    }
    return out;
}

void store_parameters(DriveTransport& t, const Profile& p, std::string_view what,
                      DriveTransport::WriteDone done) {
    write_signature(t, p, what, 0x1010, kSaveSignature, std::move(done));
}

void restore_default_parameters(DriveTransport& t, const Profile& p, std::string_view what,
                                DriveTransport::WriteDone done) {
    write_signature(t, p, what, 0x1011, kLoadSignature, std::move(done));
}

std::string DeviceIdentity::label() const {
    if (is_drive()) {
        return std::string(profile != nullptr ? profile->title : generic_profile().title);
    }
    const unsigned number = device_type & 0xFFFFU;
    return number == 0 ? fmt::format("CANopen device, device type {:08X}h (no standard profile)",
                                     device_type)
                       : fmt::format("CANopen device, device type {:08X}h (CiA {} profile)",
                                     device_type, number);
}

void identify_device(DriveTransport& t, std::function<void(DriveResult<DeviceIdentity>)> done) {
    struct Pending {
        int pending = 4;
        bool have_type = false;
        DeviceIdentity id;
        std::string error;
        std::function<void(DriveResult<DeviceIdentity>)> done;
        void finish() {
            if (--pending != 0) {
                return;
            }
            if (!have_type) {
                done(drive_fail(DriveErrc::Transport, error));
                return;
            }
            if (!id.is_drive()) {
                id.profile = &canopen_device_profile();
            } else {
                const Profile* p =
                    match_identity(id.device_type, id.vendor_id, id.product_code, id.device_name);
                id.profile = p != nullptr ? p : &generic_profile();
            }
            done(std::move(id));
        }
    };
    auto s = std::make_shared<Pending>();
    s->done = std::move(done);
    t.read(0x1008, 0, [s](DriveResult<Bytes> r) {
        if (r) {
            s->id.device_name.assign(r->begin(), r->end());
        }
        s->finish();
    });
    t.read_as<std::uint32_t>(0x1018, 1, [s](DriveResult<std::uint32_t> r) {
        s->id.vendor_id = r.value_or(0);
        s->finish();
    });
    t.read_as<std::uint32_t>(0x1018, 2, [s](DriveResult<std::uint32_t> r) {
        s->id.product_code = r.value_or(0);
        s->finish();
    });
    t.read_as<std::uint32_t>(0x1000, 0, [s](DriveResult<std::uint32_t> r) {
        if (r) {
            s->id.device_type = *r;
            s->have_type = true;
        } else {
            s->error = r.error().message;
        }
        s->finish();
    });
}

void identify_profile(DriveTransport& t, std::function<void(DriveResult<const Profile*>)> done) {
    identify_device(t, [name = t.name(), done = std::move(done)](DriveResult<DeviceIdentity> r) {
        if (!r) {
            done(tl::unexpected(r.error()));
            return;
        }
        if (!r->is_drive()) {
            done(
                drive_fail(DriveErrc::NotSupported,
                           fmt::format("{} is not a CiA 402 drive: it is a {}", name, r->label())));
            return;
        }
        done(r->profile);
    });
}

} // namespace codrive::drives
