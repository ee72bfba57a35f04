// SPDX-License-Identifier: Apache-2.0
// The hook through which drive profiles add vendor knowledge (EMCY texts) to the decoder.
#pragma once

#include <codrive/emcy/text_provider.hpp>

#include <cstdint>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

namespace codrive::dump {

/// What a drive profile (drives/ profiles: AKD2G, DS-BVS, FIO...) tells the decoder. Profiles
/// register themselves with a ProfileRegistry; the decoder picks one per node from
/// `--profile NODE=NAME`, from the identity in the node's EDS, or from 1018h:01/02 uploads it
/// sees in the trace.
class IDumpProfile {
public:
    virtual ~IDumpProfile() = default;
    /// Short name used on the command line ("akd2g").
    [[nodiscard]] virtual std::string_view name() const = 0;
    /// True if the profile describes devices with this identity (1018h:01 and 1018h:02).
    [[nodiscard]] virtual bool matches(std::uint32_t vendor_id,
                                       std::uint32_t product_code) const = 0;
    /// Vendor texts for EMCY messages, or nullptr.
    [[nodiscard]] virtual const emcy::IEmcyTextProvider* emcy_text() const = 0;
};

/// The profiles known to codrive-dump.
class ProfileRegistry {
public:
    void add(std::shared_ptr<const IDumpProfile> profile) {
        profiles_.push_back(std::move(profile));
    }
    [[nodiscard]] const IDumpProfile* find(std::string_view name) const {
        for (const auto& p : profiles_) {
            if (p->name() == name) {
                return p.get();
            }
        }
        return nullptr;
    }
    [[nodiscard]] const IDumpProfile* match(std::uint32_t vendor, std::uint32_t product) const {
        for (const auto& p : profiles_) {
            if (p->matches(vendor, product)) {
                return p.get();
            }
        }
        return nullptr;
    }
    [[nodiscard]] const std::vector<std::shared_ptr<const IDumpProfile>>& all() const {
        return profiles_;
    }

private:
    std::vector<std::shared_ptr<const IDumpProfile>> profiles_;
};

} // namespace codrive::dump
