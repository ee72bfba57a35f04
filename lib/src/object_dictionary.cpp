// SPDX-License-Identifier: Apache-2.0
// Object dictionary storage and the access, length and range checks an SDO server applies.
#include <codrive/core/object_dictionary.hpp>

namespace codrive {

bool SubObject::mappable(PdoDir dir) const {
    if (!pdo_mappable) {
        return false;
    }
    // CiA 306 §4.6.3: rwr is mapped into TPDOs (read by the PDO), rww into RPDOs (written).
    switch (access) {
    case Access::Ro:
    case Access::Const:
    case Access::Rwr:
        return dir == PdoDir::Tpdo;
    case Access::Wo:
    case Access::Rww:
        return dir == PdoDir::Rpdo;
    case Access::Rw:
        return true;
    }
    return false;
}

const SubObject* Object::find(std::uint8_t subindex) const {
    auto it = subs.find(subindex);
    return it == subs.end() ? nullptr : &it->second;
}

SubObject* Object::find(std::uint8_t subindex) {
    auto it = subs.find(subindex);
    return it == subs.end() ? nullptr : &it->second;
}

Object& ObjectDictionary::insert(Object obj) {
    const std::uint16_t index = obj.index;
    auto [it, inserted] = objects_.insert_or_assign(index, std::move(obj));
    (void)inserted;
    return it->second;
}

Object& ObjectDictionary::add_var(std::uint16_t index, std::string name, DataType type,
                                  Access access, Value value, bool pdo_mappable) {
    Object obj;
    obj.index = index;
    obj.name = name;
    obj.code = ObjectCode::Var;
    SubObject sub;
    sub.subindex = 0;
    sub.name = std::move(name);
    sub.type = type;
    sub.access = access;
    sub.pdo_mappable = pdo_mappable;
    sub.default_value = value;
    sub.value = std::move(value);
    obj.subs.emplace(0, std::move(sub));
    return insert(std::move(obj));
}

SubObject& ObjectDictionary::add_sub(std::uint16_t index, SubObject sub, std::string object_name) {
    auto it = objects_.find(index);
    if (it == objects_.end()) {
        Object obj;
        obj.index = index;
        obj.name = std::move(object_name);
        obj.code = ObjectCode::Record;
        it = objects_.emplace(index, std::move(obj)).first;
    }
    const std::uint8_t si = sub.subindex;
    auto [sit, inserted] = it->second.subs.insert_or_assign(si, std::move(sub));
    (void)inserted;
    return sit->second;
}

const Object* ObjectDictionary::find(std::uint16_t index) const {
    auto it = objects_.find(index);
    return it == objects_.end() ? nullptr : &it->second;
}

Object* ObjectDictionary::find(std::uint16_t index) {
    auto it = objects_.find(index);
    return it == objects_.end() ? nullptr : &it->second;
}

const SubObject* ObjectDictionary::find(std::uint16_t index, std::uint8_t subindex) const {
    const Object* o = find(index);
    return o == nullptr ? nullptr : o->find(subindex);
}

SubObject* ObjectDictionary::find(std::uint16_t index, std::uint8_t subindex) {
    Object* o = find(index);
    return o == nullptr ? nullptr : o->find(subindex);
}

tl::expected<std::span<const std::uint8_t>, SdoAbort>
ObjectDictionary::read(std::uint16_t index, std::uint8_t subindex) {
    Object* o = find(index);
    if (o == nullptr) {
        return tl::unexpected(SdoAbort::NoObject);
    }
    SubObject* s = o->find(subindex);
    if (s == nullptr) {
        return tl::unexpected(SdoAbort::NoSubindex);
    }
    if (!readable(s->access)) {
        return tl::unexpected(SdoAbort::WriteOnly);
    }
    if (auto hook = read_hooks_.find(index); hook != read_hooks_.end()) {
        hook->second(index, subindex, *s);
    }
    return s->value.bytes();
}

tl::expected<void, SdoAbort>
ObjectDictionary::check_write(std::uint16_t index, std::uint8_t subindex,
                              std::span<const std::uint8_t> data) const {
    const Object* o = find(index);
    if (o == nullptr) {
        return tl::unexpected(SdoAbort::NoObject);
    }
    const SubObject* s = o->find(subindex);
    if (s == nullptr) {
        return tl::unexpected(SdoAbort::NoSubindex);
    }
    if (!writable(s->access)) {
        return tl::unexpected(SdoAbort::ReadOnly);
    }
    const std::size_t size = data_type_size(s->type);
    if (size != 0) {
        if (data.size() > size) {
            return tl::unexpected(SdoAbort::LengthTooHigh);
        }
        if (data.size() < size) {
            return tl::unexpected(SdoAbort::LengthTooLow);
        }
        const Value candidate(s->type, std::vector<std::uint8_t>(data.begin(), data.end()));
        if (is_signed_integer(s->type)) {
            const auto v = candidate.as_int();
            if (s->low_limit && v && s->low_limit->as_int() && *v < *s->low_limit->as_int()) {
                return tl::unexpected(SdoAbort::ValueTooLow);
            }
            if (s->high_limit && v && s->high_limit->as_int() && *v > *s->high_limit->as_int()) {
                return tl::unexpected(SdoAbort::ValueTooHigh);
            }
        } else if (is_unsigned_integer(s->type)) {
            const auto v = candidate.as_uint();
            if (s->low_limit && v && s->low_limit->as_uint() && *v < *s->low_limit->as_uint()) {
                return tl::unexpected(SdoAbort::ValueTooLow);
            }
            if (s->high_limit && v && s->high_limit->as_uint() && *v > *s->high_limit->as_uint()) {
                return tl::unexpected(SdoAbort::ValueTooHigh);
            }
        } else if (is_real(s->type)) {
            const auto v = candidate.as_double();
            if (s->low_limit && v && s->low_limit->as_double() && *v < *s->low_limit->as_double()) {
                return tl::unexpected(SdoAbort::ValueTooLow);
            }
            if (s->high_limit && v && s->high_limit->as_double() &&
                *v > *s->high_limit->as_double()) {
                return tl::unexpected(SdoAbort::ValueTooHigh);
            }
        }
    }
    return {};
}

tl::expected<void, SdoAbort> ObjectDictionary::write(std::uint16_t index, std::uint8_t subindex,
                                                     std::span<const std::uint8_t> data,
                                                     bool force) {
    if (!force) {
        if (auto ok = check_write(index, subindex, data); !ok) {
            return ok;
        }
    }
    SubObject* s = find(index, subindex);
    if (s == nullptr) {
        return tl::unexpected(find(index) == nullptr ? SdoAbort::NoObject : SdoAbort::NoSubindex);
    }
    // Hooks may veto (e.g. "mapping only in pre-operational"): run them before storing.
    if (auto hook = write_hooks_.find(index); hook != write_hooks_.end()) {
        if (auto ok = hook->second(index, subindex, data); !ok) {
            return ok;
        }
    }
    if (global_write_hook_) {
        if (auto ok = global_write_hook_(index, subindex, data); !ok) {
            return ok;
        }
    }
    auto& bytes = s->value.mutable_bytes();
    bytes.assign(data.begin(), data.end());
    return {};
}

std::string ObjectDictionary::name_of(std::uint16_t index, std::uint8_t subindex) const {
    const Object* o = find(index);
    if (o == nullptr) {
        return {};
    }
    if (o->code == ObjectCode::Var) {
        return o->name;
    }
    const SubObject* s = o->find(subindex);
    if (s == nullptr || s->name.empty()) {
        return o->name;
    }
    return o->name + "." + s->name;
}

} // namespace codrive
