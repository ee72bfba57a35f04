// SPDX-License-Identifier: Apache-2.0
// Adapts drives::Profile to the decoder's profile hook.
#include <codrive/drives/profile.hpp>
#include <codrive/dump/drive_profiles.hpp>

namespace codrive::dump {
namespace {

class DriveProfile final : public IDumpProfile {
public:
    explicit DriveProfile(const drives::Profile& p)
        : profile_(p), emcy_(drives::emcy_text_provider(p)) {}
    [[nodiscard]] std::string_view name() const override { return profile_.name; }
    [[nodiscard]] bool matches(std::uint32_t vendor, std::uint32_t product) const override {
        // The device type is not always uploaded; assume a CiA 402 drive (1000h = 0x00020192).
        return drives::match_identity(0x00020192, vendor, product) == &profile_;
    }
    [[nodiscard]] const emcy::IEmcyTextProvider* emcy_text() const override { return emcy_.get(); }

private:
    const drives::Profile& profile_;
    std::shared_ptr<const emcy::IEmcyTextProvider> emcy_;
};

} // namespace

void register_drive_profiles(ProfileRegistry& registry) {
    for (const drives::Profile* p : drives::all_profiles()) {
        if (p != nullptr && p->name != "generic") {
            registry.add(std::make_shared<DriveProfile>(*p));
        }
    }
}

} // namespace codrive::dump
