// SPDX-License-Identifier: Apache-2.0
// Simulated non-volatile memory behind 1010h/1011h (see parameter_store.hpp).
#include "parameter_store.hpp"

#include <codrive/core/endian.hpp>

namespace codrive::sim {

namespace {

Value u32(std::uint32_t v) {
    return *Value::from_uint(DataType::Unsigned32, v);
}

Object command_object(std::uint16_t index, const char* name, const drives::Profile& p,
                      const char* verb) {
    Object o;
    o.index = index;
    o.name = name;
    o.code = ObjectCode::Record; // AKD2G §5.2.11, DS-BVS §6.2.6, FIO §7.13.7: RECORD/ARRAY
    const std::uint8_t highest = p.persistence.highest_subindex;
    o.subs.emplace(0, SubObject::make(0, "Highest sub-index supported", DataType::Unsigned8,
                                      Access::Ro, *Value::from_uint(DataType::Unsigned8, highest)));
    for (std::uint8_t si = 1; si <= highest; ++si) {
        const drives::StoreCategory* c = p.store_category(si);
        std::string sub_name = c != nullptr ? std::string(verb) + " " + std::string(c->title)
                                            : std::string(verb) + " (no category)";
        o.subs.emplace(si, SubObject::make(si, std::move(sub_name), DataType::Unsigned32,
                                           Access::Rw, u32(p.persistence.store_read_before_save)));
    }
    return o;
}

} // namespace

void ParameterStore::add_objects() {
    od_.insert(command_object(0x1010, "Store parameters", profile_, "Save"));
    od_.insert(command_object(0x1011, "Restore default parameters", profile_, "Restore"));
}

void ParameterStore::snapshot_factory() {
    factory_.clear();
    for (const auto& [index, o] : od_.objects()) {
        for (const auto& [si, s] : o.subs) {
            factory_[key(index, si)] = s.value;
        }
    }
    stored_ = factory_;
}

void ParameterStore::install_hooks(Check restore_allowed, std::function<void()> restored) {
    const std::uint32_t idle = profile_.persistence.store_read_before_save;
    od_.on_write(0x1010,
                 [this](std::uint16_t, std::uint8_t sub,
                        std::span<const std::uint8_t> d) -> tl::expected<void, SdoAbort> {
                     if (sub == 0) {
                         return tl::unexpected(SdoAbort::ReadOnly);
                     }
                     if (d.size() != 4 ||
                         get_le<std::uint32_t>(d.data()) != drives::kSaveSignature) {
                         return tl::unexpected(SdoAbort::DataTransfer); // CiA 301 §7.5.2.13
                     }
                     if (const drives::StoreCategory* c = profile_.store_category(sub)) {
                         save(*c);
                     }
                     saved_subs_.insert(sub);
                     return {};
                 });
    // AKD2G §5.2.11 / DS-BVS: reads 1 (saves on command only); FIO §7.12.4.15: 0 until the
    // save has ended, then 1.
    od_.on_read(0x1010, [this, idle](std::uint16_t, std::uint8_t sub, SubObject& s) {
        if (sub != 0) {
            s.value = u32(saved_subs_.count(sub) != 0 ? 1U : idle);
        }
    });
    od_.on_read(0x1011, [idle](std::uint16_t, std::uint8_t sub, SubObject& s) {
        if (sub != 0) {
            s.value = u32(idle); // AKD2G §5.2.12, DS-BVS §6.2.7: always 1
        }
    });
    od_.on_write(0x1011,
                 [this, check = std::move(restore_allowed), done = std::move(restored)](
                     std::uint16_t, std::uint8_t sub,
                     std::span<const std::uint8_t> d) -> tl::expected<void, SdoAbort> {
                     if (sub == 0) {
                         return tl::unexpected(SdoAbort::ReadOnly);
                     }
                     if (d.size() != 4 ||
                         get_le<std::uint32_t>(d.data()) != drives::kLoadSignature) {
                         return tl::unexpected(SdoAbort::DataTransfer); // CiA 301 §7.5.2.14
                     }
                     if (check) {
                         if (auto ok = check(); !ok) {
                             return ok;
                         }
                     }
                     if (const drives::StoreCategory* c = profile_.store_category(sub)) {
                         restore_defaults(*c);
                     }
                     if (done) {
                         done();
                     }
                     return {};
                 });
}

void ParameterStore::save(const drives::StoreCategory& c) {
    for (const auto& [index, o] : od_.objects()) {
        if (!profile_.saves(c, index)) {
            continue;
        }
        for (const auto& [si, sub] : o.subs) {
            if (writable(sub.access)) {
                stored_[key(index, si)] = sub.value;
            }
        }
    }
}

void ParameterStore::restore_defaults(const drives::StoreCategory& c) {
    // The factory values replace the saved ones; the dictionary keeps its current values until
    // the next reset or power-on (CiA 301 §7.5.2.14, DS-BVS §6.2.7).
    for (const auto& [k, v] : factory_) {
        if (profile_.saves(c, static_cast<std::uint16_t>(k >> 8))) {
            stored_[k] = v;
        }
    }
}

void ParameterStore::load(bool communication_only) {
    for (const auto& [k, v] : stored_) {
        const auto index = static_cast<std::uint16_t>(k >> 8);
        if (communication_only && (index < 0x1000 || index > 0x1FFF)) {
            continue;
        }
        if (SubObject* s = od_.find(index, static_cast<std::uint8_t>(k & 0xFF))) {
            s->value = v;
        }
    }
}

void ParameterStore::write_factory(ObjectDictionary& od) const {
    for (const auto& [k, v] : factory_) {
        if (SubObject* w =
                od.find(static_cast<std::uint16_t>(k >> 8), static_cast<std::uint8_t>(k & 0xFF))) {
            w->value = v;
            w->default_value = v;
        }
    }
}

std::map<std::uint32_t, Value> ParameterStore::changes() const {
    std::map<std::uint32_t, Value> out;
    for (const auto& [k, v] : stored_) {
        const auto f = factory_.find(k);
        if (f == factory_.end() || !(f->second == v)) {
            out.emplace(k, v);
        }
    }
    return out;
}

void ParameterStore::adopt(const std::map<std::uint32_t, Value>& saved) {
    for (const auto& [k, v] : saved) {
        if (factory_.count(k) != 0) {
            stored_[k] = v;
        }
    }
}

void ParameterStore::keep(std::uint16_t index, std::uint8_t subindex) {
    if (const SubObject* s = od_.find(index, subindex)) {
        stored_[key(index, subindex)] = s->value;
    }
}

} // namespace codrive::sim
